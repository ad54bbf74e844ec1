// What every pass's launch shares: the fixed work-group size and the checks of its inputs.
#pragma once
#include <climits>
#include <string>

#include "offsetmap/cl.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/input.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap {

// PoCL compiles a kernel once per local size: keep it fixed and pad the global size.
inline constexpr size_t kLocalSize = 64;

inline cl::NDRange padded(size_t n) {
    return cl::NDRange((n + kLocalSize - 1) / kLocalSize * kLocalSize);
}

// The same for the grids the precomputes and the footprint pass launch over (a map's texels, a
// pyramid level, a distance volume): a fixed work-group, 64 in 1D, 8 x 8 (x 1) in 2D and 3D,
// with the grid padded to it; the kernels return outside their grid. Left to the driver
// (a null local size), PoCL picks one from each grid's factors and compiles the kernel anew for
// every map size it meets, keeping each build loaded.
inline constexpr size_t kGridTile = 8;

inline size_t round_up(size_t n, size_t m) { return (n + m - 1) / m * m; }

inline cl::NDRange grid_local(size_t dims) {
    return dims == 1   ? cl::NDRange(kLocalSize)
           : dims == 2 ? cl::NDRange(kGridTile, kGridTile)
                       : cl::NDRange(kGridTile, kGridTile, 1);
}

inline cl::NDRange grid_global(const cl::NDRange& grid) {
    switch (grid.dimensions()) {
        case 1:
            return padded(grid[0]);
        case 2:
            return cl::NDRange(round_up(grid[0], kGridTile), round_up(grid[1], kGridTile));
        default:
            return cl::NDRange(round_up(grid[0], kGridTile), round_up(grid[1], kGridTile), grid[2]);
    }
}

inline void enqueue_grid(const cl::CommandQueue& queue, cl::Kernel& kernel, const cl::NDRange& grid,
                         const std::vector<cl::Event>* wait, cl::Event* done) {
    queue.enqueueNDRangeKernel(kernel, cl::NullRange, grid_global(grid),
                               grid_local(grid.dimensions()), wait, done);
}

// A kernel's arguments, in order.
template <typename... Args>
void set_args_from(cl::Kernel& k, cl_uint first, const Args&... args) {
    cl_uint index = first;
    (k.setArg(index++, args), ...);
}
template <typename... Args>
void set_args(cl::Kernel& k, const Args&... args) {
    set_args_from(k, 0, args...);
}

inline void set_optional(cl::Kernel& k, cl_uint index, const cl::Buffer& b) {
    if (b())
        k.setArg(index, b);
    else
        k.setArg(index, sizeof(cl_mem), nullptr);  // a NULL global pointer in the kernel
}

// A device buffer, or an Error naming what it was for when the device cannot allocate it.
inline cl::Buffer device_buffer(const cl::Context& context, cl_mem_flags flags, size_t bytes,
                                const std::string& what, const void* host = nullptr) {
    try {
        return cl::Buffer(context, flags, bytes, const_cast<void*>(host));
    } catch (const cl::Error& e) {
        throw Error("cannot allocate " + what + " on the device (" +
                    std::to_string((bytes + (1 << 20) - 1) >> 20) +
                    " MiB): " + describe_cl_error(e.err()));
    }
}

// What a pass is handed, checked before anything is enqueued: a buffer (not an image) of this
// runtime's context, large enough for `count` elements of `element` (e.g. "float2", 8 bytes), and
// readable or writable as the pass uses it. A null buffer passes when `optional`.
struct BufferUse {
    const char* name;     // "the G-buffer's uv buffer"
    const char* element;  // "float2"
    size_t element_bytes;
    size_t count;
    bool written = false;
    bool optional = false;
};

inline void check_buffer(const cl::Context& context, const cl::Buffer& b, const BufferUse& use) {
    const std::string name = use.name;
    if (!b()) {
        if (use.optional) return;
        throw Error(name + " is a null buffer");
    }
    cl_mem_object_type type = 0;
    cl_context owner = nullptr;
    cl_mem_flags flags = 0;
    size_t bytes = 0;
    if (clGetMemObjectInfo(b(), CL_MEM_TYPE, sizeof type, &type, nullptr) != CL_SUCCESS ||
        clGetMemObjectInfo(b(), CL_MEM_CONTEXT, sizeof owner, &owner, nullptr) != CL_SUCCESS ||
        clGetMemObjectInfo(b(), CL_MEM_FLAGS, sizeof flags, &flags, nullptr) != CL_SUCCESS ||
        clGetMemObjectInfo(b(), CL_MEM_SIZE, sizeof bytes, &bytes, nullptr) != CL_SUCCESS)
        throw Error(name + " is not a valid OpenCL memory object");
    if (type != CL_MEM_OBJECT_BUFFER) throw Error(name + " is an image, not a buffer");
    if (owner != context()) throw Error(name + " belongs to another OpenCL context");
    const size_t need = use.count * use.element_bytes;
    if (bytes < need)
        throw Error(name + " holds " + std::to_string(bytes) + " bytes; it needs " +
                    std::to_string(need) + " (" + std::to_string(use.count) + " " + use.element +
                    ", " + std::to_string(use.element_bytes) + " bytes each)");
    if (use.written && (flags & CL_MEM_READ_ONLY))
        throw Error(name + " is read-only (CL_MEM_READ_ONLY), but the pass writes it");
    if (!use.written && (flags & CL_MEM_WRITE_ONLY))
        throw Error(name + " is write-only (CL_MEM_WRITE_ONLY), but the pass reads it");
}

// Checks an input in the caller's memory (`what`: "the engine G-buffer's normal"): bound once (a
// buffer or an image), of this context; a buffer holding `values` values per pixel of its storage
// for width x height pixels, or a width x height image with that many channels, read as float.
void check_input(const cl::Context& context, const Input& in, const std::string& what, int values,
                 int width, int height);

// `in` as a kernel can read it. PoCL's read_imagef returns wrong values for one-channel half
// images (CL_R, CL_HALF_FLOAT; tested with PoCL 3.1): on PoCL such an image is copied, its raw
// half bits, into a buffer of Storage::Half on `queue` after `wait`, and `copied` is set to the
// copy's event. Every other input comes back as it is, `copied` left null.
Input readable_input(const Runtime& rt, const Input& in, int width, int height,
                     const cl::CommandQueue& queue, const std::vector<cl::Event>& wait,
                     cl::Event& copied);

// The queue a pass enqueues on: the caller's `queue` when given (checked to be on the runtime's
// context), else the runtime's own.
inline const cl::CommandQueue& pass_queue(const Runtime& rt, const cl::CommandQueue& queue) {
    if (!queue()) return rt.queue();
    cl_context owner = nullptr;
    if (clGetCommandQueueInfo(queue(), CL_QUEUE_CONTEXT, sizeof owner, &owner, nullptr) !=
        CL_SUCCESS)
        throw Error("the queue given to the pass is not a valid OpenCL command queue");
    if (owner != rt.context()())
        throw Error("the queue given to the pass belongs to another OpenCL context");
    return queue;
}

inline void check_field(const cl::Context& context, const DeviceHeightField& f,
                        bool needs_normals = false) {
    if (f.width <= 0 || f.height <= 0 || !f.heights())
        throw Error("the height field has not been uploaded");
    if (f.mip_levels < 1 || f.mip_levels > mip_level_count(f.width, f.height))
        throw Error("the height field's mip_levels is " + std::to_string(f.mip_levels) + "; a " +
                    std::to_string(f.width) + "x" + std::to_string(f.height) + " field has 1 to " +
                    std::to_string(mip_level_count(f.width, f.height)));
    check_buffer(context, f.heights,
                 {f.packed ? "the height field's heights buffer (floats and unorm16 words)"
                           : "the height field's heights buffer",
                  "float", sizeof(float), height_buffer_bytes(f) / sizeof(float)});
    const size_t texels = static_cast<size_t>(f.width) * f.height;
    check_buffer(context, f.normals,
                 {"the height field's normals buffer", "float4", sizeof(cl_float4), texels, false,
                  !needs_normals});
}

inline void check_gbuffer(const cl::Context& context, const DeviceGBuffer& g) {
    if (g.width <= 0 || g.height <= 0)
        throw Error("the G-buffer's size is " + std::to_string(g.width) + "x" +
                    std::to_string(g.height));
    if (g.pixels() > static_cast<size_t>(INT_MAX))
        throw Error("the G-buffer is too large (" + std::to_string(g.pixels()) + " pixels)");
    const size_t n = g.pixels();
    check_buffer(context, g.uv, {"the G-buffer's uv buffer", "float2", sizeof(cl_float2), n});
    check_buffer(context, g.view, {"the G-buffer's view buffer", "float4", sizeof(cl_float4), n});
    check_buffer(context, g.light,
                 {"the G-buffer's light buffer", "float4", sizeof(cl_float4), n, false, true});
    check_buffer(context, g.lod,
                 {"the G-buffer's lod buffer", "float", sizeof(float), n, false, true});
    check_buffer(context, g.material,
                 {"the G-buffer's material buffer", "float", sizeof(float), n, false, true});
    check_buffer(context, g.curvature,
                 {"the G-buffer's curvature buffer", "float4", sizeof(cl_float4), n, false, true});
    check_buffer(context, g.uv_metric,
                 {"the G-buffer's uv metric buffer (three planes)", "float4", sizeof(cl_float4),
                  3 * n, false, true});
    if (g.uv_metric() && !g.curvature())
        throw Error("the G-buffer's uv metric needs its curvature plane (zeros for a flat base)");
}

}  // namespace offsetmap
