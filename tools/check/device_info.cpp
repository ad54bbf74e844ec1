// What the device offers, and what the passes choose there.
#include <sstream>

#include "check.hpp"
#include "launch.hpp"

namespace offsetmap::check {
namespace {

std::string type_name(cl_device_type t) {
    if (t & CL_DEVICE_TYPE_GPU) return "GPU";
    if (t & CL_DEVICE_TYPE_CPU) return "CPU";
    if (t & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
    return "other";
}

std::string trimmed(std::string s) {
    while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
    return s;
}

}  // namespace

std::vector<Fact> describe_device(const Runtime& rt) {
    const cl::Device& d = rt.device();
    const cl::Platform platform(d.getInfo<CL_DEVICE_PLATFORM>());
    std::vector<Fact> f;
    auto text = [&](const char* key, const std::string& value) {
        f.push_back({key, trimmed(value), false});
    };
    auto number = [&](const char* key, double value) {
        std::ostringstream s;
        s << value;
        f.push_back({key, s.str(), true});
    };
    text("platform", platform.getInfo<CL_PLATFORM_NAME>());
    text("device", d.getInfo<CL_DEVICE_NAME>());
    text("type", type_name(d.getInfo<CL_DEVICE_TYPE>()));
    text("opencl", d.getInfo<CL_DEVICE_VERSION>());
    text("driver", d.getInfo<CL_DRIVER_VERSION>());
    number("compute_units", d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
    number("clock_mhz", d.getInfo<CL_DEVICE_MAX_CLOCK_FREQUENCY>());
    number("global_memory_mib", static_cast<double>(d.getInfo<CL_DEVICE_GLOBAL_MEM_SIZE>() >> 20));
    number("max_allocation_mib",
           static_cast<double>(d.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>() >> 20));
    number("local_memory_kib", static_cast<double>(d.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>() >> 10));
    number("max_work_group_size", static_cast<double>(d.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>()));
    const bool images = d.getInfo<CL_DEVICE_IMAGE_SUPPORT>() != 0;
    text("image_support", images ? "yes" : "no");
    if (images)
        number("image1d_buffer_max_texels",
               static_cast<double>(d.getInfo<CL_DEVICE_IMAGE_MAX_BUFFER_SIZE>()));
    text("out_of_order_queue",
         (d.getInfo<CL_DEVICE_QUEUE_PROPERTIES>() & CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE) ? "yes"
                                                                                            : "no");
    number("timer_resolution_ns",
           static_cast<double>(d.getInfo<CL_DEVICE_PROFILING_TIMER_RESOLUTION>()));
    // What the passes choose here.
    number("lanes", rt.lanes());
    text("heights_path", rt.images() ? "images (image1d_buffer views)" : "buffers");
    number("local_size", static_cast<double>(kLocalSize));
    text("grid_tile", std::to_string(kGridTile) + "x" + std::to_string(kGridTile));
    text("timer", rt.profiling() ? "profiling events"
                                 : "host clock (the device's events carry no usable times)");
    text("build_options", rt.build_options());
    return f;
}

}  // namespace offsetmap::check
