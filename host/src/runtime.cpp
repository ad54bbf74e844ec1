#include "offsetmap/runtime.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "kernel_sources.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap {
namespace {

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

std::string full_name(const cl::Platform& p, const cl::Device& d) {
    return p.getInfo<CL_PLATFORM_NAME>() + " / " + d.getInfo<CL_DEVICE_NAME>();
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
        case -1001:
            return "no OpenCL platform found (is an ICD such as pocl-opencl-icd installed?)";
        default:
            return "OpenCL error " + std::to_string(code);
    }
}

std::shared_ptr<Runtime> Runtime::create(const std::string& filter_arg) {
    std::string filter = filter_arg;
    if (filter.empty()) {
        const char* env = std::getenv("OFFSETMAP_DEVICE");
        if (env) filter = env;
    }
    std::vector<cl::Platform> platforms;
    try {
        cl::Platform::get(&platforms);
    } catch (const cl::Error& e) {
        throw Error("cannot list OpenCL platforms: " + describe_cl_error(e.err()));
    }
    std::vector<std::pair<cl::Platform, cl::Device>> all;
    for (auto& p : platforms) {
        std::vector<cl::Device> devices;
        try {
            p.getDevices(CL_DEVICE_TYPE_ALL, &devices);
        } catch (const cl::Error&) {
            continue;  // a platform without devices is not an error while another has one
        }
        for (auto& d : devices) all.emplace_back(p, d);
    }
    if (all.empty())
        throw Error("no OpenCL device found: install an OpenCL driver (e.g. pocl-opencl-icd)");
    const std::pair<cl::Platform, cl::Device>* chosen = nullptr;
    if (!filter.empty()) {
        for (auto& pd : all)
            if (lower(full_name(pd.first, pd.second)).find(lower(filter)) != std::string::npos) {
                chosen = &pd;
                break;
            }
        if (!chosen) {
            std::string names;
            for (auto& pd : all)
                names += (names.empty() ? "" : "; ") + full_name(pd.first, pd.second);
            throw Error("no OpenCL device matches '" + filter + "' (devices here: " + names + ")");
        }
    } else {
        for (auto& pd : all)
            if (pd.second.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) {
                chosen = &pd;
                break;
            }
        if (!chosen) chosen = &all.front();
    }
    cl::Context context(chosen->second);
    cl::CommandQueue queue(context, chosen->second, CL_QUEUE_PROFILING_ENABLE);
    return std::make_shared<Runtime>(context, chosen->second, queue);
}

Runtime::Runtime(cl::Context context, cl::Device device, cl::CommandQueue queue)
    : context_(std::move(context)), device_(std::move(device)), queue_(std::move(queue)) {
    profiling_ = (queue_.getInfo<CL_QUEUE_PROPERTIES>() & CL_QUEUE_PROFILING_ENABLE) != 0;
    cl::Platform platform(device_.getInfo<CL_DEVICE_PLATFORM>());
    is_pocl_ = platform.getInfo<CL_PLATFORM_NAME>().find("Portable Computing Language") !=
               std::string::npos;
    lanes_ = (device_.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_CPU) ? 16 : 1;
    if (const char* env = std::getenv("OFFSETMAP_LANES"); env && *env) {
        const std::string text = env;
        if (text != "1" && text != "8" && text != "16")
            throw Error("OFFSETMAP_LANES must be 1, 8 or 16, got '" + text + "'");
        lanes_ = std::stoi(text);
    }
    images_ = (device_.getInfo<CL_DEVICE_TYPE>() & CL_DEVICE_TYPE_GPU) &&
              device_.getInfo<CL_DEVICE_IMAGE_SUPPORT>();
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

    // On a CPU without AVX-512, clang warns for every float16/int16 argument that its ABI differs
    // from AVX-512's (-Wpsabi). PoCL compiles the kernels and its builtin library for the same
    // target, so the ABIs agree and the warning says nothing; every other warning stays on.
    std::string source =
        is_pocl_ ? "#define OM_POCL 1\n#pragma clang diagnostic ignored \"-Wpsabi\"\n" : "";
    source += defines + "\n" + kernel_source("common/om_shared.h", kernel_dir_) + "\n";
    for (const auto& f : files)
        source += "#line 1 \"" + f + "\"\n" + kernel_source(f, kernel_dir_) + "\n";
    cl::Program program(context_, source);
    try {
        program.build({device_}, build_options().c_str());
    } catch (const cl::BuildError& e) {
        std::string log;
        for (const auto& entry : e.getBuildLog()) log += entry.second;
        std::string what;
        for (const auto& f : files) what += (what.empty() ? "" : " + ") + f;
        throw Error("kernel build failed for " + what + " on " + device_name() + ":\n" + log);
    } catch (const cl::Error& e) {
        throw Error("kernel build failed on " + device_name() + ": " + describe_cl_error(e.err()));
    }
    for (const auto& entry : program.getBuildInfo<CL_PROGRAM_BUILD_LOG>())
        if (entry.second.find("warning") != std::string::npos) {
            std::string what;
            for (const auto& f : files) what += (what.empty() ? "" : " + ") + f;
            warnings_.push_back(what + ":\n" + entry.second);
        }
    programs_.emplace(key, program);
    return program;
}

std::string Runtime::build_options() const { return "-cl-std=CL1.2"; }

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
    for (const auto& entry : embedded_kernels())
        if (path == entry.first) return entry.second;
    throw Error("no embedded kernel file '" + path + "'");
}

double event_ms(const cl::Event& event) {
    auto start = event.getProfilingInfo<CL_PROFILING_COMMAND_START>();
    auto end = event.getProfilingInfo<CL_PROFILING_COMMAND_END>();
    return static_cast<double>(end - start) * 1e-6;
}

}  // namespace offsetmap
