// The material frame in the bench: a frame of four materials against one method for the whole
// frame, what a material on a tenth of the screen costs against the whole screen, and the tile
// height.
#include "bench_materials.hpp"

#include <cstdio>
#include <random>

namespace offsetmap::bench {

FrameMaterial bench_material(int id, const std::string& name, const DeviceHeightField& f,
                             const PassSettings& s, const std::string& method,
                             const std::map<std::string, std::string>& params) {
    FrameMaterial m;
    m.id = id;
    m.name = name;
    m.field = f;
    m.settings = s;
    m.params = resolve_params(find_method(method), params);
    return m;
}

namespace {

struct Table {
    std::vector<HeightMap> maps;
    std::vector<PassSettings> settings;
    std::vector<DeviceHeightField> fields;
};

// One frame: classification and dispatches, kernel time (profiling events) and the wall time from
// enqueue to completion (it includes the counts' read-back between them).
struct FrameTime {
    double kernel_ms = 0, wall_ms = 0;
};
FrameTime run_frame(MaterialFrame& frame, const DeviceGBuffer& g, const OffsetTargets& t) {
    const Stopwatch clock;
    frame.enqueue(g, t).wait();
    FrameTime f;
    f.wall_ms = clock.total();
    f.kernel_ms = frame.kernel_ms();
    return f;
}

double dispatch_ms(const MaterialFrame& frame, const std::string& method) {
    for (const auto& d : frame.dispatches())
        if (d.method->name == method) return event_ms(d.event);
    return 0.0;
}

}  // namespace

nlohmann::json bench_materials(std::shared_ptr<Runtime> rt, const Resolution& res,
                               double target_ms) {
    using nlohmann::json;
    if (host_clock()) {
        // Its table is each dispatch's own time and the classification's: events only.
        std::printf(
            "\nmaterial frame skipped under the host's clock: its table is each "
            "dispatch's event time\n");
        return {{"skipped", "timed by the host's clock; the table needs event times"}};
    }
    PlaneScene p;
    p.width = res.w;
    p.height = res.h;
    p.camera_height = 0.9;
    p.pitch_deg = 28.0;
    GBuffer gb = make_scene(p);
    const size_t n = gb.pixels();
    PassSettings s;
    s.scale = 0.05f;
    PassSettings smooth = s;
    smooth.scale = 0.02f;
    const DeviceHeightField f1024 = upload(*rt, bench_map(1024), s),
                            f256 = upload(*rt, bench_map(256), s),
                            f512 = upload(*rt, bench_map(512), smooth),
                            f128 = upload(*rt, bench_map(128), s);
    // Four materials whose methods differ in cost, as a table might pick them.
    const std::vector<FrameMaterial> four = {
        bench_material(1, "1024^2", f1024, s, "pom", {{"min_samples", "8"}, {"max_samples", "32"}}),
        bench_material(2, "256^2", f256, s, "relief"),
        bench_material(3, "512^2 smooth", f512, smooth, "parallax-iterative",
                       {{"iterations", "2"}}),
        bench_material(4, "128^2", f128, s, "secant")};
    lay_out_materials(gb, {1, 2, 3, 4});
    DeviceGBuffer g = upload(*rt, gb);
    OffsetTargets t;
    t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    json out = {{"resolution", res.name}, {"pixels", n}};

    // (1) The frame of four materials against pom 8/32 for every material, in turns.
    {
        MaterialFrame mixed(rt, four);
        std::vector<FrameMaterial> all_pom = four;
        for (auto& m : all_pom) m.params = four[0].params;
        MaterialFrame single(rt, all_pom);
        FrameTime last_mixed, last_single;
        const auto times =
            time_interleaved_ms({[&] { return (last_mixed = run_frame(mixed, g, t)).kernel_ms; },
                                 [&] { return (last_single = run_frame(single, g, t)).kernel_ms; }},
                                target_ms);
        json dispatches = json::array();
        for (const auto& d : mixed.dispatches())
            dispatches.push_back(
                {{"method", d.method->name}, {"tiles", d.entries}, {"ms", event_ms(d.event)}});
        out["four_materials"] = {{"mixed_ms", times[0].median_ms},
                                 {"all_pom_ms", times[1].median_ms},
                                 {"mixed_wall_ms", last_mixed.wall_ms},
                                 {"classify_ms", event_ms(mixed.classify_event())},
                                 {"dispatches", dispatches}};
        std::printf(
            "\nmaterial frame, %s, four materials (pom 8/32, relief, parallax-iterative 2, secant "
            "on 1024^2, 256^2, 512^2, 128^2 maps): %.3f ms (classification %.3f ms, wall %.3f "
            "ms); pom 8/32 for all of them %.3f ms\n",
            res.name, times[0].median_ms, event_ms(mixed.classify_event()), last_mixed.wall_ms,
            times[1].median_ms);
    }

    // (2) One method on a tenth of the screen (a band of whole tile columns, and scattered tiles)
    // against the whole screen; the rest is id 0 (no relief).
    {
        const std::vector<FrameMaterial> one = {
            bench_material(2, "256^2", f256, s, "pom"),
            bench_material(5, "1024^2", f1024, s, "relief", {{"linear", "32"}, {"binary", "8"}})};
        auto ids_for = [&](auto is_exact) {
            GBuffer h = gb;
            for (int y = 0; y < h.height; ++y)
                for (int x = 0; x < h.width; ++x) {
                    const size_t k = static_cast<size_t>(y) * h.width + x;
                    h.material[k] = std::isnan(h.uv[k].s[0]) ? 0.0f : is_exact(x, y) ? 5.0f : 0.0f;
                }
            return upload(*rt, h);
        };
        const int tiles_x = (gb.width + OM_TILE_W - 1) / OM_TILE_W;
        std::mt19937 rng(7);
        std::vector<char> scattered(static_cast<size_t>(tiles_x) *
                                    ((gb.height + kDefaultTileRows - 1) / kDefaultTileRows));
        for (auto& c : scattered) c = rng() % 10 == 0;
        const DeviceGBuffer whole = ids_for([](int, int) { return true; });
        const DeviceGBuffer band = ids_for([&](int x, int) { return x / OM_TILE_W % 10 == 3; });
        const DeviceGBuffer spots = ids_for([&](int x, int y) {
            return scattered[static_cast<size_t>(y / kDefaultTileRows) * tiles_x + x / OM_TILE_W] !=
                   0;
        });
        MaterialFrame frame(rt, one);
        const auto times = time_interleaved_ms({[&] {
                                                    run_frame(frame, whole, t);
                                                    return dispatch_ms(frame, "relief");
                                                },
                                                [&] {
                                                    run_frame(frame, band, t);
                                                    return dispatch_ms(frame, "relief");
                                                },
                                                [&] {
                                                    run_frame(frame, spots, t);
                                                    return dispatch_ms(frame, "relief");
                                                }},
                                               target_ms);
        // The share of the screen each covers, counted.
        auto share = [&](const DeviceGBuffer& d) {
            std::vector<float> m(n);
            rt->queue().enqueueReadBuffer(d.material, CL_TRUE, 0, n * sizeof(float), m.data());
            size_t c = 0;
            for (float v : m) c += v == 5.0f;
            return static_cast<double>(c) / n;
        };
        const double whole_share = share(whole), band_share = share(band),
                     spot_share = share(spots);
        out["tenth_of_screen"] = {
            {"method", "relief linear=32 binary=8"},
            {"whole_ms", times[0].median_ms},
            {"band_ms", times[1].median_ms},
            {"scattered_ms", times[2].median_ms},
            {"whole_share", whole_share},
            {"band_share", band_share},
            {"scattered_share", spot_share},
            {"band_cost_ratio", times[1].median_ms / times[0].median_ms},
            {"scattered_cost_ratio", times[2].median_ms / times[0].median_ms}};
        std::printf(
            "relief 32/8 on part of the screen, %s: whole %.3f ms; a band of %.1f %% of the "
            "covered "
            "pixels %.3f ms (%.1f %% of the cost); scattered tiles, %.1f %% of them, %.3f ms "
            "(%.1f %%)\n",
            res.name, times[0].median_ms, 100.0 * band_share / whole_share, times[1].median_ms,
            100.0 * times[1].median_ms / times[0].median_ms, 100.0 * spot_share / whole_share,
            times[2].median_ms, 100.0 * times[2].median_ms / times[0].median_ms);
    }

    // (3) Tile height: the four-material frame (classification and dispatches) at each.
    {
        std::vector<int> rows = {1, 2, 4, 8, 16, 32};
        std::vector<std::unique_ptr<MaterialFrame>> frames;
        std::vector<std::function<double()>> runs;
        for (int r : rows) {
            frames.push_back(std::make_unique<MaterialFrame>(rt, four, r));
            MaterialFrame* f = frames.back().get();
            runs.push_back([f, &g, &t] { return run_frame(*f, g, t).kernel_ms; });
        }
        const auto times = time_interleaved_ms(runs, target_ms);
        json by_rows = json::array();
        std::printf("tile height (16 x rows), four-material frame, %s:", res.name);
        for (size_t k = 0; k < rows.size(); ++k) {
            size_t traced_items = 0;
            for (const auto& d : frames[k]->dispatches()) traced_items += d.work_items;
            by_rows.push_back({{"rows", rows[k]},
                               {"ms", times[k].median_ms},
                               {"classify_ms", event_ms(frames[k]->classify_event())},
                               {"work_items", traced_items}});
            std::printf(" %d: %.3f ms", rows[k], times[k].median_ms);
        }
        std::printf("\n");
        out["tile_rows"] = by_rows;
    }
    return out;
}

}  // namespace offsetmap::bench
