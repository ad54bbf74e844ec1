#include "offsetmap/gbuffer.hpp"

#include "offsetmap/error.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap {

void GBuffer::resize(int w, int h, bool with_light, bool with_lod) {
    if (w <= 0 || h <= 0)
        throw Error("G-buffer size must be positive, got " + std::to_string(w) + "x" +
                    std::to_string(h));
    width = w;
    height = h;
    uv.assign(pixels(), {{0.0f, 0.0f}});
    view.assign(pixels(), {{0.0f, 0.0f, 1.0f, 0.0f}});
    light.assign(with_light ? pixels() : 0, {{0.0f, 0.0f, 1.0f, 0.0f}});
    lod.assign(with_lod ? pixels() : 0, 0.0f);
}

DeviceGBuffer upload(Runtime& rt, const GBuffer& gb) {
    if (gb.width <= 0 || gb.height <= 0 || gb.uv.size() != gb.pixels() ||
        gb.view.size() != gb.pixels() || (gb.has_light() && gb.light.size() != gb.pixels()) ||
        (gb.has_lod() && gb.lod.size() != gb.pixels()))
        throw Error("G-buffer arrays do not match its size " + std::to_string(gb.width) + "x" +
                    std::to_string(gb.height));
    auto buffer = [&](const void* data, size_t bytes) {
        return cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes,
                          const_cast<void*>(data));
    };
    DeviceGBuffer d;
    d.width = gb.width;
    d.height = gb.height;
    d.uv = buffer(gb.uv.data(), gb.pixels() * sizeof(cl_float2));
    d.view = buffer(gb.view.data(), gb.pixels() * sizeof(cl_float4));
    if (gb.has_light()) d.light = buffer(gb.light.data(), gb.pixels() * sizeof(cl_float4));
    if (gb.has_lod()) d.lod = buffer(gb.lod.data(), gb.pixels() * sizeof(float));
    return d;
}

}  // namespace offsetmap
