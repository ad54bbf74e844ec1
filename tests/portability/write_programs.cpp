// Every program variant (program_variants), for the portability checks:
//   offsetmap_programs OUT_DIR          writes each as the portable source a driver other than
//                                       PoCL is handed (Runtime::program_source without OM_POCL),
//                                       one .cl file each, and an index of their names, for the
//                                       offline SPIR-V gate (tests/portability/spirv_gate.sh)
//   offsetmap_programs --build [PART]   builds each (whose name contains PART) on the device
//                                       $OFFSETMAP_DEVICE picks and creates all its kernels: one
//                                       line a variant with its build time, and exit 1 if any
//                                       failed
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "offsetmap/error.hpp"
#include "offsetmap/program_variants.hpp"
#include "offsetmap/runtime.hpp"

namespace {

int write_sources(const std::filesystem::path& dir) {
    std::filesystem::create_directories(dir);
    std::ofstream index(dir / "index.txt");
    for (const auto& v : offsetmap::program_variants()) {
        std::string file = v.name;
        for (char& c : file)
            if (c == '/') c = '.';
        file += ".cl";
        std::ofstream(dir / file) << offsetmap::Runtime::program_source(v.files, v.defines, false);
        index << file << " " << v.name << "\n";
    }
    return 0;
}

int build_all(const std::string& part) {
    auto rt = offsetmap::Runtime::create();
    std::cout << "building on " << rt->device_name() << "\n";
    int built = 0, failed = 0;
    double total_s = 0;
    for (const auto& v : offsetmap::program_variants()) {
        if (v.name.find(part) == std::string::npos) continue;
        const auto start = std::chrono::steady_clock::now();
        try {
            std::vector<cl::Kernel> kernels;
            rt->program(v.files, v.defines).createKernels(&kernels);
            if (kernels.empty()) throw offsetmap::Error("no kernels");
            const double s =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            total_s += s;
            ++built;
            std::cout << "ok " << v.name << " " << kernels.size() << " kernels " << s << " s\n";
        } catch (const std::exception& e) {
            ++failed;
            std::cout << "FAIL " << v.name << ": " << e.what() << "\n";
        }
        std::cout.flush();
    }
    std::cout << built << " passed, " << failed << " failed (program variants built in " << total_s
              << " s)\n";
    return failed == 0 && built > 0 ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc >= 2 && std::strcmp(argv[1], "--build") == 0 && argc <= 3)
            return build_all(argc == 3 ? argv[2] : "");
        if (argc == 2 && argv[1][0] != '-') return write_sources(argv[1]);
    } catch (const std::exception& e) {
        std::cerr << "offsetmap_programs: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "usage: offsetmap_programs OUT_DIR | --build [PART]\n";
    return 2;
}
