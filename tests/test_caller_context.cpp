// The deferred-renderer path: the caller's own context, queue and buffers, with a wait list.
#include "support.hpp"

namespace omtest {
namespace {

TEST(CallerContext, PassRunsOnCallerObjectsAndHonoursWaitList) {
    // Build everything from scratch, as an engine would: its own context and a queue without
    // profiling.
    cl::Device device = runtime()->device();
    cl::Context context(device);
    cl::CommandQueue queue(context, device);
    auto rt = std::make_shared<Runtime>(context, device, queue);
    EXPECT_FALSE(rt->profiling());

    HeightMap map = smooth_map(64);
    GBuffer host = make_scene(RandomScene{40, 20, 31, 10.0, 90.0});
    PassSettings s;
    s.scale = 0.08f;
    const size_t n = host.pixels();
    DeviceGBuffer g;
    g.width = host.width;
    g.height = host.height;
    g.uv = cl::Buffer(context, CL_MEM_READ_ONLY, n * sizeof(cl_float2));
    g.view = cl::Buffer(context, CL_MEM_READ_ONLY, n * sizeof(cl_float4));
    queue.enqueueWriteBuffer(g.uv, CL_TRUE, 0, n * sizeof(cl_float2), host.uv.data());
    queue.enqueueWriteBuffer(g.view, CL_TRUE, 0, n * sizeof(cl_float4), host.view.data());
    DeviceHeightField field = upload(*rt, map, s);
    OffsetTargets out;
    out.uv = cl::Buffer(context, CL_MEM_WRITE_ONLY, n * sizeof(cl_float2));  // uv only

    cl::UserEvent gate(context);
    OffsetPass pass(rt, "exact");
    cl::Event done = pass.enqueue(g, field, s, out, {gate});
    EXPECT_NE(done.getInfo<CL_EVENT_COMMAND_EXECUTION_STATUS>(), CL_COMPLETE);
    gate.setStatus(CL_COMPLETE);
    done.wait();
    std::vector<cl_float2> uv(n);
    queue.enqueueReadBuffer(out.uv, CL_TRUE, 0, n * sizeof(cl_float2), uv.data());

    // Same answer as the library-managed path.
    OffsetResult ref = run("exact", map, host, s);
    for (size_t k = 0; k < n; ++k) {
        EXPECT_EQ(uv[k].s[0], ref.uv[k].s[0]) << k;
        EXPECT_EQ(uv[k].s[1], ref.uv[k].s[1]) << k;
    }

    // And the shading pass on the same caller objects.
    cl::Buffer rgba(context, CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
    ShadePass shade(rt);
    shade.enqueue(out.uv, cl::Buffer(), g, field, nullptr, s, ShadeSettings{}, rgba, {done}).wait();
    std::vector<cl_float4> color(n);
    queue.enqueueReadBuffer(rgba, CL_TRUE, 0, n * sizeof(cl_float4), color.data());
    for (const auto& c : color)
        for (int a = 0; a < 3; ++a) {
            EXPECT_TRUE(std::isfinite(c.s[a]));
            EXPECT_GE(c.s[a], 0.0f);
        }
}

}  // namespace
}  // namespace omtest
