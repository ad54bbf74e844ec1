// offsetmap_bench: throughput of every offset method on the device at hand, measured against that
// device's own roofline (G-buffer pass-through and dependent bilinear fetches), with cost growth
// against resolution, height-map size and step count, and the memory each method needs.
//
//   offsetmap_bench [--quick] [--out DIR] [--device NAME] [--target-ms T]
//
// Kernel times come from OpenCL profiling events: one warm-up launch, then as many launches as
// fit in the target time (3 to 30), median and minimum reported. Output: a table on stdout,
// DIR/bench.json, and charts by tools/bench/plot_bench.py.
#include <CL/cl_half.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "bench_frame.hpp"
#include "bench_glsl_peer.hpp"
#include "bench_groups.hpp"
#include "bench_materials.hpp"
#include "bench_rebuild.hpp"
#include "bench_util.hpp"
#include "cpu_peer.hpp"
#include "offsetmap/evaluation.hpp"
#include "offsetmap/shared.h"
#include "offsetmap/timing.hpp"

using namespace offsetmap;
using namespace offsetmap::bench;
using nlohmann::json;

namespace {

// Host memcpy of `bytes` over all hardware threads, as GB/s of traffic (read + write): the
// median of `reps` copies, each preceded by `before` (a kernel to time in turns with it).
double host_memcpy_gbps(size_t bytes, int reps = 7, const std::function<void()>& before = {}) {
    std::vector<char> src(bytes, 1), dst(bytes, 0);
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<double> ts;
    for (int rep = 0; rep < reps; ++rep) {
        if (before) before();
        Stopwatch clock;
        std::vector<std::thread> pool;
        for (unsigned t = 0; t < threads; ++t)
            pool.emplace_back([&, t] {
                size_t a = bytes * t / threads, b = bytes * (t + 1) / threads;
                std::memcpy(dst.data() + a, src.data() + a, b - a);
            });
        for (auto& th : pool) th.join();
        ts.push_back(clock.total());
    }
    return 2.0 * bytes / median(ts) * 1e-6;
}

struct Bench {
    std::shared_ptr<Runtime> rt;
    double target_ms;
    // The roofs timed beside each method: pass-through, and fetches along a line and in a chain
    // in lanes.
    cl::Kernel roof_pass, roof_line, roof_chain;
    json out;

    // The roofline microkernels at `lanes` pixels per work-item (1: the file's default).
    cl::Program roof_program(int lanes) {
        const std::vector<std::string> files = sampling_program_files("bench/roofline.cl");
        return rt->program(files, lanes_define(lanes));
    }

    // Work-items for the G-buffer, one per block of `lanes` pixels (the offset entry's groups),
    // in groups of 64.
    static cl::NDRange lane_range(const DeviceGBuffer& g, int lanes) {
        const size_t blocks = om_image_blocks(g.width, g.height, lanes);
        return cl::NDRange((blocks + 63) / 64 * 64);
    }

    OmOffsetParams params_for(const DeviceHeightField& f, const DeviceGBuffer& g) {
        OmOffsetParams p = offset_params(PassSettings{}, f.width, f.height, g.width, g.height);
        p.mip_levels = f.mip_levels;
        p.packed_heights = packed_heights_offset(f);  // the roofs read what the methods read
        return p;
    }

    // Arguments of the roofline microkernels (kernels/bench/roofline.cl): pass-through reads the
    // G-buffer; the fetch kernels (chain, line) its uv and the field, their count (argument 4)
    // set per launch.
    static void bind_passthrough(cl::Kernel& k, const DeviceGBuffer& g, const cl::Buffer& sink) {
        k.setArg(0, g.uv);
        k.setArg(1, g.view);
        k.setArg(2, sink);
        k.setArg(3, static_cast<int>(g.pixels()));
    }
    void bind_fetches(cl::Kernel& k, const DeviceGBuffer& g, const DeviceHeightField& f,
                      const cl::Buffer& sink) {
        k.setArg(0, params_for(f, g));
        k.setArg(1, f.heights);
        k.setArg(2, g.uv);
        k.setArg(3, sink);
    }

    // A launch of a roofline kernel over the G-buffer in blocks of `lanes` pixels.
    std::function<cl::Event()> roof_launch(cl::Kernel& k, const DeviceGBuffer& g, int lanes) {
        return [this, &k, range = lane_range(g, lanes)] {
            cl::Event e;
            rt->queue().enqueueNDRangeKernel(k, cl::NullRange, range, cl::NDRange(64), nullptr, &e);
            return e;
        };
    }

    void roofline(const Resolution& res, const DeviceHeightField& field) {
        GBuffer gb = camera_gbuffer(res);
        DeviceGBuffer g = upload(*rt, gb);
        const int n = static_cast<int>(g.pixels());
        cl::Buffer sink(rt->context(), CL_MEM_WRITE_ONLY, g.pixels() * sizeof(cl_float2));
        cl::Kernel pass(roof_program(1), "om_bench_passthrough");
        bind_passthrough(pass, g, sink);
        Timing tp = time_launches(roof_launch(pass, g, 1), target_ms);
        const double passthrough_ns = tp.median_ms * 1e6 / n;
        const double bytes = 32.0 * n;  // 24 B in, 8 B out
        double kernel_gbps = bytes / (tp.median_ms * 1e-3) * 1e-9;
        double memcpy_gbps = host_memcpy_gbps(static_cast<size_t>(16.0 * n));  // same traffic
        std::printf("\nroofline at %s (%d pixels), height map %dx%d\n", res.name, n, field.width,
                    field.height);
        std::printf(
            "  pass-through    %7.3f ns/pixel  %6.1f GB/s   host memcpy %6.1f GB/s  -> %5.1f%%\n",
            passthrough_ns, kernel_gbps, memcpy_gbps, 100.0 * kernel_gbps / memcpy_gbps);
        json chain_rows = json::array();
        double fetch_ns = 1e30;  // per bilinear fetch: the faster of chain and line at 32
        // One pixel per work-item, then the runtime's lanes (the methods' form), when it has more.
        std::vector<int> lane_counts = {1};
        if (rt->lanes() > 1) lane_counts.push_back(rt->lanes());
        for (int lanes : lane_counts) {
            cl::Program lane_prog = roof_program(lanes);
            for (const char* kind : {"om_bench_fetch_chain", "om_bench_fetch_line"}) {
                cl::Kernel k(lane_prog, kind);
                bind_fetches(k, g, field, sink);
                const bool dependent = std::string(kind) == "om_bench_fetch_chain";
                for (int len : {1, 8, 32, 128}) {
                    k.setArg(4, len);
                    Timing t = time_launches(roof_launch(k, g, lanes), target_ms);
                    double per_fetch = (t.median_ms * 1e6 / n - passthrough_ns) / len;
                    if (len == 32) fetch_ns = std::min(fetch_ns, per_fetch);
                    std::printf(
                        "  %3d %-11s %-9s %8.3f ns/pixel  -> %6.3f ns per bilinear fetch\n", len,
                        dependent ? "dependent" : "independent",
                        lanes > 1 ? ("x" + std::to_string(lanes) + " lanes").c_str() : "1 pixel",
                        t.median_ms * 1e6 / n, per_fetch);
                    chain_rows.push_back({{"fetches", len},
                                          {"dependent", dependent},
                                          {"lanes", lanes},
                                          {"ns_per_pixel", t.median_ms * 1e6 / n},
                                          {"ns_per_fetch", per_fetch}});
                }
            }
        }
        out["roofline"] = {{"resolution", res.name},
                           {"pixels", n},
                           {"passthrough_ns_per_pixel", passthrough_ns},
                           {"passthrough_gbps", kernel_gbps},
                           {"host_memcpy_gbps", memcpy_gbps},
                           {"passthrough_vs_memcpy", kernel_gbps / memcpy_gbps},
                           {"fetch_chain", chain_rows},
                           {"ns_per_fetch", fetch_ns}};
    }

    // `none` against the host memcpy of its traffic (G-buffer 24 B in, uv' 8 B and depth 4 B
    // out per pixel), timed in turns: the bandwidth target for the pass that only moves
    // bytes.
    json none_vs_memcpy(const DeviceGBuffer& g, const DeviceHeightField& f, const PassSettings& s) {
        OffsetPass pass(rt, "none", {});
        const size_t n = g.pixels();
        OffsetTargets t;
        t.uv = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float2));
        t.depth = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
        pass.enqueue(g, f, s, t).wait();
        std::vector<double> kernel_ms;
        const int reps = target_ms > 0 ? 9 : 1;
        double memcpy_gbps = host_memcpy_gbps(18 * n, reps, [&] {
            kernel_ms.push_back(launch_ms([&] { return pass.enqueue(g, f, s, t); }));
        });
        double kernel_gbps = 36.0 * n / (median(kernel_ms) * 1e-3) * 1e-9;
        std::printf(
            "\nnone moves 36 B/pixel at %.1f GB/s: %.0f%% of the host memcpy of the same "
            "traffic (%.1f GB/s), timed in turns\n",
            kernel_gbps, 100.0 * kernel_gbps / memcpy_gbps, memcpy_gbps);
        return {{"none_gbps", kernel_gbps},
                {"host_memcpy_gbps", memcpy_gbps},
                {"none_vs_memcpy", kernel_gbps / memcpy_gbps}};
    }

    // One method at one setting: time (uv' and depth written), fetches per pixel, and the ratio
    // to its roof: pass-through + fetches x the lane fetch rate at that many fetches per pixel,
    // both timed in turns with the method on the same G-buffer and map.
    // The engine-shaped G-buffer's reconstruct pass (depth, camera, frame, uv to tangent-space V
    // and L) in each storage, timed in turns with pom at its defaults on the explicit G-buffer of
    // the same frame: what the engine path adds to a frame.
    json reconstruct(const Resolution& res, const DeviceHeightField& f, const PassSettings& s) {
        PlaneScene p;
        p.width = res.w;
        p.height = res.h;
        const EngineScene e = make_engine_scene(p, DepthConvention::Reversed);
        const size_t n = static_cast<size_t>(e.width) * e.height;
        auto buffer = [&](const std::vector<float>& v, bool half) {
            Input in;
            in.storage = half ? Storage::Half : Storage::Float;
            std::vector<cl_half> h(half ? v.size() : 0);
            for (size_t k = 0; k < h.size(); ++k) h[k] = cl_half_from_float(v[k], CL_HALF_RTE);
            in.buffer =
                cl::Buffer(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                           v.size() * storage_bytes(in.storage),
                           half ? static_cast<void*>(h.data()) : const_cast<float*>(v.data()));
            return in;
        };
        auto engine_gbuffer = [&](bool half) {
            EngineGBuffer g;
            g.width = e.width;
            g.height = e.height;
            g.camera = e.camera;
            g.depth = buffer(e.depth, false);
            g.normal = buffer(e.normal, half);
            g.tangent = buffer(e.tangent, half);
            g.uv = buffer(e.uv, half);
            g.light = {LightKind::Directional, {0.55f, 0.35f, 0.76f}};
            return g;
        };
        const EngineGBuffer full = engine_gbuffer(false), half = engine_gbuffer(true);
        DeviceGBuffer out = allocate_gbuffer(*rt, e.width, e.height, true, false);
        ReconstructPass pass(rt);
        OffsetPass pom(rt, "pom");
        OffsetTargets t;
        t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
        const std::vector<Timing> times = time_interleaved(
            {[&] { return pass.enqueue(full, out); }, [&] { return pass.enqueue(half, out); },
             [&] { return pom.enqueue(out, f, s, t); }},
            target_ms);
        const double px = static_cast<double>(n);
        json r = {{"resolution", res.name},
                  {"float_ns_per_pixel", times[0].median_ms * 1e6 / px},
                  {"half_ns_per_pixel", times[1].median_ms * 1e6 / px},
                  {"pom_ns_per_pixel", times[2].median_ms * 1e6 / px},
                  {"bytes_read_per_pixel_float", 4 + 16 + 16 + 8},
                  {"bytes_written_per_pixel", 8 + 16 + 16}};
        std::printf(
            "\nengine G-buffer (reversed-Z depth, normal + tangent, uv, directional light), %s: "
            "reconstruct %.2f ns/px from float, %.2f from half; pom at defaults %.2f ns/px "
            "(reconstruct %.1f%% of it)\n",
            res.name, r["float_ns_per_pixel"].get<double>(), r["half_ns_per_pixel"].get<double>(),
            r["pom_ns_per_pixel"].get<double>(), 100.0 * times[0].median_ms / times[2].median_ms);
        return r;
    }

    json measure(const std::string& method, const std::map<std::string, std::string>& setting,
                 const DeviceGBuffer& g, const DeviceHeightField& f, const PassSettings& s) {
        OffsetPass pass(rt, method, setting);
        const size_t n = g.pixels();
        const int lanes = rt->lanes();
        OffsetTargets t;
        t.uv = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float2));
        t.depth = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
        if (!roof_line()) {
            roof_pass = cl::Kernel(roof_program(1), "om_bench_passthrough");
            roof_line = cl::Kernel(roof_program(lanes), "om_bench_fetch_line");
            roof_chain = cl::Kernel(roof_program(lanes), "om_bench_fetch_chain");
        }
        cl::Buffer sink(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float2));
        bind_passthrough(roof_pass, g, sink);
        bind_fetches(roof_line, g, f, sink);
        bind_fetches(roof_chain, g, f, sink);
        // Fetch counts from one run with the fetch output on (not timed).
        OffsetResult counted = run_offset(*rt, pass, g, f, s, 1);
        const double fetches = mean_fetches(counted);
        // Lanes busy: a work-item's steps last as long as its slowest lane's; the fraction of
        // lane-steps that fetch for an active lane, for the work-item's block of `lanes` pixels
        // and, from the same counts, for the other shapes it could take instead.
        json busy_by_shape = json::object();
        for (auto [tw, th] :
             {std::pair{lanes, 1}, std::pair{8, 2}, std::pair{4, 4}, std::pair{4, 2}})
            if (tw * th == lanes)
                busy_by_shape[std::to_string(tw) + "x" + std::to_string(th)] =
                    lanes_busy(counted.fetches, g.width, g.height, tw, th);
        // Two roofs at the method's fetch count per pixel (rounded up), each less the same
        // kernel making none (its own loads and stores): fetches along a line (independent, as a
        // linear search makes them: the faster, strict roof) and a chain of fetches each placed
        // by the last height (the dependent-fetch roofline). A fetch's cost depends on
        // how many a work-item makes (one exposes its latency, a row of them overlaps), so both
        // are taken at the method's count.
        const int roof_fetches = std::max(1, static_cast<int>(std::ceil(fetches - 1e-9)));
        auto count = [&](cl::Kernel& k, int c) {
            return [&, c, run = roof_launch(k, g, lanes)] {
                k.setArg(4, c);
                return run();
            };
        };
        std::vector<std::function<cl::Event()>> launches = {
            [&] { return pass.enqueue(g, f, s, t); }, roof_launch(roof_pass, g, 1)};
        if (fetches > 0)
            for (cl::Kernel* k : {&roof_line, &roof_chain}) {
                launches.push_back(count(*k, roof_fetches));
                launches.push_back(count(*k, 0));
            }
        std::vector<Timing> tms = time_interleaved(launches, target_ms);
        const Timing& tm = tms[0];
        double pass_ns = tms[1].median_ms * 1e6 / n;
        auto per_fetch = [&](size_t at) {
            return fetches > 0
                       ? (tms[at].median_ms - tms[at + 1].median_ms) * 1e6 / n / roof_fetches
                       : 0.0;
        };
        double fetch = per_fetch(2), chain_fetch = per_fetch(4);
        double ns = tm.median_ms * 1e6 / n;
        double roof = pass_ns + fetches * fetch, chain_roof = pass_ns + fetches * chain_fetch;
        return {{"method", method},
                {"setting", describe_setting(setting)},
                {"ns_per_pixel", ns},
                {"min_ns_per_pixel", tm.min_ms * 1e6 / n},
                {"mpix_per_s", n / (tm.median_ms * 1e-3) * 1e-6},
                {"runs", tm.runs},
                {"fetches_per_pixel", fetches},
                {"roofline_ns_per_pixel", roof},
                {"roofline_ratio", roof / ns},
                {"roof_passthrough_ns_per_pixel", pass_ns},
                {"roof_ns_per_fetch", fetch},
                {"chain_roofline_ns_per_pixel", chain_roof},
                {"chain_roofline_ratio", chain_roof / ns},
                {"chain_ns_per_fetch", chain_fetch},
                {"lanes_busy", busy_by_shape[std::to_string(OM_BLOCK_W(lanes)) + "x" +
                                             std::to_string(OM_BLOCK_H(lanes))]},
                {"lanes_busy_by_tile", busy_by_shape},
                {"precomputed_bytes", pass.precomputed().bytes}};
    }
};

void print_row(const json& r, const char* extra = "") {
    std::printf(
        "  %-18s %-34s %9.2f %9.2f %9.1f %8.2f %6.2f %9.2f %7.0f%% %6.2f %8.0f%% %6.0f%% %s\n",
        r["method"].get<std::string>().c_str(), r["setting"].get<std::string>().c_str(),
        r["ns_per_pixel"].get<double>(), r["min_ns_per_pixel"].get<double>(),
        r["mpix_per_s"].get<double>(), r["fetches_per_pixel"].get<double>(),
        r["roof_ns_per_fetch"].get<double>(), r["roofline_ns_per_pixel"].get<double>(),
        100.0 * r["roofline_ratio"].get<double>(), r["chain_ns_per_fetch"].get<double>(),
        100.0 * r["chain_roofline_ratio"].get<double>(), 100.0 * r["lanes_busy"].get<double>(),
        extra);
}

// Two copies of the kernel sources (folders like kernels/) timed in one process: per method,
// rounds of A, B, A on the same G-buffer and map (or, for a G-buffer with material ids, as a
// material frame of one material per map, ids 1, 2, ...), each round's ratio B / mean(A, A), median
// and quartiles. Two processes run minutes apart differ by more than most kernel changes here.
json compare_kernels(const std::array<std::string, 2>& dirs, const std::string& device,
                     const std::vector<const MethodInfo*>& methods, const GBuffer& gbuffer,
                     const std::vector<HeightMap>& maps, const PassSettings& s, int rounds) {
    struct Side {
        std::shared_ptr<Runtime> rt;
        DeviceGBuffer g;
        std::vector<DeviceHeightField> f;
        OffsetTargets t;
    };
    std::array<Side, 2> side;
    const size_t n = gbuffer.pixels();
    for (int k = 0; k < 2; ++k) {
        Side& x = side[k];
        x.rt = Runtime::create(device);
        x.rt->set_kernel_dir(dirs[k]);
        x.g = upload(*x.rt, gbuffer);
        for (const HeightMap& map : maps) x.f.push_back(upload(*x.rt, map, s));
        x.t.uv = cl::Buffer(x.rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float2));
        x.t.depth = cl::Buffer(x.rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
    }
    // With a material id per pixel, each method runs as a material frame of one material per map.
    const bool frame = !gbuffer.material.empty();
    std::printf(
        "\n%s (A) against %s (B), %zu pixels, %d rounds of A B A\n  %-18s %10s %10s %8s %15s\n",
        dirs[0].c_str(), dirs[1].c_str(), n, rounds, "method", "A ns/px", "B ns/px", "B / A",
        "quartiles");
    json rows = json::array();
    for (const MethodInfo* m : methods) {
        std::array<std::function<double()>, 2> run;
        std::array<std::unique_ptr<OffsetPass>, 2> pass;
        std::array<std::unique_ptr<MaterialFrame>, 2> frames;
        for (int k = 0; k < 2; ++k) {
            Side& x = side[k];
            if (frame) {
                std::vector<FrameMaterial> table;
                for (size_t i = 0; i < x.f.size(); ++i)
                    table.push_back(bench_material(static_cast<int>(i) + 1,
                                                   std::to_string(maps[i].width) + "^2", x.f[i], s,
                                                   m->name));
                frames[k] = std::make_unique<MaterialFrame>(x.rt, table);
                MaterialFrame* f = frames[k].get();
                run[k] = [f, &x] {
                    if (host_clock()) return launch_ms([&] { return f->enqueue(x.g, x.t); });
                    f->enqueue(x.g, x.t).wait();
                    return f->kernel_ms();
                };
            } else {
                pass[k] = std::make_unique<OffsetPass>(x.rt, m->name);
                OffsetPass* p = pass[k].get();
                run[k] = [p, &x, &s] {
                    return launch_ms([&] { return p->enqueue(x.g, x.f[0], s, x.t); });
                };
            }
        }
        for (int w = 0; w < 2; ++w) run[0](), run[1]();
        std::vector<double> ta, tb, ratio;
        for (int r = 0; r < rounds; ++r) {
            double a1 = run[0](), b1 = run[1](), a2 = run[0]();
            ta.push_back(0.5 * (a1 + a2));
            tb.push_back(b1);
            ratio.push_back(b1 / ta.back());
        }
        auto q = [](std::vector<double> v, double at) {
            std::sort(v.begin(), v.end());
            return v[static_cast<size_t>(at * static_cast<double>(v.size() - 1) + 0.5)];
        };
        const double ns = 1e6 / static_cast<double>(n);
        json r = {{"method", m->name},
                  {"a_ns_per_pixel", q(ta, 0.5) * ns},
                  {"b_ns_per_pixel", q(tb, 0.5) * ns},
                  {"b_over_a", q(ratio, 0.5)},
                  {"b_over_a_q1", q(ratio, 0.25)},
                  {"b_over_a_q3", q(ratio, 0.75)}};
        std::printf("  %-18s %10.2f %10.2f %8.3f   %.3f - %.3f\n", m->name.c_str(),
                    r["a_ns_per_pixel"].get<double>(), r["b_ns_per_pixel"].get<double>(),
                    r["b_over_a"].get<double>(), r["b_over_a_q1"].get<double>(),
                    r["b_over_a_q3"].get<double>());
        std::fflush(stdout);
        rows.push_back(r);
    }
    return {{"kernel_dirs", dirs}, {"pixels", n}, {"rounds", rounds}, {"methods", rows}};
}

void print_header(const char* title) {
    std::printf("\n%s\n  %-18s %-34s %9s %9s %9s %8s %6s %9s %8s %6s %9s %7s\n", title, "method",
                "setting", "ns/pixel", "min", "Mpix/s", "fetches", "ns/f", "roof ns", "of roof",
                "chn/f", "of chain", "busy");
}

}  // namespace

// tools/bench/plot_bench.py on a bench JSON: the growth chart and, when it holds them, the GLSL
// peer's.
void draw_charts(const std::string& json_path, const std::string& out_dir) {
    const std::string cmd = "/usr/bin/python3 '" + std::string(OFFSETMAP_SCRIPT_DIR) +
                            "/plot_bench.py' '" + json_path + "' '" + out_dir + "'";
    std::fflush(stdout);  // our table first, then the script's line
    if (std::system(cmd.c_str()) != 0)
        std::cerr << "offsetmap_bench: warning: charts not drawn (" << cmd << ")\n";
}

int main(int argc, char** argv) {
    CLI::App app{
        "offsetmap_bench: throughput of every offset method against the device's roofline"};
    bool quick = false, smoke = false, materials_only = false, peer_only = false,
         frame_only = false, rebuild_only = false, curved_only = false, shadow_only = false,
         triplanar_only = false, groups_only = false;
    std::string out_dir = "out/bench", device;
    double target_ms = 300;
    app.add_flag("--quick", quick, "720p only, smaller maps and grids (about a minute)");
    app.add_flag("--smoke", smoke,
                 "tiny sizes and one run each: checks the program, not the device");
    app.add_option("--out", out_dir, "output folder")->capture_default_str();
    app.add_option("--device", device, "OpenCL platform/device substring ($OFFSETMAP_DEVICE)");
    app.add_option("--target-ms", target_ms, "time spent per measurement")->capture_default_str();
    bool charts = true, wall_clock = false;
    app.add_flag("!--no-charts", charts, "skip tools/bench/plot_bench.py");
    app.add_flag("--host-clock", wall_clock,
                 "time launches by the host's clock (enqueue to completion) even where events "
                 "carry times: to compare with a device whose events do not");
    std::vector<std::string> only;
    app.add_option(
        "--methods", only,
        "only these methods: roofline, their defaults and the C++ loop (no growth charts)");
    app.add_flag("--materials", materials_only,
                 "only the material frame (tiles, one dispatch per method) at the main resolution");
    app.add_flag("--glsl-peer", peer_only,
                 "only the kernels against the GLSL fragment-shader peer at the main resolution");
    app.add_flag("--frame", frame_only,
                 "only the rendered room's deferred frame at the main resolution: each pass "
                 "against the offset pass, every shadow mode, in turns");
    app.add_flag("--curved", curved_only,
                 "only the curved scene's deferred frame at the main resolution: over the "
                 "tangent plane, the curved base and with the layer behind (drawn where the "
                 "first layer needs it, and over the whole frame), in turns; and the curvature "
                 "plane's read on the offset pass");
    app.add_flag("--shadow-map", shadow_only,
                 "only the room under a low sun at the main resolution, without and with its "
                 "2048^2 displaced shadow map, in turns: the light's passes a map pixel against "
                 "the camera's a frame pixel, the receivers' test and the shading with the mask");
    app.add_flag("--triplanar", triplanar_only,
                 "only the terrain scene (no uv) at the main resolution, its materials triplanar "
                 "against the same scene uv-mapped from above with the same methods, in turns");
    app.add_flag("--groups", groups_only,
                 "only each method's (or --methods') cost in a GPU's SIMD groups at the main "
                 "resolution: steps per pixel and group efficiency (groups of 8, 16, 32, 64 "
                 "pixels) on the room, the terrain and random rays, with its error against exact "
                 "and its time here against pom's");
    app.add_flag("--rebuild", rebuild_only,
                 "only a changing height field: its in-place update and each method's "
                 "precomputed data rebuilt, at 256^2, 1024^2 and 2048^2");
    std::vector<std::string> ab;
    app.add_option("--ab", ab,
                   "A/B of two kernel folders (copies of kernels/): the methods (or --methods) "
                   "timed in turns in one process at the main resolution; nothing else runs")
        ->expected(2);
    std::string ab_scene = "camera";
    app.add_option("--ab-scene", ab_scene,
                   "--ab's G-buffer: the camera plane, random rays (no order between "
                   "neighbouring pixels), or the camera plane as a material frame of four maps "
                   "(1024^2, 256^2, 512^2, 128^2), each method for all four; or the rendered "
                   "room's deferred frame (its shade and offset kernels, every shadow mode)")
        ->check(CLI::IsMember({"camera", "random", "materials", "frame"}))
        ->capture_default_str();
    CLI11_PARSE(app, argc, argv);
    try {
        std::filesystem::create_directories(out_dir);
        Bench b;
        b.rt = Runtime::create(device);
        host_clock() = wall_clock || !b.rt->profiling();
        quick = quick || smoke;
        b.target_ms = smoke ? 0.0 : quick ? std::min(target_ms, 100.0) : target_ms;
        const cl::Device& d = b.rt->device();
        b.out["device"] = b.rt->device_name();
        b.out["driver"] = d.getInfo<CL_DRIVER_VERSION>();
        b.out["opencl"] = d.getInfo<CL_DEVICE_VERSION>();
        b.out["compute_units"] = d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>();
        b.out["build_options"] = b.rt->build_options();
        b.out["local_size"] = 64;
        b.out["lanes"] = b.rt->lanes();
        b.out["heights_path"] = b.rt->images() ? "images" : "buffers";
        // The bench maps hold 16-bit heights: words wherever the reads go through buffers.
        b.out["height_storage"] = b.rt->images() ? "float" : "unorm16";
        b.out["quick"] = quick;
        b.out["clock"] = host_clock() ? "host" : "profiling events";
        std::printf(
            "offsetmap_bench on %s\n  driver %s, %s, %u compute units, kernels built with "
            "-cl-std=CL1.2, local size 64, lane methods %d pixels per work-item, heights via %s\n",
            b.rt->device_name().c_str(), b.out["driver"].get<std::string>().c_str(),
            b.out["opencl"].get<std::string>().c_str(), d.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>(),
            b.rt->lanes(), b.rt->images() ? "images (floats)" : "buffers (unorm16 words)");
        if (host_clock())
            std::printf("  timed by the host's clock (enqueue to completion)%s\n",
                        b.rt->profiling() ? "" : ": the device's events carry no times");

        const std::vector<Resolution> all_res = {
            {"720p", 1280, 720}, {"1080p", 1920, 1080}, {"4K", 3840, 2160}};
        const Resolution tiny = {"160x90", 160, 90};
        const std::vector<Resolution> resolutions = smoke   ? std::vector<Resolution>{tiny}
                                                    : quick ? std::vector<Resolution>{all_res[0]}
                                                            : all_res;
        const Resolution main_res = smoke ? tiny : quick ? all_res[0] : all_res[1];
        // The roofline at 4K in a full run: a G-buffer too large for any last-level cache.
        const Resolution roof_res = smoke ? tiny : quick ? all_res[0] : all_res[2];
        const std::vector<int> map_sizes = smoke   ? std::vector<int>{64, 1024}
                                           : quick ? std::vector<int>{256, 1024}
                                                   : std::vector<int>{256, 1024, 4096};
        PassSettings s;
        s.scale = 0.05f;
        const std::string data_dir = OFFSETMAP_DATA_DIR;
        const int frame_rounds = smoke ? 1 : std::clamp(static_cast<int>(target_ms / 30), 5, 21);
        if (!ab.empty() && ab_scene == "frame") {
            b.out["ab"] = bench_frame(b.rt, main_res, data_dir, frame_rounds, {ab[0], ab[1]});
            std::ofstream(out_dir + "/bench-ab.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-ab.json\n", out_dir.c_str());
            return 0;
        }
        if (frame_only) {
            b.out["frame"] = bench_frame(b.rt, main_res, data_dir, frame_rounds);
            std::ofstream(out_dir + "/bench-frame.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-frame.json\n", out_dir.c_str());
            return 0;
        }
        if (shadow_only) {
            b.out["shadow_map"] =
                bench_shadow_map(b.rt, main_res, data_dir, frame_rounds, smoke ? 256 : 2048);
            std::ofstream(out_dir + "/bench-shadow-map.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-shadow-map.json\n", out_dir.c_str());
            return 0;
        }
        if (triplanar_only) {
            b.out["triplanar"] = bench_triplanar_frame(b.rt, main_res, data_dir, frame_rounds);
            std::ofstream(out_dir + "/bench-triplanar.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-triplanar.json\n", out_dir.c_str());
            return 0;
        }
        if (groups_only) {
            b.out["groups"] =
                bench_groups(b.rt, main_res, data_dir, b.target_ms, select_methods(only));
            std::ofstream(out_dir + "/bench-groups.json") << b.out.dump(1) << "\n";
            std::printf("\nwrote %s/bench-groups.json\n", out_dir.c_str());
            if (charts) draw_charts(out_dir + "/bench-groups.json", out_dir);
            return 0;
        }
        if (curved_only) {
            b.out["curved"] =
                bench_curved_frame(b.rt, main_res, data_dir, frame_rounds, b.target_ms);
            std::ofstream(out_dir + "/bench-curved.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-curved.json\n", out_dir.c_str());
            return 0;
        }
        if (!ab.empty()) {
            const int rounds = smoke ? 1 : std::clamp(static_cast<int>(target_ms / 20), 5, 40);
            GBuffer gb = ab_scene == "random"
                             ? make_scene(RandomScene{main_res.w, main_res.h, 1, 10.0, 90.0})
                             : camera_gbuffer(main_res);
            std::vector<HeightMap> maps = {bench_map(1024)};
            if (ab_scene == "materials") {
                for (int size : {256, 512, 128}) maps.push_back(bench_map(size));
                lay_out_materials(gb, {1, 2, 3, 4});
            }
            b.out["ab"] =
                compare_kernels({ab[0], ab[1]}, device, select_methods(only), gb, maps, s, rounds);
            b.out["ab"]["scene"] = ab_scene;
            std::ofstream(out_dir + "/bench-ab.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-ab.json\n", out_dir.c_str());
            return 0;
        }
        const std::vector<int> rebuild_sizes =
            smoke ? std::vector<int>{64, 256} : std::vector<int>{256, 1024, 2048};
        const int rebuild_rounds = smoke ? 1 : quick ? 3 : 5;
        if (rebuild_only) {
            b.out["rebuild"] = bench_rebuild(b.rt, rebuild_sizes, rebuild_rounds);
            std::ofstream(out_dir + "/bench-rebuild.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-rebuild.json\n", out_dir.c_str());
            return 0;
        }
        if (materials_only) {
            b.out["materials"] = bench_materials(b.rt, main_res, b.target_ms);
            std::ofstream(out_dir + "/bench-materials.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-materials.json\n", out_dir.c_str());
            return 0;
        }
        if (peer_only) {
            b.out["glsl_peer"] = bench_glsl_peer(b.rt, main_res, bench_map(1024), s, b.target_ms);
            std::ofstream(out_dir + "/bench-glsl-peer.json") << b.out.dump(2) << "\n";
            std::printf("\nwrote %s/bench-glsl-peer.json\n", out_dir.c_str());
            if (charts) draw_charts(out_dir + "/bench-glsl-peer.json", out_dir);
            return 0;
        }
        std::map<int, DeviceHeightField> fields;
        std::map<int, HeightMap> host_maps;
        for (int size : map_sizes) {
            host_maps[size] = bench_map(size);
            fields[size] = upload(*b.rt, host_maps[size], s);
        }
        const DeviceHeightField& field = fields[1024];

        b.roofline(roof_res, field);

        // Every method at its defaults.
        GBuffer host_main = camera_gbuffer(main_res);
        DeviceGBuffer g_main = upload(*b.rt, host_main);
        print_header(
            ("methods at their defaults, " + std::string(main_res.name) + ", 1024^2 map").c_str());
        json rows = json::array();
        for (const MethodInfo* m : select_methods(only)) {
            json r = b.measure(m->name, {}, g_main, field, s);
            print_row(r);
            rows.push_back(r);
        }
        b.out["methods"] = rows;
        for (const auto& r : rows)
            if (r["method"] == "none") b.out["none_vs_memcpy"] = b.none_vs_memcpy(g_main, field, s);

        // The same kernel sources compiled as C++ (-O3 -march=native), threads over pixels.
        unsigned threads = std::max(1u, std::thread::hardware_concurrency());
        std::printf(
            "\nkernel against the plain threaded C++ loop of the same source (%u threads, "
            "-O3 -march=native), %s\n  %-18s %12s %12s %10s\n",
            threads, main_res.name, "method", "loop ns/px", "kernel ns/px", "kernel x");
        json peers = json::array();
        for (auto& r : rows) {
            const std::string name = r["method"];
            if (find_method(name).precompute) continue;  // the peer builds no precomputed data
            auto run =
                cpu_peer::run(name, {}, host_main, host_maps[1024], s, smoke ? 1 : 3, threads);
            double loop_ns = run.median_ms * 1e6 / static_cast<double>(host_main.pixels());
            double ratio = loop_ns / r["ns_per_pixel"].get<double>();
            r["cpp_loop_ns_per_pixel"] = loop_ns;
            r["kernel_vs_loop"] = ratio;
            std::printf("  %-18s %12.2f %12.2f %9.2fx\n", name.c_str(), loop_ns,
                        r["ns_per_pixel"].get<double>(), ratio);
            peers.push_back(
                {{"method", name}, {"loop_ns_per_pixel", loop_ns}, {"kernel_vs_loop", ratio}});
        }
        b.out["methods"] = rows;
        b.out["cpp_loop"] = peers;
        if (!only.empty()) {
            std::ofstream(out_dir + "/bench.json") << b.out.dump(1) << "\n";
            std::printf("\nwrote %s/bench.json (--methods: growth, memory and charts skipped)\n",
                        out_dir.c_str());
            return 0;
        }

        b.out["glsl_peer"] = bench_glsl_peer(b.rt, main_res, host_maps[1024], s, b.target_ms);
        b.out["reconstruct"] = b.reconstruct(main_res, field, s);
        b.out["materials"] = bench_materials(b.rt, main_res, b.target_ms);
        b.out["rebuild"] = bench_rebuild(b.rt, rebuild_sizes, rebuild_rounds);

        // Cost against resolution (should be flat per pixel).
        json by_res = json::array();
        print_header("cost against resolution (1024^2 map)");
        for (const auto& res : resolutions) {
            DeviceGBuffer g = res.w == main_res.w ? g_main : upload(*b.rt, camera_gbuffer(res));
            for (const char* m : {"none", "parallax", "steep", "pom", "exact"}) {
                json r = b.measure(m, {}, g, field, s);
                r["resolution"] = res.name;
                r["pixels"] = g.pixels();
                print_row(r, res.name);
                by_res.push_back(r);
            }
        }
        b.out["by_resolution"] = by_res;

        // Cost against height-map size (cache effects).
        json by_map = json::array();
        print_header(("cost against height-map size (" + std::string(main_res.name) + ")").c_str());
        for (int size : map_sizes)
            for (const char* m : {"parallax", "pom", "exact"}) {
                json r = b.measure(m, {}, g_main, fields[size], s);
                r["map_size"] = size;
                print_row(r, (std::to_string(size) + "^2").c_str());
                by_map.push_back(r);
            }
        b.out["by_map_size"] = by_map;

        // Cost against step count (should be linear).
        json by_steps = json::array();
        print_header("cost against step count");
        std::vector<int> steps = smoke   ? std::vector<int>{8}
                                 : quick ? std::vector<int>{8, 32, 128}
                                         : std::vector<int>{8, 16, 32, 64, 128};
        for (int n : steps) {
            auto ns = std::to_string(n);
            for (auto [m, setting] :
                 std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
                     {"steep", {{"layers", ns}}},
                     {"relief", {{"linear", ns}}},
                     {"pom", {{"min_samples", ns}, {"max_samples", ns}}},
                     {"sphere", {{"steps", ns}, {"res", "128"}, {"layers", "16"}}}}) {
                json r = b.measure(m, setting, g_main, field, s);
                r["steps"] = n;
                print_row(r);
                by_steps.push_back(r);
            }
        }
        b.out["by_steps"] = by_steps;

        // Memory of every buffer per method and resolution.
        json memory = json::array();
        std::printf(
            "\nmemory (MiB): G-buffer uv+view, outputs uv'+depth(+fetches+flags), height "
            "pyramid, normals (shading), precomputed\n");
        for (const auto& res : all_res) {
            double px = static_cast<double>(res.w) * res.h;
            for (int size : {256, 1024, 4096}) {
                double pyramid = mip_pyramid_floats(size, size, mip_level_count(size, size)) * 4.0;
                for (const auto& m : methods()) {
                    // What the pass keeps, from the method's row (wrap addressing, defaults).
                    const double pre = m.precompute
                                           ? static_cast<double>(m.precompute->bytes(
                                                 resolve_params(m, {}), PassSettings{}, size, size))
                                           : 0.0;
                    json row = {{"resolution", res.name},   {"map_size", size},
                                {"method", m.name},         {"gbuffer_bytes", 24 * px},
                                {"output_bytes", 12 * px},  {"debug_output_bytes", 8 * px},
                                {"pyramid_bytes", pyramid}, {"normals_bytes", 16.0 * size * size},
                                {"precomputed_bytes", pre}};
                    memory.push_back(row);
                    if (size == 1024 && (m.name == "pom" || m.precompute))
                        std::printf("  %-6s %-8s 1024^2: %8.1f %8.1f (+%.1f) %8.1f %8.1f %8.1f\n",
                                    res.name, m.name.c_str(), 24 * px / 1048576, 12 * px / 1048576,
                                    8 * px / 1048576, pyramid / 1048576,
                                    16.0 * size * size / 1048576, pre / 1048576);
                }
            }
        }
        b.out["memory"] = memory;

        std::ofstream(out_dir + "/bench.json") << b.out.dump(1) << "\n";
        std::printf("\nwrote %s/bench.json\n", out_dir.c_str());
        if (charts) draw_charts(out_dir + "/bench.json", out_dir);
        return 0;
    } catch (const offsetmap::Error& e) {
        std::cerr << "offsetmap_bench: error: " << e.what() << "\n";
    } catch (const cl::Error& e) {
        std::cerr << "offsetmap_bench: error: " << e.what() << ": " << describe_cl_error(e.err())
                  << "\n";
    }
    return 1;
}
