#include "bench_groups.hpp"

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "offsetmap/evaluation.hpp"

#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/scene.hpp"
#endif

namespace offsetmap::bench {
namespace {

using nlohmann::json;

// The group shapes a GPU's wave takes over neighbouring pixels.
struct Shape {
    int size, w, h;
};
constexpr Shape kShapes[] = {{8, 4, 2}, {16, 4, 4}, {32, 8, 4}, {64, 8, 8}};

// The room's G-buffer as the renderer reconstructs it (its relief pixels; the rest empty), or an
// empty one without the renderer.
GBuffer room_gbuffer(const std::shared_ptr<Runtime>& rt, const Resolution& res,
                     const std::string& data_dir) {
#ifdef OFFSETMAP_HAVE_RENDERER
    using namespace offsetmap::renderer;
    const std::vector<LoadedMaterial> table =
        load_materials(read_material_table(data_dir + "/room.json"));
    const std::vector<MethodParams> methods = table_methods(table);
    FrameRenderer r(rt, builtin_room(data_dir), table, methods, res.w, res.h, ShadeSettings{});
    r.render(FrameMode::Deferred, false, 1);
    GBuffer g = r.explicit_gbuffer();
    for (size_t i = 0; i < g.uv.size(); ++i)
        if (!g.material.empty() && !(g.material[i] > 0.0f)) g.uv[i] = {{NAN, NAN}};
    g.material.clear();
    g.lod.clear();
    g.curvature.clear();
    return g;
#else
    (void)rt, (void)res, (void)data_dir;
    return {};
#endif
}

// The rows: each method at its defaults, and the walks that take the beam with it.
std::vector<std::pair<std::string, std::map<std::string, std::string>>> rows(
    const std::vector<const MethodInfo*>& methods) {
    std::vector<std::pair<std::string, std::map<std::string, std::string>>> out;
    for (const MethodInfo* m : methods) {
        out.push_back({m->name, {}});
        if (m->beam) out.push_back({m->name, {{"beam", "1"}}});
    }
    return out;
}

json scene_rows(const std::shared_ptr<Runtime>& rt, const GBuffer& host,
                const DeviceHeightField& field, const PassSettings& s, double target_ms,
                const std::vector<const MethodInfo*>& methods) {
    const DeviceGBuffer g = upload(*rt, host);
    OffsetPass exact_pass(rt, "exact"), pom(rt, "pom");
    const OffsetResult exact = run_offset(*rt, exact_pass, g, field, s, 1);
    OffsetTargets t;
    t.uv = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, host.pixels() * sizeof(cl_float2));
    t.depth = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, host.pixels() * sizeof(float));
    json out = json::array();
    for (const auto& [method, setting] : rows(methods)) {
        OffsetPass pass(rt, method, setting);
        const OffsetResult r = run_offset(*rt, pass, g, field, s, 1);
        // Timed in turns with pom at its defaults (8/32): the ratio holds on a noisy machine.
        const std::vector<Timing> tm =
            time_interleaved({[&] { return pass.enqueue(g, field, s, t); },
                              [&] { return pom.enqueue(g, field, s, t); }},
                             target_ms);
        const double traced = static_cast<double>(std::max<size_t>(traced_pixels(r), 1));
        const ErrorStats e = uv_error(r, exact, field.width, field.height);
        json row = {{"method", method},
                    {"setting", describe_setting(setting)},
                    {"steps_per_pixel", mean_fetches(r)},
                    {"ns_per_pixel", tm[0].median_ms * 1e6 / host.pixels()},
                    {"pom_ns_per_pixel", tm[1].median_ms * 1e6 / host.pixels()},
                    {"time_vs_pom", tm[0].median_ms / tm[1].median_ms},
                    {"error_p95", e.p95},
                    {"error_mean", e.mean}};
        for (const Shape& sh : kShapes) {
            double lane_steps = 0;
            const std::string k = std::to_string(sh.size);
            row["efficiency"][k] =
                lanes_busy(r.fetches, r.width, r.height, sh.w, sh.h, &lane_steps);
            row["group_steps_per_pixel"][k] = lane_steps / traced;
        }
        std::printf("  %-10s %-18s %9.2f %7.2f  %5.2f %5.2f %5.2f %5.2f %9.3g %9.2f %7.2f\n",
                    method.c_str(), describe_setting(setting).c_str(),
                    row["steps_per_pixel"].get<double>(),
                    row["group_steps_per_pixel"]["32"].get<double>(),
                    row["efficiency"]["8"].get<double>(), row["efficiency"]["16"].get<double>(),
                    row["efficiency"]["32"].get<double>(), row["efficiency"]["64"].get<double>(),
                    e.p95, row["ns_per_pixel"].get<double>(), row["time_vs_pom"].get<double>());
        out.push_back(row);
    }
    return out;
}

}  // namespace

json bench_groups(std::shared_ptr<Runtime> rt, const Resolution& res, const std::string& data_dir,
                  double target_ms, const std::vector<const MethodInfo*>& methods) {
    PassSettings s;
    s.scale = 0.05f;
    const DeviceHeightField field = upload(*rt, bench_map(1024), s);
    const std::pair<const char*, GBuffer> scenes[] = {
        {"room", room_gbuffer(rt, res, data_dir)},
        {"terrain", camera_gbuffer(res)},
        {"random", make_scene(RandomScene{res.w, res.h, 1, 10.0, 90.0})}};
    json out = {{"resolution", {res.w, res.h}}, {"map", 1024}, {"scale", s.scale}};
    for (const auto& [name, host] : scenes) {
        if (host.pixels() == 0) {
            out["scenes"][name] = {{"skipped", "built without the renderer"}};
            continue;
        }
        std::printf(
            "\nSIMD groups, %s %dx%d, 1024^2 terrain map: steps per traced pixel, lane-steps per "
            "traced pixel in groups of 32, efficiency in groups of 8 16 32 64, p95 uv error "
            "(texels) against exact, ns per pixel here and its time over pom 8/32's (in turns)\n",
            name, host.width, host.height);
        out["scenes"][name] = scene_rows(rt, host, field, s, target_ms, methods);
    }
    return out;
}

}  // namespace offsetmap::bench
