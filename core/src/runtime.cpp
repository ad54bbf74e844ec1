#include "offsetmap/runtime.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "kernel_sources.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {
namespace {

const char* const kSharedHeader = "offsetmap/shared.h";

std::string embedded_source(const std::string& path) {
    for (const auto& entry : embedded_kernels())
        if (path == entry.first) return entry.second;
    throw Error("no embedded kernel file '" + path + "'");
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string full_name(const cl::Platform& p, const cl::Device& d) {
    return p.getInfo<CL_PLATFORM_NAME>() + " / " + d.getInfo<CL_DEVICE_NAME>();
}

// A driver's build log as one line: its first error line (else its first line), and how many lines
// it had. The whole log goes to $OFFSETMAP_BUILD_LOG when that names a file.
std::string log_summary(const std::string& log, const std::string& none) {
    std::vector<std::string> lines;
    std::istringstream in(log);
    for (std::string line; std::getline(in, line);)
        if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
    if (lines.empty()) return none;
    std::string first = lines.front();
    for (const auto& line : lines)
        if (lower(line).find("error") != std::string::npos) {
            first = line;
            break;
        }
    const size_t start = first.find_first_not_of(" \t");
    first = first.substr(start, first.find_last_not_of(" \t\r") + 1 - start);
    if (const char* path = std::getenv("OFFSETMAP_BUILD_LOG"); path && *path) {
        std::ofstream(path, std::ios::app) << log << "\n";
        return first + " (the log's " + std::to_string(lines.size()) + " lines are in " + path +
               ")";
    }
    if (lines.size() == 1) return first;
    return first + " (" + std::to_string(lines.size()) +
           " lines in the driver's log; OFFSETMAP_BUILD_LOG=FILE keeps them)";
}

}  // namespace

std::string describe_cl_error(int code) {
    switch (code) {
        case CL_DEVICE_NOT_FOUND:
            return "no OpenCL device found (CL_DEVICE_NOT_FOUND)";
        case CL_OUT_OF_RESOURCES:
            return "the device ran out of resources (CL_OUT_OF_RESOURCES)";
        case CL_OUT_OF_HOST_MEMORY:
            return "out of host memory (CL_OUT_OF_HOST_MEMORY)";
        case CL_MEM_OBJECT_ALLOCATION_FAILURE:
            return "the device could not allocate a buffer (CL_MEM_OBJECT_ALLOCATION_FAILURE)";
        case CL_INVALID_BUFFER_SIZE:
            return "a buffer has an invalid size (CL_INVALID_BUFFER_SIZE)";
        case CL_INVALID_KERNEL_NAME:
            return "the program has no such kernel, or the driver could not link it "
                   "(CL_INVALID_KERNEL_NAME)";
        case CL_INVALID_PROGRAM_EXECUTABLE:
            return "the program did not build (CL_INVALID_PROGRAM_EXECUTABLE)";
        case -1001:
            return "no OpenCL platform found (is an ICD such as pocl-opencl-icd installed?)";
        default:
            return "OpenCL error " + std::to_string(code);
    }
}

std::vector<DeviceEntry> list_devices() {
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error& e) {
        throw Error("cannot list OpenCL platforms: " + describe_cl_error(e.err()));
    }
    std::vector<DeviceEntry> all;
    for (auto& p : platforms) {
        std::vector<cl::Device> devices;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            // A platform without devices (rusticl with no driver enabled, Clover with no GPU)
            // answers CL_DEVICE_NOT_FOUND: listed as empty, never a reason to fail.
        }
        if (devices.empty()) all.push_back({p, cl::Device(), p.getInfo<CL_PLATFORM_NAME>()});
        for (auto& d : devices) all.push_back({p, d, full_name(p, d)});
    }
    return all;
}

int choose_device(const std::vector<DeviceEntry>& all, const std::string& filter) {
    int first = -1;
    for (size_t k = 0; k < all.size(); ++k) {
        if (!all[k].device()) continue;
        if (!filter.empty()) {
            if (lower(all[k].name).find(lower(filter)) != std::string::npos)
                return static_cast<int>(k);
            continue;
        }
        if (all[k].device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU)
            return static_cast<int>(k);
        if (first < 0) first = static_cast<int>(k);
    }
    return first;
}

std::shared_ptr<Runtime> Runtime::create(const std::string& filter_arg) {
    std::string filter = filter_arg;
    if (filter.empty()) {
        const char* env = std::getenv("OFFSETMAP_DEVICE");
        if (env) filter = env;
    }
    const std::vector<DeviceEntry> all = list_devices();
    std::string names;
    for (auto& e : all)
        if (e.device()) names += (names.empty() ? "" : "; ") + e.name;
    if (names.empty())
        throw Error("no OpenCL device found: install an OpenCL driver (e.g. pocl-opencl-icd)");
    const int chosen = choose_device(all, filter);
    if (chosen < 0)
        throw Error("no OpenCL device matches '" + filter + "' (devices here: " + names + ")");
    const cl::Device& device = all[chosen].device;
    cl::Context context(device);
    cl::CommandQueue queue(context, device, CL_QUEUE_PROFILING_ENABLE);
    return std::make_shared<Runtime>(context, device, queue);
}

namespace {

bool on_pocl(const cl::Device& device) {
    return cl::Platform(device.getInfo<CL_DEVICE_PLATFORM>())
               .getInfo<CL_PLATFORM_NAME>()
               .find("Portable Computing Language") != std::string::npos;
}

// Oclgrind 21.10 cannot run what clang's optimiser makes of the kernels (llvm.ctpop,
// freeze, llvm.experimental.noalias.scope.decl from inlined struct results; and it mis-evaluates
// a vector `xor <N x i1>, true`): there programs are built unoptimised, their helpers as calls.
bool on_oclgrind(const cl::Device& device) {
    return cl::Platform(device.getInfo<CL_DEVICE_PLATFORM>())
               .getInfo<CL_PLATFORM_NAME>()
               .find("Oclgrind") != std::string::npos;
}

// Whether the device computes fma without a fused instruction (CL_FP_FMA unset): Mesa's llvmpipe
// (rusticl) takes libclc's software fma, correctly rounded and built as a routine with branches
// for every component, which made each 16-lane program take seconds to minutes to build
// (docs/design.md, "Portability").
bool soft_fma(const cl::Device& device) {
    return (device.getInfo<CL_DEVICE_SINGLE_FP_CONFIG>() & CL_FP_FMA) == 0;
}

}  // namespace

int Runtime::default_lanes(const cl::Device& device) {
    return on_pocl(device) && (device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) ? 16 : 1;
}

bool Runtime::default_images(const cl::Device& device) {
    return (device.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) &&
           device.getInfo<CL_DEVICE_IMAGE_SUPPORT>();
}

namespace {

// Whether the device's profiling timestamps come from a clock. rusticl in Mesa 22.3 answers 0, 1,
// 2 and 3 ns (queued, submitted, started, ended) for every command, which would time every kernel
// at 3e-6 ms. Probed with a marker on a queue of its own, so the caller's queue sees nothing (and
// no buffer: Oclgrind 21.10's uninitialised-value plugin gives a released buffer's shadow to the
// next one created).
bool profiling_timer_works(const cl::Context& context, const cl::Device& device) {
    try {
        cl::CommandQueue probe(context, device, CL_QUEUE_PROFILING_ENABLE);
        cl::Event done;
        probe.enqueueMarkerWithWaitList(nullptr, &done);
        done.wait();
        return done.getProfilingInfo<CL_PROFILING_COMMAND_END>() > 1000;
    } catch (const cl::Error&) {
        return false;
    }
}

}  // namespace

Runtime::Runtime(cl::Context context, cl::Device device, cl::CommandQueue queue)
    : context_(std::move(context)), device_(std::move(device)), queue_(std::move(queue)) {
    profiling_ = (queue_.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_PROFILING_ENABLE) != 0 &&
                 profiling_timer_works(context_, device_);
    is_pocl_ = on_pocl(device_);
    is_oclgrind_ = on_oclgrind(device_);
    soft_fma_ = soft_fma(device_);
    lanes_ = default_lanes(device_);
    if (const char* env = std::getenv("OFFSETMAP_LANES"); env && *env) {
        const std::string text = env;
        if (text != "1" && text != "8" && text != "16")
            throw Error("OFFSETMAP_LANES must be 1, 8 or 16, got '" + text + "'");
        lanes_ = std::stoi(text);
    }
    images_ = default_images(device_);
    if (const char* env = std::getenv("OFFSETMAP_IMAGES"); env && *env) {
        const std::string text = env;
        if (text != "0" && text != "1")
            throw Error("OFFSETMAP_IMAGES must be 0 or 1, got '" + text + "'");
        set_images(text == "1");
    }
}

void Runtime::set_images(bool images) {
    if (images && !device_.getInfo<CL_DEVICE_IMAGE_SUPPORT>())
        throw Error("the device " + device_name() + " has no image support");
    images_ = images;
}

void Runtime::set_lanes(int lanes) {
    if (lanes != 1 && lanes != 8 && lanes != 16)
        throw Error("lanes must be 1, 8 or 16, got " + std::to_string(lanes));
    lanes_ = lanes;
}

std::string Runtime::device_name() const {
    return full_name(cl::Platform(device_.getInfo<CL_DEVICE_PLATFORM>()), device_);
}

cl::Program Runtime::program(const std::vector<std::string>& files, const std::string& defines) {
    std::string key = defines;
    for (const auto& f : files) key += "|" + f;
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = programs_.find(key);
    if (it != programs_.end()) return it->second;

    const std::string source =
        program_source(files,
                       std::string(is_oclgrind_ ? "#define OM_PLAIN_CALLS 1\n" : "") +
                           (soft_fma_ ? "#define OM_SOFT_FMA 1\n" : "") + defines,
                       is_pocl_, kernel_dir_);
    std::string what;
    for (const auto& f : files) what += (what.empty() ? "" : " + ") + f;
    cl::Program program(context_, source);
    try {
        program.build({device_}, build_options().c_str());
    } catch (const cl::BuildError& e) {
        std::string log;
        for (const auto& entry : e.getBuildLog()) log += entry.second;
        throw Error("kernel build failed for " + what + " on " + device_name() + ": " +
                    log_summary(log, "no log"));
    } catch (const cl::Error& e) {
        throw Error("kernel build failed for " + what + " on " + device_name() + ": " +
                    describe_cl_error(e.err()));
    }
    for (const auto& entry : program.getBuildInfo<CL_PROGRAM_BUILD_LOG>())
        if (entry.second.find("warning") != std::string::npos)
            warnings_.push_back(what + ":\n" + entry.second);
    names_[program()] = what;
    programs_.emplace(key, program);
    return program;
}

std::string Runtime::program_source(const std::vector<std::string>& files,
                                    const std::string& defines, bool pocl, const std::string& dir) {
    // On a CPU without AVX-512, clang warns for every float16/int16 argument that its ABI differs
    // from AVX-512's (-Wpsabi). PoCL compiles the kernels and its builtin library for the same
    // target, so the ABIs agree and the warning says nothing; every other warning stays on.
    std::string source =
        pocl ? "#define OM_POCL 1\n#pragma clang diagnostic ignored \"-Wpsabi\"\n" : "";
    // The shared header is always the library's own copy, never a kernel folder's: the host was
    // compiled against it, and a layout of its own would shift every uploaded field.
    source +=
        defines + "\n#line 1 \"" + kSharedHeader + "\"\n" + embedded_source(kSharedHeader) + "\n";
    std::vector<std::string> all = prelude_files();
    all.insert(all.end(), files.begin(), files.end());
    for (const auto& f : all) source += "#line 1 \"" + f + "\"\n" + kernel_source(f, dir) + "\n";
    return source;
}

std::string Runtime::build_options() const {
    return is_oclgrind_ ? "-cl-std=CL1.2 -cl-opt-disable" : "-cl-std=CL1.2";
}

cl::Kernel Runtime::kernel(const cl::Program& program, const std::string& name) const {
    try {
        return cl::Kernel(program, name.c_str());
    } catch (const cl::Error& e) {
        std::string what = "a program", log;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto it = names_.find(program());
            if (it != names_.end()) what = it->second;
        }
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_);
        } catch (const cl::Error&) {
        }
        throw Error("cannot create kernel '" + name + "' of " + what + " on " + device_name() +
                    ": " + describe_cl_error(e.err()) +
                    "; the driver's log: " + log_summary(log, "empty"));
    }
}

size_t Runtime::programs_built() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return programs_.size();
}

std::vector<std::string> Runtime::build_warnings() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return warnings_;
}

void Runtime::set_kernel_dir(const std::string& dir) {
    std::lock_guard<std::mutex> lock(mutex_);
    kernel_dir_ = dir;
    programs_.clear();
    names_.clear();
}

std::string kernel_source(const std::string& path, const std::string& dir_arg) {
    const char* env = std::getenv("OFFSETMAP_KERNEL_DIR");
    if (!dir_arg.empty() || env) {
        std::string dir = dir_arg.empty() ? std::string(env) : dir_arg;
        std::string full = dir + "/" + path;
        std::ifstream in(full, std::ios::binary);
        if (!in)
            throw Error(
                "cannot read kernel file '" + full + "' (" +
                (dir_arg.empty() ? "OFFSETMAP_KERNEL_DIR is set" : "the runtime's kernel folder") +
                ")");
        std::ostringstream text;
        text << in.rdbuf();
        return text.str();
    }
    return embedded_source(path);
}

double event_ms(const cl::Event& event) {
    auto start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    auto end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return static_cast<double>(end - start) * 1e-6;
}

}  // namespace offsetmap
