// Every program variant (program_variants), for the portability checks; with --sample only the
// sample (one variant a kernel file, the one a GPU driver gets by default: `./run test`'s tier):
//   offsetmap_programs [--sample] OUT_DIR   writes each as the portable source a driver other
//                                           than PoCL is handed (Runtime::program_source without
//                                           OM_POCL), one .cl file each, and an index of their
//                                           names, for the offline SPIR-V gate
//                                           (tests/portability/spirv_gate.sh)
//   offsetmap_programs --build [--sample | PART] [SHARD/SHARDS]
//                                           builds each (the sample, or those whose name contains
//                                           PART; every SHARDS-th from SHARD) on the device
//                                           $OFFSETMAP_DEVICE picks and creates all its kernels:
//                                           one line a variant with its build time, and exit 1
//                                           if any failed
#include <chrono>
#include <string>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <vector>

#include "offsetmap/error.hpp"
#include "offsetmap/program_variants.hpp"
#include "offsetmap/runtime.hpp"

namespace {

struct Selection {
    bool sample = false;
    std::string part;
    int shard = 0, shards = 1;
};

std::vector<offsetmap::ProgramVariant> selected(const Selection& s) {
    std::vector<offsetmap::ProgramVariant> out;
    int k = 0;
    for (auto& v : offsetmap::program_variants()) {
        if (s.sample ? !v.sample : v.name.find(s.part) == std::string::npos) continue;
        if (k++ % s.shards == s.shard) out.push_back(std::move(v));
    }
    return out;
}

int write_sources(const std::filesystem::path& dir, const Selection& s) {
    std::filesystem::create_directories(dir);
    std::ofstream index(dir / "index.txt");
    for (const auto& v : selected(s)) {
        std::string file = v.name;
        for (char& c : file)
            if (c == '/') c = '.';
        file += ".cl";
        std::ofstream(dir / file) << offsetmap::Runtime::program_source(v.files, v.defines, false);
        index << file << " " << v.name << "\n";
    }
    return 0;
}

int build_all(const Selection& s) {
    auto rt = offsetmap::Runtime::create();
    std::cout << "building on " << rt->device_name() << "\n";
    int built = 0, failed = 0;
    double total_s = 0;
    for (const auto& v : selected(s)) {
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

// "SHARD/SHARDS" (0 <= SHARD < SHARDS), or false.
bool parse_shard(const std::string& text, Selection& s) {
    const size_t slash = text.find('/');
    if (slash == std::string::npos) return false;
    try {
        s.shard = std::stoi(text.substr(0, slash));
        s.shards = std::stoi(text.substr(slash + 1));
    } catch (const std::exception&) {
        return false;
    }
    return s.shards >= 1 && s.shard >= 0 && s.shard < s.shards;
}

}  // namespace

int main(int argc, char** argv) {
    const std::vector<std::string> args(argv + 1, argv + argc);
    Selection s;
    try {
        if (!args.empty() && args[0] == "--build" && args.size() <= 3) {
            size_t k = 1;
            if (k < args.size() && args[k] == "--sample") {
                s.sample = true;
                ++k;
            } else if (k < args.size() && args[k].find('/') == std::string::npos) {
                s.part = args[k++];
            }
            if (k == args.size() || (k + 1 == args.size() && parse_shard(args[k], s)))
                return build_all(s);
        } else if (args.size() == 2 && args[0] == "--sample") {
            s.sample = true;
            return write_sources(args[1], s);
        } else if (args.size() == 1 && args[0][0] != '-') {
            return write_sources(args[0], s);
        }
    } catch (const std::exception& e) {
        std::cerr << "offsetmap_programs: " << e.what() << "\n";
        return 1;
    }
    std::cerr << "usage: offsetmap_programs [--sample] OUT_DIR | --build [--sample | PART] "
                 "[SHARD/SHARDS]\n";
    return 2;
}
