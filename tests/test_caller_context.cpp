// The deferred-renderer path: the caller's own context, queue and buffers, with a wait list.
#include <cstring>

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
    shade.enqueue(g, field, {out.uv, {}, nullptr}, s, ShadeSettings{}, {rgba}, {done}).wait();
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
            shade.enqueue(good, field, {out.uv, {}, albedo}, s, ShadeSettings{}, {rgba}).wait();
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

TEST(CallerContext, PrepareLeavesNothingToCompileForTheFirstFrame) {
    auto shared = runtime();
    HeightMap map = smooth_map(64);
    GBuffer host = make_scene(RandomScene{40, 20, 3, 10.0, 90.0});
    for (const std::string method : {"pom", "cone"}) {
        for (bool lod : {false, true}) {
            // A runtime of its own: nothing built before this pass.
            auto rt =
                std::make_shared<Runtime>(shared->context(), shared->device(), shared->queue());
            PassSettings s;
            s.scale = 0.06f;
            s.lod.enabled = s.lod.footprint = lod;
            DeviceHeightField field = upload(*rt, map, s);
            DeviceGBuffer g = upload(*rt, host);
            OffsetTargets t;  // uv alone: not the variant the constructor builds
            t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, host.pixels() * sizeof(cl_float2));
            OffsetPass pass(rt, method);
            pass.prepare(g, field, s, t);
            const size_t built = rt->programs_built();
            pass.enqueue(g, field, s, t).wait();
            EXPECT_EQ(rt->programs_built(), built) << method << (lod ? " with LOD" : "");
            // And prepare launched over no pixels: it wrote nothing, the frame is the usual one.
            std::vector<cl_float2> uv(host.pixels());
            rt->queue().enqueueReadBuffer(t.uv, CL_TRUE, 0, uv.size() * sizeof(cl_float2),
                                          uv.data());
            OffsetResult ref = run(method, map, host, s);
            EXPECT_EQ(std::memcmp(uv.data(), ref.uv.data(), uv.size() * sizeof(cl_float2)), 0)
                << method;
        }
    }
}

// The pass's outputs read back on `rt`'s queue after `done`.
OffsetResult read_back(Runtime& rt, const OffsetTargets& t, size_t n, const cl::Event& done) {
    OffsetResult r;
    r.uv.resize(n);
    r.depth.resize(n);
    r.fetches.resize(n);
    r.flags.resize(n);
    const std::vector<cl::Event> after = {done};
    auto& q = rt.queue();
    q.enqueueReadBuffer(t.uv, CL_TRUE, 0, n * sizeof(cl_float2), r.uv.data(), &after);
    q.enqueueReadBuffer(t.depth, CL_TRUE, 0, n * sizeof(float), r.depth.data(), &after);
    q.enqueueReadBuffer(t.fetches, CL_TRUE, 0, n * sizeof(cl_uint), r.fetches.data(), &after);
    q.enqueueReadBuffer(t.flags, CL_TRUE, 0, n * sizeof(cl_uint), r.flags.data(), &after);
    return r;
}

void expect_same_frame(const OffsetResult& a, const OffsetResult& b, const std::string& what) {
    ASSERT_EQ(a.uv.size(), b.uv.size()) << what;
    EXPECT_EQ(std::memcmp(a.uv.data(), b.uv.data(), a.uv.size() * sizeof(cl_float2)), 0) << what;
    EXPECT_EQ(std::memcmp(a.depth.data(), b.depth.data(), a.depth.size() * sizeof(float)), 0)
        << what;
    EXPECT_EQ(a.fetches, b.fetches) << what;
    EXPECT_EQ(a.flags, b.flags) << what;
}

TEST(CallerContext, OutOfOrderQueueGivesTheInOrderFrame) {
    // Every dependency inside the library (upload, mips, normals, precomputes, the footprint
    // pre-pass) must be an event: on an out-of-order queue nothing else orders them.
    cl::Device device = runtime()->device();
    SKIP_WITHOUT_OUT_OF_ORDER_QUEUE(device);
    cl::Context context(device);
    cl::CommandQueue queue(context, device,
                           CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE | CL_QUEUE_PROFILING_ENABLE);
    auto ooo = std::make_shared<Runtime>(context, device, queue);

    HeightMap map = smooth_map(96);
    GBuffer host = make_scene(RandomScene{48, 20, 17, 8.0, 90.0});
    const size_t n = host.pixels();
    auto targets = [&] {
        OffsetTargets t;
        t.uv = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_float2));
        t.depth = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(float));
        t.fetches = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
        t.flags = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
        return t;
    };
    for (bool lod : {false, true}) {
        PassSettings s;
        s.scale = 0.07f;
        s.lod.enabled = s.lod.footprint = lod;
        // A fresh field per setting, used at once: nothing waits for its upload but the passes.
        DeviceHeightField field = upload(*ooo, map, s);
        DeviceGBuffer g = upload(*ooo, host);
        for (const auto& m : methods()) {
            OffsetPass pass(ooo, m.name);
            OffsetTargets t = targets();
            OffsetResult got = read_back(*ooo, t, n, pass.enqueue(g, field, s, t));
            expect_same_frame(got, run(m.name, map, host, s),
                              m.name + (lod ? " (footprint LOD)" : ""));
        }
    }

    // Held back by the caller's event, the upload, a precompute's build and the passes enqueue
    // and return; nothing runs until the event completes. (cone's build reads one value back, so
    // it waits for the field and is left out here.) The map differs from the one above, so a pass
    // that ran on a pyramid not yet written (or on its memory's earlier contents) is seen.
    PassSettings s;
    s.scale = 0.07f;
    HeightMap inverted = map;
    for (float& h : inverted.h) h = 1.0f - h;
    cl::UserEvent gate(context);
    DeviceHeightField field = upload(*ooo, inverted, s, nullptr, {gate});
    DeviceGBuffer g = upload(*ooo, host);
    std::vector<std::pair<std::string, cl::Event>> runs;
    std::vector<OffsetTargets> outs;
    std::vector<std::unique_ptr<OffsetPass>> passes;
    for (const std::string method : {"pom", "maxmip"}) {
        passes.push_back(std::make_unique<OffsetPass>(ooo, method));
        outs.push_back(targets());
        runs.emplace_back(method, passes.back()->enqueue(g, field, s, outs.back()));
    }
    EXPECT_NE(field.ready.getInfo<CL_EVENT_COMMAND_EXECUTION_STATUS>(), CL_COMPLETE);
    for (const auto& r : runs)
        EXPECT_NE(r.second.getInfo<CL_EVENT_COMMAND_EXECUTION_STATUS>(), CL_COMPLETE) << r.first;
    gate.setStatus(CL_COMPLETE);
    for (size_t k = 0; k < runs.size(); ++k)
        expect_same_frame(read_back(*ooo, outs[k], n, runs[k].second),
                          run(runs[k].first, inverted, host, s), "gated " + runs[k].first);
}

// One runtime, three of the caller's queues (the runtime's, another in-order one and an
// out-of-order one): the same frame from each, no program built for the second and third, and
// a queue of another context refused.
TEST(CallerContext, OneRuntimeServesSeveralQueues) {
    cl::Device device = runtime()->device();
    cl::Context context(device);
    cl::CommandQueue own(context, device);
    auto rt = std::make_shared<Runtime>(context, device, own);
    const std::vector<cl::CommandQueue> queues = {
        cl::CommandQueue(), cl::CommandQueue(context, device),
        out_of_order_queue(context, device)};
    HeightMap map = smooth_map(64);
    GBuffer host = make_scene(RandomScene{40, 24, 23, 8.0, 90.0});
    const size_t n = host.pixels();
    PassSettings s;
    s.scale = 0.06f;
    s.lod.enabled = s.lod.footprint = true;  // the footprint pre-pass goes on the queue too
    DeviceHeightField field = upload(*rt, map, s);
    DeviceGBuffer g = upload(*rt, host);
    const OffsetResult want = run("cone", map, host, s);
    OffsetPass pass(rt, "cone");
    ShadePass shade(rt);
    size_t built = 0;
    for (size_t q = 0; q < queues.size(); ++q) {
        OffsetTargets t;
        t.uv = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_float2));
        t.depth = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(float));
        t.fetches = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
        t.flags = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_uint));
        cl::Event done = pass.enqueue(g, field, s, t, {}, queues[q]);
        cl::Buffer rgba(context, CL_MEM_READ_WRITE, n * sizeof(cl_float4));
        shade.enqueue(g, field, shade_inputs(t), s, ShadeSettings{}, {rgba}, {done}, queues[q])
            .wait();
        expect_same_frame(read_back(*rt, t, n, done), want, "queue " + std::to_string(q));
        if (q == 0) built = rt->programs_built();
        EXPECT_EQ(rt->programs_built(), built) << "queue " << q;
    }
    cl::Context other(device);
    OffsetTargets t;
    t.uv = cl::Buffer(context, CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    EXPECT_TRUE(contains(
        error_of([&] { pass.enqueue(g, field, s, t, {}, cl::CommandQueue(other, device)); }),
        "the queue given to the pass belongs to another OpenCL context"));
}

}  // namespace
}  // namespace omtest