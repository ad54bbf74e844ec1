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
    // uv only; read-write, since the shade pass below reads it.
    out.uv = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_float2));

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

TEST(CallerContext, BuffersTooSmallOrMisusedAreRefusedBeforeEnqueue) {
    auto rt = runtime();
    const cl::Context& context = rt->context();
    HeightMap map = smooth_map(64);
    GBuffer host = make_scene(RandomScene{32, 16, 5, 10.0, 90.0});
    PassSettings s;
    s.scale = 0.05f;
    const size_t n = host.pixels();
    DeviceHeightField field = upload(*rt, map, s);
    const DeviceGBuffer good = upload(*rt, host);
    auto buffer = [&](size_t bytes, cl_mem_flags flags = CL_MEM_READ_WRITE) {
        return cl::Buffer(context, flags, bytes);
    };
    OffsetTargets out;
    out.uv = buffer(n * sizeof(cl_float2));
    OffsetPass pass(rt, "pom");
    auto offset_error = [&](const DeviceGBuffer& g, const DeviceHeightField& f,
                            const OffsetTargets& t) {
        return error_of([&] { pass.enqueue(g, f, s, t).wait(); });
    };
    ASSERT_EQ(offset_error(good, field, out), "");

    // Inputs: a quarter-size uv, a view buffer of float2 instead of float4, another context.
    DeviceGBuffer g = good;
    g.uv = buffer(n / 4 * sizeof(cl_float2));
    EXPECT_TRUE(contains(offset_error(g, field, out),
                         "the G-buffer's uv buffer holds " + std::to_string(n / 4 * 8) +
                             " bytes; it needs " + std::to_string(n * 8) + " (" +
                             std::to_string(n) + " float2, 8 bytes each)"));
    g = good;
    g.view = buffer(n * sizeof(cl_float2));
    EXPECT_TRUE(contains(offset_error(g, field, out), "the G-buffer's view buffer holds"));
    g = good;
    g.lod = buffer(n / 2 * sizeof(float));
    EXPECT_TRUE(contains(offset_error(g, field, out), "the G-buffer's lod buffer holds"));
    g = good;
    cl::Context other(rt->device());
    g.view = cl::Buffer(other, CL_MEM_READ_WRITE, n * sizeof(cl_float4));
    EXPECT_TRUE(contains(offset_error(g, field, out),
                         "the G-buffer's view buffer belongs to another OpenCL context"));
    g = good;
    g.uv = buffer(n * sizeof(cl_float2), CL_MEM_WRITE_ONLY);
    EXPECT_TRUE(contains(offset_error(g, field, out), "the G-buffer's uv buffer is write-only"));

    // An image handed in as a buffer.
    cl::Image2D image(context, CL_MEM_READ_WRITE, cl::ImageFormat(CL_RGBA, CL_FLOAT), host.width,
                      host.height);
    g = good;
    g.view = cl::Buffer(image(), true);
    EXPECT_TRUE(contains(offset_error(g, field, out),
                         "the G-buffer's view buffer is an image, not a buffer"));

    // Outputs: a sixteenth of uv, a short depth, fetches read-only.
    OffsetTargets t = out;
    t.uv = buffer(n / 16 * sizeof(cl_float2));
    EXPECT_TRUE(contains(offset_error(good, field, t), "the offset pass's uv output holds"));
    t = out;
    t.depth = buffer((n - 1) * sizeof(float));
    EXPECT_TRUE(contains(offset_error(good, field, t), "the offset pass's depth output holds"));
    t = out;
    t.fetches = buffer(n * sizeof(cl_uint), CL_MEM_READ_ONLY);
    EXPECT_TRUE(
        contains(offset_error(good, field, t), "the offset pass's fetches output is read-only"));

    // The height field: a pyramid shorter than its mip_levels say, too many levels.
    DeviceHeightField f = field;
    f.heights = buffer(64 * 64 * sizeof(float));
    EXPECT_TRUE(contains(offset_error(good, f, out), "the height field's heights buffer holds"));
    f = field;
    f.mip_levels = 12;
    EXPECT_TRUE(contains(offset_error(good, f, out), "the height field's mip_levels is 12"));

    // The shade pass: its colour output and the albedo image.
    ShadePass shade(rt);
    auto shade_error = [&](const cl::Buffer& rgba, const DeviceImage* albedo) {
        return error_of([&] {
            shade.enqueue(out.uv, cl::Buffer(), good, field, albedo, s, ShadeSettings{}, rgba)
                .wait();
        });
    };
    EXPECT_EQ(shade_error(buffer(n * sizeof(cl_float4)), nullptr), "");
    EXPECT_TRUE(contains(shade_error(buffer(n * sizeof(cl_float2)), nullptr),
                         "the shade pass's colour output holds"));
    DeviceImage albedo;
    albedo.width = albedo.height = 16;
    albedo.texels = buffer(8 * 16 * sizeof(cl_float4));
    EXPECT_TRUE(contains(shade_error(buffer(n * sizeof(cl_float4)), &albedo),
                         "the albedo image's texels holds"));
}

}  // namespace
}  // namespace omtest
