#include "offsetmap/gbuffer.hpp"

#include <new>

#include "launch.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap {

void check_gbuffer_size(int w, int h, const std::string& what) {
    const std::string size = std::to_string(w) + "x" + std::to_string(h);
    if (w <= 0 || h <= 0) throw Error(what + " size must be positive, got " + size);
    if (w > kMaxGBufferSide || h > kMaxGBufferSide ||
        static_cast<size_t>(w) * h > kMaxGBufferPixels)
        throw Error(what + " is " + size + ", above the G-buffer limit of " +
                    std::to_string(kMaxGBufferPixels) + " pixels (" +
                    std::to_string(kMaxGBufferSide) + " per side)");
}

void GBuffer::resize(int w, int h, bool with_light, bool with_lod) {
    check_gbuffer_size(w, h, "the G-buffer");
    const size_t n = static_cast<size_t>(w) * h;
    try {
        uv.assign(n, {{0.0f, 0.0f}});
        view.assign(n, {{0.0f, 0.0f, 1.0f, 0.0f}});
        light.assign(with_light ? n : 0, {{0.0f, 0.0f, 1.0f, 0.0f}});
        lod.assign(with_lod ? n : 0, 0.0f);
    } catch (const std::bad_alloc&) {
        *this = GBuffer();
        const size_t bytes = n * (sizeof(cl_float2) + sizeof(cl_float4) * (1 + with_light) +
                                  sizeof(float) * with_lod);
        throw Error("out of memory allocating a " + std::to_string(w) + "x" + std::to_string(h) +
                    " G-buffer (" + std::to_string(bytes >> 20) + " MiB)");
    }
    width = w;
    height = h;
}

DeviceGBuffer upload(Runtime& rt, const GBuffer& gb) {
    if (gb.width <= 0 || gb.height <= 0 || gb.uv.size() != gb.pixels() ||
        gb.view.size() != gb.pixels() || (gb.has_light() && gb.light.size() != gb.pixels()) ||
        (gb.has_lod() && gb.lod.size() != gb.pixels()) ||
        (gb.has_material() && gb.material.size() != gb.pixels()) ||
        (gb.has_curvature() && gb.curvature.size() != gb.pixels()) ||
        (gb.has_uv_metric() && gb.uv_metric.size() != 3 * gb.pixels()))
        throw Error("G-buffer arrays do not match its size " + std::to_string(gb.width) + "x" +
                    std::to_string(gb.height));
    auto buffer = [&](const void* data, size_t bytes) {
        return device_buffer(
            rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes,
            "the " + std::to_string(gb.width) + "x" + std::to_string(gb.height) + " G-buffer",
            data);
    };
    DeviceGBuffer d;
    d.width = gb.width;
    d.height = gb.height;
    d.uv = buffer(gb.uv.data(), gb.pixels() * sizeof(cl_float2));
    d.view = buffer(gb.view.data(), gb.pixels() * sizeof(cl_float4));
    if (gb.has_light()) d.light = buffer(gb.light.data(), gb.pixels() * sizeof(cl_float4));
    if (gb.has_lod()) d.lod = buffer(gb.lod.data(), gb.pixels() * sizeof(float));
    if (gb.has_material()) d.material = buffer(gb.material.data(), gb.pixels() * sizeof(float));
    if (gb.has_curvature())
        d.curvature = buffer(gb.curvature.data(), gb.pixels() * sizeof(cl_float4));
    if (gb.has_uv_metric())
        d.uv_metric = buffer(gb.uv_metric.data(), 3 * gb.pixels() * sizeof(cl_float4));
    return d;
}

}  // namespace offsetmap
