// Each method's time per pixel on a camera view and on random rays, and the device's roofline:
// the G-buffer moved with no work, and a bilinear fetch dependent (a march) and independent.
#include "offsetmap/timing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "check.hpp"
#include "launch.hpp"

namespace offsetmap::check {
namespace {

// The median of `runs` launches after one to warm up (the host's clock where the device's events
// carry no times).
double median_ms(const Runtime& rt, int runs, const std::function<cl::Event()>& launch) {
    launch().wait();
    std::vector<double> t;
    for (int r = 0; r < runs; ++r) t.push_back(launch_ms(launch, !rt.profiling()));
    return median(t);
}

struct Frame {
    DeviceGBuffer g;
    OffsetTargets uv_only, with_fetches;
};

Frame frame(Runtime& rt, const GBuffer& gb) {
    Frame f;
    f.g = upload(rt, gb);
    const size_t n = gb.pixels();
    f.uv_only.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    f.with_fetches = f.uv_only;
    f.with_fetches.fetches = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    f.with_fetches.flags = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    return f;
}

// ns per pixel (uv' alone bound, as an engine binds it) and fetches per traced pixel.
std::pair<double, double> time_pass(Runtime& rt, OffsetPass& pass, const Frame& f,
                                    const DeviceHeightField& field, const PassSettings& s,
                                    int runs) {
    pass.prepare(f.g, field, s, f.uv_only);
    const double ms = median_ms(rt, runs, [&] { return pass.enqueue(f.g, field, s, f.uv_only); });
    pass.enqueue(f.g, field, s, f.with_fetches).wait();
    const size_t n = f.g.pixels();
    std::vector<cl_uint> fetches(n), flags(n);
    rt.queue().enqueueReadBuffer(f.with_fetches.fetches, CL_TRUE, 0, n * sizeof(cl_uint),
                                 fetches.data());
    rt.queue().enqueueReadBuffer(f.with_fetches.flags, CL_TRUE, 0, n * sizeof(cl_uint),
                                 flags.data());
    double sum = 0;
    size_t count = 0;
    for (size_t k = 0; k < n; ++k)
        if (traced(flags[k])) sum += fetches[k], ++count;
    return {ms * 1e6 / static_cast<double>(n), count ? sum / count : 0.0};
}

Roofline roofline(Runtime& rt, const Frame& f, const DeviceHeightField& field, int runs) {
    Roofline roof;
    const int n = static_cast<int>(f.g.pixels()), lanes = rt.lanes();
    cl::Buffer sink(rt.context(), CL_MEM_WRITE_ONLY, f.g.pixels() * sizeof(cl_float2));
    const std::vector<std::string> files = sampling_program_files("bench/roofline.cl");
    cl::Kernel pass = rt.kernel(rt.program(files, lanes_define(1)), "om_bench_passthrough");
    set_args(pass, f.g.uv, f.g.view, sink, n);
    // ns per pixel of `kernel` over `items` work-items.
    auto ns_per_pixel = [&](cl::Kernel& kernel, size_t items) {
        return median_ms(rt, runs,
                         [&] {
                             cl::Event e;
                             rt.queue().enqueueNDRangeKernel(kernel, cl::NullRange, padded(items),
                                                             cl::NDRange(kLocalSize), nullptr, &e);
                             return e;
                         }) *
               1e6 / n;
    };
    roof.passthrough_ns = ns_per_pixel(pass, static_cast<size_t>(n));
    OmOffsetParams p =
        offset_params(PassSettings{}, field.width, field.height, f.g.width, f.g.height);
    p.mip_levels = field.mip_levels;
    p.packed_heights = packed_heights_offset(field);
    const cl::Program lane_program = rt.program(files, lanes_define(lanes));
    const int fetches = 32;
    for (const char* name : {"om_bench_fetch_chain", "om_bench_fetch_line"}) {
        cl::Kernel k = rt.kernel(lane_program, name);
        set_args(k, p, field.heights, f.g.uv, sink, fetches);
        const double ns = ns_per_pixel(k, om_image_blocks(f.g.width, f.g.height, lanes));
        // Below the timer's resolution over the pass-through, a fetch shows as free (0), not less.
        const double per_fetch = std::max(0.0, (ns - roof.passthrough_ns) / fetches);
        (std::string(name) == "om_bench_fetch_chain" ? roof.chain_ns : roof.line_ns) = per_fetch;
    }
    return roof;
}

}  // namespace

void time_methods(const std::shared_ptr<Runtime>& rt, const Options& o, DeviceReport& report) {
    const int w = o.quick ? 640 : 1920, h = o.quick ? 360 : 1080, map = o.quick ? 256 : 1024;
    const int runs = o.quick ? 3 : 5;
    report.timing_frame = std::to_string(w) + "x" + std::to_string(h) + ", " + std::to_string(map) +
                          "^2 map (unorm16), s = 0.05";
    PassSettings s;
    s.scale = 0.05f;
    const DeviceHeightField field = upload(*rt, bench_map(map), s);
    PlaneScene camera;
    camera.width = w;
    camera.height = h;
    const Frame cam = frame(*rt, make_scene(camera));
    const Frame random = frame(*rt, make_scene(RandomScene{w, h, 1, 10.0, 90.0}));
    report.roof = roofline(*rt, cam, field, runs);
    for (const MethodInfo* m : select_methods(o.methods)) {
        MethodTime t;
        t.method = m->name;
        OffsetPass pass(rt, m->name);
        std::tie(t.camera_ns, t.camera_fetches) = time_pass(*rt, pass, cam, field, s, runs);
        std::tie(t.random_ns, t.random_fetches) = time_pass(*rt, pass, random, field, s, runs);
        report.times.push_back(t);
    }
}

}  // namespace offsetmap::check
