// An engine's frame through offsetmap: its own OpenCL context and queue, its G-buffer as it writes
// it (reversed-Z depth, camera, normal + tangent, uv), the offset pass and the shade pass.
#include <cmath>
#include <cstdio>

#include "offsetmap/offsetmap.hpp"

int main() try {
    using namespace offsetmap;
    cl::Device device = cl::Device::getDefault();
    cl::Context context(device);
    cl::CommandQueue queue(context, device);
    auto rt = std::make_shared<Runtime>(context, device, queue);

    // 64 x 64 pixels looking straight down at the plane z = 0 from z = 1: 90 degree field of view,
    // reversed-Z, near plane 0.1, far plane at infinity, so every pixel's depth is 0.1.
    const int w = 64, h = 64, n = w * h;
    EngineGBuffer g;
    g.width = w;
    g.height = h;
    g.camera.depth = DepthConvention::Reversed;
    g.camera.eye = {0.5f, 0.5f, 1.0f};
    g.camera.inverse_view_projection = {1, 0, 0, 0, 0, 1, 0, 0, 5, 5, 10, 10, 0, 0, -1, 0};
    std::vector<float> depth(n, 0.1f), normal(4 * n), tangent(4 * n), uv(2 * n);
    for (int k = 0; k < n; ++k) {
        normal[4 * k + 2] = tangent[4 * k] = tangent[4 * k + 3] = 1.0f;
        uv[2 * k] = (2.0f * (k % w) + 1) / w - 0.5f;
        uv[2 * k + 1] = 1.5f - (2.0f * (k / w) + 1) / h;
    }
    auto input = [&](std::vector<float>& v) {
        Input in;
        in.buffer =
            cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, v.size() * 4, v.data());
        return in;
    };
    g.depth = input(depth), g.normal = input(normal), g.tangent = input(tangent), g.uv = input(uv);
    g.light = {LightKind::Directional, {0.5f, 0.3f, 0.8f}};

    HeightMap map;  // 32 x 32 bumps
    map.width = map.height = 32;
    for (int k = 0; k < 32 * 32; ++k)
        map.h.push_back(0.5f + 0.5f * std::sin(0.4f * (k % 32)) * std::cos(0.4f * (k / 32)));
    PassSettings settings;
    settings.scale = 0.05f;
    DeviceHeightField field = upload(*rt, map, settings);

    DeviceGBuffer tangent_space = allocate_gbuffer(*rt, w, h, true, false);
    OffsetTargets out;
    out.uv = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    cl::Buffer rgba(context, CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
    ReconstructPass reconstruct(rt);
    OffsetPass pom(rt, "pom");
    ShadePass shade(rt);
    cl::Event views = reconstruct.enqueue(g, tangent_space);
    cl::Event offsets = pom.enqueue(tangent_space, field, settings, out, {views});
    shade.enqueue(tangent_space, field, shade_inputs(out), settings, {}, {rgba}, {offsets}).wait();

    std::vector<cl_float4> color(n);
    queue.enqueueReadBuffer(rgba, CL_TRUE, 0, n * sizeof(cl_float4), color.data());
    int lit = 0;
    for (const cl_float4& c : color) lit += c.s[3] == 1.0f && std::isfinite(c.s[0]);
    std::printf("engine example: %d of %d pixels shaded on %s\n", lit, n,
                rt->device_name().c_str());
    return lit == n ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "engine example: %s\n", e.what());
    return 1;
}
