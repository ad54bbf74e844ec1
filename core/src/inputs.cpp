// Inputs in the caller's device memory: their storage and their checks.
#include <array>
#include <cstdio>

#include "launch.hpp"
#include "offsetmap/input.hpp"

namespace offsetmap {
namespace {

std::string image_type_name(cl_channel_type type) {
    switch (type) {
        case CL_FLOAT:
            return "float";
        case CL_HALF_FLOAT:
            return "half";
        case CL_UNORM_INT8:
            return "unorm8";
        case CL_UNORM_INT16:
            return "unorm16";
        case CL_SNORM_INT8:
            return "snorm8";
        case CL_SNORM_INT16:
            return "snorm16";
        default:
            return "";
    }
}

// Channels read_imagef returns in .x, .xy, ... for each order an input may use (it returns
// (r, g, b, a) whatever order the memory holds them in).
int leading_channels(cl_channel_order order) {
    switch (order) {
        case CL_R:
            return 1;
        case CL_RG:
            return 2;
        case CL_RGBA:
        case CL_BGRA:
        case CL_ARGB:
            return 4;
        default:
            return 0;
    }
}

}  // namespace

void check_input(const cl::Context& context, const Input& in, const std::string& what, int values,
                 int width, int height) {
    if (in.buffer() && in.image()) throw Error(what + " has both a buffer and an image; bind one");
    if (!in.bound()) throw Error(what + " is not bound (no buffer and no image)");
    const size_t pixels = static_cast<size_t>(width) * height;
    if (in.buffer()) {
        const std::string element = std::to_string(values) + " value(s) of " +
                                    std::to_string(storage_bytes(in.storage)) + " byte(s)";
        const std::string buffer_name = what + " buffer";
        check_buffer(
            context, in.buffer,
            {buffer_name.c_str(), element.c_str(), values * storage_bytes(in.storage), pixels});
        return;
    }
    cl_mem_object_type type = 0;
    cl_context owner = nullptr;
    cl_image_format format{};
    size_t w = 0, h = 0;
    const cl_mem m = in.image();
    if (clGetMemObjectInfo(m, CL_MEM_TYPE, sizeof type, &type, nullptr) != CL_SUCCESS ||
        clGetMemObjectInfo(m, CL_MEM_CONTEXT, sizeof owner, &owner, nullptr) != CL_SUCCESS)
        throw Error(what + " image is not a valid OpenCL memory object");
    if (type != CL_MEM_OBJECT_IMAGE2D) throw Error(what + " image is not a 2D image");
    if (owner != context()) throw Error(what + " image belongs to another OpenCL context");
    clGetImageInfo(m, CL_IMAGE_FORMAT, sizeof format, &format, nullptr);
    clGetImageInfo(m, CL_IMAGE_WIDTH, sizeof w, &w, nullptr);
    clGetImageInfo(m, CL_IMAGE_HEIGHT, sizeof h, &h, nullptr);
    if (w != static_cast<size_t>(width) || h != static_cast<size_t>(height))
        throw Error(what + " image is " + std::to_string(w) + "x" + std::to_string(h) +
                    "; the G-buffer is " + std::to_string(width) + "x" + std::to_string(height));
    if (image_type_name(format.image_channel_data_type).empty())
        throw Error(what + " image's channel type (0x" + [&] {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%X", format.image_channel_data_type);
            return std::string(hex);
        }() + ") is not read as float; use float, half, unorm8/16 or snorm8/16");
    if (leading_channels(format.image_channel_order) < values)
        throw Error(what + " image needs " + std::to_string(values) +
                    " channel(s) (order CL_R, CL_RG, CL_RGBA, CL_BGRA or CL_ARGB; the first " +
                    std::to_string(values) + " read)");
}

Input readable_input(const Runtime& rt, const Input& in, int width, int height,
                     const cl::CommandQueue& queue, const std::vector<cl::Event>& wait,
                     cl::Event& copied) {
    if (!rt.is_pocl() || !in.image()) return in;
    const cl_image_format format = in.image.getImageInfo<CL_IMAGE_FORMAT>();
    if (format.image_channel_order != CL_R || format.image_channel_data_type != CL_HALF_FLOAT)
        return in;
    Input copy;
    copy.storage = Storage::Half;
    copy.buffer = device_buffer(rt.context(), CL_MEM_READ_WRITE,
                                static_cast<size_t>(width) * height * storage_bytes(Storage::Half),
                                "a copy of a one-channel half image");
    const std::array<cl::size_type, 3> origin = {0, 0, 0};
    const std::array<cl::size_type, 3> region = {static_cast<cl::size_type>(width),
                                                 static_cast<cl::size_type>(height), 1};
    queue.enqueueCopyImageToBuffer(in.image, copy.buffer, origin, region, 0, &wait, &copied);
    return copy;
}

size_t storage_bytes(Storage s) {
    switch (s) {
        case Storage::Float:
            return 4;
        case Storage::Half:
        case Storage::Snorm16:
        case Storage::Unorm16:
            return 2;
        case Storage::Unorm8:
            return 1;
    }
    throw Error("unknown storage " + std::to_string(static_cast<int>(s)));
}

}  // namespace offsetmap
