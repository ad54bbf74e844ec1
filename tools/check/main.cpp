// offsetmap_check: does the pass run correctly on this machine's OpenCL devices, and how fast.
//   offsetmap_check [--device TEXT]... [--methods M,M...] [--quick] [--no-timing] [--json FILE]
//                   [--list]
// Exit status 0 when every case passes on every device checked, 1 on any failure or error (each
// failure one line on stderr: device, kernel, case, worst pixel), 2 for a usage error.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "check.hpp"
#include "offsetmap/timing.hpp"

namespace {

using namespace offsetmap;
using namespace offsetmap::check;

const char* const kUsage =
    "usage: offsetmap_check [--device TEXT]... [--methods M,M...] [--quick] [--no-timing]\n"
    "                       [--json FILE] [--list]\n"
    "  --device TEXT   only devices whose \"platform / device\" contains TEXT (any case;\n"
    "                  repeatable); default: every OpenCL device\n"
    "  --methods LIST  only these methods (comma-separated); default: every method\n"
    "  --quick         smaller cases and timing frames (about 15 s on a 2-core CPU)\n"
    "  --no-timing     correctness only\n"
    "  --json FILE     write the whole report as JSON\n"
    "  --list          list the devices and what the passes choose there, nothing else\n"
    "Kernels are the library's own; OFFSETMAP_KERNEL_DIR=DIR loads them from DIR instead.\n";

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

struct Args {
    Options options;
    bool list = false;
};

// Throws std::invalid_argument with the message for a usage error.
Args parse(int argc, char** argv) {
    Args a;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
            return argv[++i];
        };
        if (arg == "--device") {
            a.options.devices.push_back(next());
        } else if (arg == "--methods") {
            std::stringstream list(next());
            for (std::string m; std::getline(list, m, ',');)
                if (!m.empty()) a.options.methods.push_back(m);
            select_methods(a.options.methods);  // an unknown name is a usage error
        } else if (arg == "--quick") {
            a.options.quick = true;
        } else if (arg == "--no-timing") {
            a.options.timing = false;
        } else if (arg == "--json") {
            a.options.json = next();
        } else if (arg == "--list") {
            a.list = true;
        } else if (arg == "--help" || arg == "-h") {
            std::cout << kUsage;
            std::exit(0);
        } else {
            throw std::invalid_argument("unknown argument '" + arg + "'");
        }
    }
    return a;
}

std::vector<cl::Device> devices_matching(const std::vector<std::string>& filters) {
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error&) {
        platforms.clear();
    }
    std::vector<cl::Device> out;
    for (const cl::Platform& p : platforms) {
        std::vector<cl::Device> devices;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue;  // a platform without devices
        }
        for (const cl::Device& d : devices) {
            const std::string name =
                lower(p.getInfo<CL_PLATFORM_NAME>() + " / " + d.getInfo<CL_DEVICE_NAME>());
            bool wanted = filters.empty();
            for (const std::string& f : filters)
                wanted = wanted || name.find(lower(f)) != std::string::npos;
            if (wanted) out.push_back(d);
        }
    }
    return out;
}

DeviceReport check_device(const cl::Device& device, const Options& o, bool list_only) {
    DeviceReport r;
    cl::Context context(device);
    cl::CommandQueue queue(context, device, CL_QUEUE_PROFILING_ENABLE);
    auto rt = std::make_shared<Runtime>(context, device, queue);
    r.name = rt->device_name();
    r.facts = describe_device(*rt);
    if (list_only) return r;
    const Stopwatch clock;
    auto stage = [&](const char* what, const std::function<void()>& run) {
        std::fprintf(stderr, "offsetmap_check: %s on %s...\n", what, r.name.c_str());
        try {
            run();
        } catch (const std::exception& e) {
            CaseResult c;
            c.kernel = what;
            c.name = "(stopped)";
            c.passed = false;
            c.worst_pixel = e.what();
            r.cases.push_back(c);
        }
    };
    stage("methods", [&] { check_methods(rt, o, r); });
    stage("material frame", [&] { check_material_frame(rt, o, r); });
    stage("shade", [&] { check_shade(rt, o, r); });
    stage("reconstruct", [&] { check_reconstruct(rt, o, r); });
    if (o.timing) stage("timing", [&] { time_methods(rt, o, r); });
    collect_failures(r);
    const double s = clock.total() / 1000.0;
    std::ostringstream secs;
    secs << s;
    r.facts.push_back({"check_seconds", secs.str(), true});
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    try {
        a = parse(argc, argv);
    } catch (const std::exception& e) {
        std::cerr << "offsetmap_check: " << e.what() << " (offsetmap_check --help)\n";
        return 2;
    }
    try {
        // Opened before the check runs, so that a path that cannot be written is said at once.
        std::ofstream json;
        if (!a.options.json.empty()) {
            json.open(a.options.json);
            if (!json) {
                std::cerr << "offsetmap_check: cannot write the JSON report '" << a.options.json
                          << "'\n";
                return 1;
            }
        }
        const std::vector<cl::Device> devices = devices_matching(a.options.devices);
        if (devices.empty()) {
            std::cerr << "offsetmap_check: no OpenCL device"
                      << (a.options.devices.empty() ? "" : " matches --device")
                      << " (the ICD loader lists the drivers in /etc/OpenCL/vendors, or where "
                         "OCL_ICD_VENDORS points)\n";
            return 1;
        }
        std::vector<DeviceReport> reports;
        size_t failures = 0;
        for (const cl::Device& d : devices) {
            reports.push_back(check_device(d, a.options, a.list));
            print_report(reports.back());
            failures += reports.back().failures.size();
        }
        std::fflush(stdout);
        for (const DeviceReport& r : reports)
            for (const std::string& line : r.failures) std::cerr << line << "\n";
        if (json.is_open()) {
            json << report_json(reports, a.options);
            if (!json.flush()) {
                std::cerr << "offsetmap_check: cannot write the JSON report '" << a.options.json
                          << "'\n";
                return 1;
            }
        }
        return failures ? 1 : 0;
    } catch (const std::exception& e) {
        std::cerr << "offsetmap_check: error: " << e.what() << "\n";
        return 1;
    }
}
