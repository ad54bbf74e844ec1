#ifdef OFFSETMAP_HAVE_RENDERER
#include "truth.hpp"

#include <cmath>
#include <cstdio>

#include "offsetmap/renderer/truth.hpp"

namespace offsetmap::cli {

using namespace offsetmap::renderer;

namespace {

std::string texels_text(double texels_per_quad) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", texels_per_quad);
    return text;
}

nlohmann::json mismatch_json(const TruthComparison& c) {
    return {{"pixels", c.mismatch},
            {"silhouette_band", c.mismatch_band},
            {"interior", c.mismatch_interior}};
}

// What every comparison shares: the truth drawn from the frame's camera, the frame's
// G-buffer, the silhouette band.
struct Truth {
    const FrameRequest& r;
    FrameRuns& f;
    int w, h;
    TessellationOptions options;
    Tessellation tess;
    GeometryFrame frame;
    std::vector<std::uint8_t> band;

    TruthComparison compare(const ShownFrame& shown) const {
        return compare_to_truth(frame, shown, f.gb, f.engine.depth, f.engine.normal, band, r.table,
                                f.engine.camera.inverse_view_projection, w, h);
    }
    // The G-buffer's first projection for a triplanar pixel's uv (every frame's alike).
    GeometryFrame draw(const Scene& scene, int repeats) const {
        return triplanar_truth_uv(f.renderer->render_geometry(scene, repeats),
                                  f.runs[0].first_projection, r.table);
    }
};

// `auto` chose its method on this frame's G-buffer before the truth was drawn: the frame is
// judged as it was shaded, and the sweep of pixel methods sets each method on every material
// alike. A triplanar material's uv is compared in the projection traced first.
nlohmann::json notes(const FrameRequest& r) {
    nlohmann::json notes = nlohmann::json::array();
    if (r.cmd->method.empty())
        for (const LoadedMaterial& m : r.table)
            if (m.spec.method == "auto")
                notes.push_back("material " + std::to_string(m.spec.id) + " (" + m.spec.name +
                                ") is auto: its rows below measure the method auto chose for this "
                                "frame; the sweep of pixel methods sets each method in its place");
    for (const LoadedMaterial& m : r.table)
        if (m.spec.triplanar.enabled)
            notes.push_back("material " + std::to_string(m.spec.id) + " (" + m.spec.name +
                            ") is triplanar: its uv is compared in the projection the frame traces "
                            "first; the truth's own bound is not derived for it");
    for (const auto& note : notes) std::printf("truth: %s\n", note.get<std::string>().c_str());
    return notes;
}

// Mismatched pixels over the frame, darkened: red where the truth shows relief and the frame
// none, blue where the frame shows relief and the truth none, magenta where both show relief of
// different surfaces.
Rgb8 mismatch_overlay(int w, int h, const FrameRun& run, const TruthComparison& c,
                      const GeometryFrame& truth, const std::vector<float>& frame_ids) {
    std::vector<cl_float4> color(run.color);
    for (size_t k = 0; k < color.size(); ++k) {
        for (int i = 0; i < 3; ++i) color[k].s[i] *= 0.35f;
        if (!c.mismatched[k]) continue;
        const bool truth_relief = truth.depth[k] < 1.0f && truth.material[k] > 0.0f;
        const bool frame_relief =
            frame_ids[k] > 0.0f && !(run.offset.flags[k] & OM_FLAGS_NOT_SHOWN);
        color[k] = truth_relief && frame_relief ? cl_float4{{1.0f, 0.2f, 1.0f, 1.0f}}
                   : truth_relief               ? cl_float4{{1.0f, 0.1f, 0.05f, 1.0f}}
                                                : cl_float4{{0.1f, 0.35f, 1.0f, 1.0f}};
    }
    return to_srgb8(w, h, color);
}

// Per material, off the silhouette band: flat against curved surfaces.
nlohmann::json material_rows(const Truth& t, const TruthComparison& c,
                             const std::vector<float>& ids, bool print) {
    nlohmann::json rows = nlohmann::json::array();
    for (const LoadedMaterial& m : t.r.table) {
        std::vector<double> errors;
        for (size_t k = 0; k < c.uv_error.size(); ++k)
            if (!t.band[k] && std::isfinite(c.uv_error[k]) &&
                ids[k] == static_cast<float>(m.spec.id))
                errors.push_back(c.uv_error[k]);
        const ErrorStats e = error_stats(errors);
        rows.push_back({{"id", m.spec.id},
                        {"name", m.spec.name},
                        {"interior_pixels", e.count},
                        {"uv_err_texels", summary_json(e)}});
        if (print)
            std::printf("  %-18s %9zu %9.3g %9.3g %9.3g  (interior)\n",
                        (std::to_string(m.spec.id) + " " + m.spec.name).c_str(), e.count, e.mean,
                        e.p95, e.max);
    }
    return rows;
}

// Triplanar pixels off the band, where one projection covers them and in the blends.
void triplanar_rows(const Truth& t, const FrameRun& run, const TruthComparison& c,
                    nlohmann::json& mode) {
    std::vector<double> errors[2];
    for (size_t k = 0; k < c.uv_error.size(); ++k)
        if (!t.band[k] && std::isfinite(c.uv_error[k]) && run.projection_count[k] > 0.0f)
            errors[run.projection_count[k] > 1.0f].push_back(c.uv_error[k]);
    for (int blend = 0; blend < 2; ++blend) {
        const ErrorStats e = error_stats(errors[blend]);
        mode[blend ? "blend" : "one_projection"] = {{"pixels", e.count},
                                                    {"uv_err_texels", summary_json(e)}};
        std::printf("  %-18s %9zu %9.3g %9.3g %9.3g  (triplanar, interior)\n",
                    blend ? "blend" : "one projection", e.count, e.mean, e.p95, e.max);
    }
}

// Every run against the truth; the first run's pixels' own bounds into `bounds`.
nlohmann::json run_rows(const Truth& t, const std::vector<float>& bound,
                        std::vector<double>& bounds, Tiles& tiles) {
    std::printf("%-20s %9s %28s %28s %10s %8s %8s\n", "mode vs truth", "compared",
                "uv texels mean/p95/max", "depth mean/p95/max", "mismatch", "band", "inside");
    nlohmann::json modes = nlohmann::json::array();
    for (size_t r = 0; r < t.f.runs.size(); ++r) {
        const FrameRun& run = t.f.runs[r];
        const std::string name = run_name(run);
        const ShownFrame shown{name, &t.f.shown_ids[r], &run.offset.uv, &run.depth_after,
                               &run.offset.flags};
        const TruthComparison c = t.compare(shown);
        std::printf("%-20s %9zu %9.3g %9.3g %9.3g %9.3g %9.3g %9.3g %10zu %8zu %8zu\n",
                    name.c_str(), c.compared_pixels, c.uv_err_texels.mean, c.uv_err_texels.p95,
                    c.uv_err_texels.max, c.depth_err.mean, c.depth_err.p95, c.depth_err.max,
                    c.mismatch, c.mismatch_band, c.mismatch_interior);
        modes.push_back({{"mode", name},
                         {"materials", material_rows(t, c, t.f.shown_ids[r], r == 0)},
                         {"compared_pixels", c.compared_pixels},
                         {"uv_err_texels", summary_json(c.uv_err_texels)},
                         {"depth_err", summary_json(c.depth_err)},
                         {"coverage_mismatch", mismatch_json(c)}});
        if (!run.projection_count.empty()) triplanar_rows(t, run, c, modes.back());
        if (r == 0)
            for (size_t k = 0; k < bound.size(); ++k)
                if (std::isfinite(c.uv_error[k]) && std::isfinite(bound[k]))
                    bounds.push_back(bound[k]);
        if (run.mode != FrameMode::Deferred) continue;
        tiles.push_back({name + " uv error vs the displaced mesh (log, white = 16 texels)",
                         heat_map(t.w, t.h, c.uv_error, 16.0f)});
        Rgb8 overlay = mismatch_overlay(t.w, t.h, run, c, t.frame, t.f.shown_ids[r]);
        // Each deferred variant's alone too, for close-ups of its outlines.
        write_image(t.r.cmd->out_dir + "/coverage-" + name + ".png", overlay);
        tiles.push_back({name + " coverage vs the truth: red truth only, blue frame only, "
                                "magenta other surface",
                         std::move(overlay)});
    }
    return modes;
}

// Tessellation as the competitor: coarser lattices of the same displaced mesh, each drawn and
// timed by the same raster and measured against the truth.
nlohmann::json tessellation_rows(const Truth& t) {
    const FrameCommand& cmd = *t.r.cmd;
    nlohmann::json levels = nlohmann::json::array();
    const std::vector<std::uint32_t> no_flags(static_cast<size_t>(t.w) * t.h, 0u);
    std::printf("%-20s %12s %10s %10s %28s %10s\n", "tessellation", "triangles", "MiB", "raster ms",
                "uv texels mean/p95/max", "mismatch");
    std::vector<float> lattice = {8.0f, 4.0f, 2.0f, 1.0f};
    if (cmd.truth_level < 1.0f) lattice.push_back(cmd.truth_level);
    for (float level : lattice) {
        progress_line("truth: tessellation at " + texels_text(level) + " texels per quad");
        TessellationOptions lo = t.options;
        lo.texels_per_quad = level;
        const bool own = level == cmd.truth_level;
        const Tessellation other = own ? Tessellation() : displace_scene(t.r.scene, t.r.table, lo);
        const Tessellation& tess = own ? t.tess : other;
        const GeometryFrame g = t.draw(tess.scene, cmd.repeats);
        std::vector<cl_float2> uv(static_cast<size_t>(t.w) * t.h);
        for (size_t k = 0; k < uv.size(); ++k) uv[k] = {{g.uv[2 * k], g.uv[2 * k + 1]}};
        const TruthComparison c =
            t.compare({"tessellation", &g.material, &uv, &g.depth, &no_flags, &g.normal});
        progress_line("");
        std::printf("%-20s %12zu %10.1f %10.2f %9.3g %9.3g %9.3g %10zu\n",
                    ("  " + texels_text(level) + " texels/quad").c_str(), tess.triangles,
                    tess.bytes / 1048576.0, g.raster_ms, c.uv_err_texels.mean, c.uv_err_texels.p95,
                    c.uv_err_texels.max, c.mismatch);
        levels.push_back({{"texels_per_quad", level},
                          {"triangles", tess.triangles},
                          {"raster_ms", g.raster_ms},
                          {"bytes", tess.bytes},
                          {"uv_err_texels", summary_json(c.uv_err_texels)},
                          {"coverage_mismatch", mismatch_json(c)}});
    }
    return levels;
}

// The per-pixel methods over the same frame (every material the same method, its defaults),
// costed as the G-buffer draw of the base meshes plus the offset pass: what a pixel's uv' costs
// each way.
nlohmann::json pixel_method_rows(const Truth& t, const std::shared_ptr<Runtime>& rt) {
    nlohmann::json rows = nlohmann::json::array();
    for (const char* name :
         {"none", "parallax-limited", "steep", "pom", "relief", "secant", "exact"}) {
        progress_line(std::string("truth: the frame with ") + name);
        const std::vector<MethodParams> one(t.r.table.size(),
                                            resolve_params(find_method(name), {}));
        FrameRenderer f(rt, t.r.scene, t.r.table, one, t.w, t.h, ShadeSettings{});
        const FrameRun run = f.render(FrameMode::Deferred, false, t.r.cmd->repeats);
        const std::vector<float> ids = f.gbuffer().material;
        const TruthComparison c =
            t.compare({name, &ids, &run.offset.uv, &run.depth_after, &run.offset.flags});
        progress_line("");
        rows.push_back({{"method", name},
                        {"gbuffer_ms", run.ms.gbuffer},
                        {"offset_ms", run.ms.offset},
                        {"offset_kernel_ms", run.offset_kernel_ms},
                        {"uv_err_texels", summary_json(c.uv_err_texels)},
                        {"coverage_mismatch", mismatch_json(c)}});
    }
    return rows;
}

// The truth's own bound over the first run's compared pixels; null where none has one (only
// triplanar relief shown), not a bound of 0.
nlohmann::json bound_json(const std::vector<double>& bounds) {
    const ErrorStats b = error_stats(bounds);
    const auto value = [&](double v) { return b.count ? nlohmann::json(v) : nlohmann::json(); };
    if (b.count)
        std::printf("truth's own bound: mean %.3g, p95 %.3g, max %.3g texels over %zu pixels\n",
                    b.mean, b.p95, b.max, b.count);
    else
        std::printf("truth's own bound: not derived for any pixel compared\n");
    return {{"p95", value(b.p95)}, {"mean", value(b.mean)}, {"max", value(b.max)}};
}

nlohmann::json mesh_rows(const Tessellation& tess) {
    nlohmann::json meshes = nlohmann::json::array();
    for (const TessellatedMesh& m : tess.meshes)
        meshes.push_back(
            {{"name", m.name},
             {"material", m.material},
             {"base_triangles", m.base_triangles},
             {"triangles", m.triangles},
             {"height_bound",
              std::isfinite(m.height_bound) ? nlohmann::json(m.height_bound) : nlohmann::json()}});
    return meshes;
}

}  // namespace

nlohmann::json truth_section(const FrameRequest& r, const std::shared_ptr<Runtime>& rt,
                             FrameRuns& f, Tiles& tiles) {
    const FrameCommand& cmd = *r.cmd;
    Truth t{r, f, cmd.width, cmd.height, {}, {}, {}, {}};
    t.options.texels_per_quad = cmd.truth_level;
    t.options.width = t.w;
    t.options.height = t.h;
    progress_line("truth: tessellating the relief meshes at " + texels_text(cmd.truth_level) +
                  " texels per quad");
    t.tess = displace_scene(r.scene, r.table, t.options);
    size_t relief_meshes = 0;
    for (const TessellatedMesh& m : t.tess.meshes) relief_meshes += m.texels_per_quad > 0.0f;
    if (relief_meshes == 0) {
        const std::string note =
            "the scene has no mesh with relief (no material or a scale of 0): nothing to measure";
        std::printf("truth: %s\n", note.c_str());
        return {{"notes", {note}}};
    }
    const nlohmann::json noted = notes(r);
    t.frame = t.draw(t.tess.scene, 1);
    const std::vector<float> bound = truth_bound_texels(f.gb, f.engine.material, r.table, t.tess);
    t.band = silhouette_band(f.engine.material, f.engine.depth, f.runs[0].offset.flags, t.w, t.h);
    std::printf("truth: %zu triangles (%.1f MiB) built in %.0f ms, drawn in %.0f ms\n",
                t.tess.triangles, t.tess.bytes / 1048576.0, t.tess.build_ms, t.frame.raster_ms);
    std::vector<double> bounds;
    const nlohmann::json modes = run_rows(t, bound, bounds, tiles);
    const nlohmann::json levels = tessellation_rows(t);
    const nlohmann::json pixel_methods = pixel_method_rows(t, rt);
    const nlohmann::json b = bound_json(bounds);
    return {{"texels_per_quad", cmd.truth_level},
            {"triangles", t.tess.triangles},
            {"bytes", t.tess.bytes},
            {"build_ms", t.tess.build_ms},
            {"raster_ms", t.frame.raster_ms},
            {"bound_texels", b["p95"]},
            {"bound_texels_stats", b},
            {"meshes", mesh_rows(t.tess)},
            {"modes", modes},
            {"tessellation", levels},
            {"pixel_methods", pixel_methods},
            {"raster_on", f.renderer->gl_renderer()},
            {"passes_on", rt->device_name()},
            {"notes", noted}};
}

}  // namespace offsetmap::cli
#endif
