// `offsetmap frame`: a rasterized deferred frame around the pass (OpenGL through EGL for the
// G-buffer, the OpenCL passes for offset and shading, the depth offset written back), and with
// --forward the forward peer: the same methods in the G-buffer pass's fragment shader.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "frame_shadows.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/gltf.hpp"
#include "offsetmap/renderer/truth.hpp"
#include "offsetmap/shadow_mask_pass.hpp"
#endif

namespace offsetmap::cli {

void FrameCommand::add_to(CLI::App& app) {
    app.add_option("--scene", scene,
                   "the built-in 'room', or a glTF 2.0 file (.gltf or .glb) whose material names "
                   "the table's entries name")
        ->capture_default_str();
    app.add_option("--materials", materials,
                   "material table (JSON) for the scene's ids or glTF material names (default: "
                   "data/room.json for the room, FILE.json beside FILE.gltf)");
    app.add_option("--camera", camera,
                   "eye and target (and vertical field of view): ex,ey,ez,tx,ty,tz[,fov]");
    app.add_option("--width", width, "frame width")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--height", height, "frame height")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    app.add_option("--method", method,
                   "one method for every material (else each entry's own; see 'offsetmap "
                   "methods')");
    app.add_option("--set", sets, "--method's parameter key=value (repeatable)");
    app.add_flag("--forward", forward,
                 "also render the forward peer: each material's method in the G-buffer "
                 "fragment shader (GLSL), with and without a depth pre-pass");
    app.add_flag("--curvature", curvature,
                 "also render the deferred frame over the curved base: the raster's curvature "
                 "plane to the offset pass, which bends each ray with the surface and leaves "
                 "the pixels whose ray leaves the relief to the background (final.png is this "
                 "frame's)");
    app.add_option("--layers", layers,
                   "2: also render the deferred frame with the G-buffer's second layer (depth "
                   "peeling): the pixels the first layer's relief does not show (rays that leave "
                   "the curved base, tile-mask discards) traced on the surface behind (final.png "
                   "is this frame's)")
        ->check(CLI::Range(1, 2))
        ->capture_default_str();
    app.add_flag("--truth", truth,
                 "also draw the truth: each relief mesh tessellated and displaced for real, and "
                 "measure every frame against it (frame.json's truth, truth-*.png)");
    app.add_option("--truth-level", truth_level,
                   "the truth's lattice in texels per quad (0.5: 2 x 2 quads a texel; 1, 0.25, "
                   "...)")
        ->check(CLI::Range(0.0625, 1.0))
        ->capture_default_str();
    app.add_option("--sun", sun,
                   "ELEVATION,AZIMUTH (degrees; azimuth from +x toward +z): also render the "
                   "directional light's view through the deferred passes, its displaced shadow "
                   "map (shadow-map.exr, and shadow-map-base.exr before the offset)");
    app.add_option("--shadow-size", shadow_size, "the light's shadow map, pixels a side")
        ->check(CLI::Range(16, 8192))
        ->capture_default_str();
    app.add_option("--shadow-truth-size", shadow_truth_size,
                   "with --truth and --sun: the displaced meshes' own shadow map, pixels a side "
                   "(default: --shadow-size; finer measures what the map's resolution misses)")
        ->check(CLI::Range(16, 8192));
    app.add_option("-o,--out", out_dir, "output folder")->capture_default_str();
    app.add_option("--repeats", repeats, "timed frames per mode (median reported)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    app.add_option("--shadows", shadows,
                   "shadows in the shading: the relief's self-shadows (hard, soft), the sun's "
                   "displaced shadow map (map, with --sun), or both (map+hard, map+soft)")
        ->check(CLI::IsMember({"none", "hard", "soft", "map", "map+hard", "map+soft"}))
        ->capture_default_str();
    app.add_option("--device", device, "OpenCL device (substring of its name)");
    app.add_option("--data", data_dir,
                   "folder of the default data (default: the data/ found "
                   "beside the program)");
}

#ifndef OFFSETMAP_HAVE_RENDERER

int run_frame(const FrameCommand&) {
    throw Error(
        "frame: this offsetmap was built without the renderer (EGL and OpenGL were not found; "
        "Debian: libegl-dev libopengl-dev libgl1-mesa-dri); rebuild with them");
}

#else

namespace {

using namespace offsetmap::renderer;

// A run's name in frame.json: `deferred` (the tangent plane), `deferred-curved`, `forward`,
// `forward-prepass` (the modes table spells the last `forward + pre-pass`).
std::string run_name(const FrameRun& r) {
    if (r.mode == FrameMode::Deferred)
        return r.layers == 2 ? "deferred-two-layers" : r.curved ? "deferred-curved" : "deferred";
    return r.prepass ? "forward-prepass" : "forward";
}

nlohmann::json pass_json(const PassTimes& t) {
    return {{"gbuffer_ms", t.gbuffer},
            {"to_device_ms", t.to_device},
            {"reconstruct_ms", t.reconstruct},
            {"offset_ms", t.offset},
            {"shade_ms", t.shade},
            {"to_gl_ms", t.to_gl},
            {"depth_offset_ms", t.depth_offset},
            {"shadow_mask_ms", t.shadow_mask},
            {"total_ms", t.total}};
}

nlohmann::json pass_json(const FrameRun& r) {
    nlohmann::json j = pass_json(r.ms);
    // With the sun's shadow map: the light's passes that drew it, once a frame (their times are
    // in the frame's total).
    if (!r.shadow_mask.empty()) j["shadow_map"] = pass_json(r.shadow_map_ms);
    j["frames"] = r.frames;
    j["light_draws"] = r.light_draws;
    return j;
}

// Depth offset as a picture: grey where unchanged, darker where pushed away from the eye.
Rgb8 depth_change_image(int w, int h, const std::vector<float>& before,
                        const std::vector<float>& after) {
    std::vector<float> change(before.size());
    for (size_t k = 0; k < change.size(); ++k)
        change[k] = before[k] >= 1.0f ? std::nanf("") : std::abs(after[k] - before[k]) * 1e4f;
    return heat_map(w, h, change, 16.0f);
}

nlohmann::json summary_json(const ErrorSummary& e) {
    return {{"mean", e.mean}, {"p95", e.p95}, {"max", e.max}};
}

// Mismatched pixels over the frame, darkened: red where the truth shows relief and the frame none,
// blue where the frame shows relief and the truth none, magenta where both show relief of
// different surfaces.
Rgb8 mismatch_overlay(int w, int h, const std::vector<cl_float4>& color,
                      const std::vector<std::uint8_t>& mismatched, const GeometryFrame& truth,
                      const std::vector<float>& frame_ids,
                      const std::vector<std::uint32_t>& flags) {
    std::vector<cl_float4> c(color);
    for (size_t k = 0; k < c.size(); ++k) {
        for (int i = 0; i < 3; ++i) c[k].s[i] *= 0.35f;
        if (!mismatched[k]) continue;
        const bool truth_relief = truth.depth[k] < 1.0f && truth.material[k] > 0.0f;
        const bool frame_relief = frame_ids[k] > 0.0f && !(flags[k] & OM_FLAGS_NOT_SHOWN);
        c[k] = truth_relief && frame_relief ? cl_float4{{1.0f, 0.2f, 1.0f, 1.0f}}
               : truth_relief               ? cl_float4{{1.0f, 0.1f, 0.05f, 1.0f}}
                                            : cl_float4{{0.1f, 0.35f, 1.0f, 1.0f}};
    }
    return to_srgb8(w, h, c);
}

// The displaced mesh drawn as the truth, and each frame against it.
std::string texels_text(double texels_per_quad) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", texels_per_quad);
    return text;
}

nlohmann::json truth_section(const FrameCommand& cmd, const Scene& scene,
                             const std::vector<LoadedMaterial>& table,
                             const std::shared_ptr<Runtime>& rt, FrameRenderer& renderer,
                             const GBuffer& gb, const EngineScene& engine,
                             const std::vector<FrameRun>& runs,
                             const std::vector<std::vector<float> >& shown_ids,
                             std::vector<std::pair<std::string, Rgb8> >& tiles) {
    const int w = cmd.width, h = cmd.height;
    TessellationOptions options;
    options.texels_per_quad = cmd.truth_level;
    options.width = w;
    options.height = h;
    progress_line("truth: tessellating the relief meshes at " + texels_text(cmd.truth_level) +
                  " texels per quad");
    const Tessellation tess = displace_scene(scene, table, options);
    size_t relief_meshes = 0;
    for (const TessellatedMesh& m : tess.meshes) relief_meshes += m.texels_per_quad > 0.0f;
    if (relief_meshes == 0) {
        const std::string note =
            "the scene has no mesh with relief (no material or a scale of 0): nothing to measure";
        std::printf("truth: %s\n", note.c_str());
        return {{"notes", {note}}};
    }
    // `auto` chose its method on this frame's G-buffer before the truth was drawn: the frame is
    // judged as it was shaded, and the sweep below sets each method on every material alike.
    nlohmann::json notes = nlohmann::json::array();
    if (cmd.method.empty())
        for (const LoadedMaterial& m : table)
            if (m.spec.method == "auto")
                notes.push_back("material " + std::to_string(m.spec.id) + " (" + m.spec.name +
                                ") is auto: its rows below measure the method auto chose for this "
                                "frame; the sweep of pixel methods sets each method in its place");
    for (const LoadedMaterial& m : table)
        if (m.spec.triplanar.enabled)
            notes.push_back("material " + std::to_string(m.spec.id) + " (" + m.spec.name +
                            ") is triplanar: its uv is compared in the projection the frame traces "
                            "first; the truth's own bound is not derived for it");
    for (const auto& note : notes) std::printf("truth: %s\n", note.get<std::string>().c_str());
    // A triplanar pixel's uv in the projection the G-buffer gives it first (every frame's alike).
    const std::vector<std::int8_t>& first = runs[0].first_projection;
    const GeometryFrame truth =
        triplanar_truth_uv(renderer.render_geometry(tess.scene, 1), first, table);
    const std::vector<float> bound = truth_bound_texels(gb, engine.material, table, tess);
    const std::vector<std::uint8_t> band =
        silhouette_band(engine.material, engine.depth, runs[0].offset.flags, w, h);
    nlohmann::json modes = nlohmann::json::array();
    std::printf("truth: %zu triangles (%.1f MiB) built in %.0f ms, drawn in %.0f ms\n",
                tess.triangles, tess.bytes / 1048576.0, tess.build_ms, truth.raster_ms);
    std::printf("%-20s %9s %28s %28s %10s %8s %8s\n", "mode vs truth", "compared",
                "uv texels mean/p95/max", "depth mean/p95/max", "mismatch", "band", "inside");
    std::vector<double> bounds;
    for (size_t r = 0; r < runs.size(); ++r) {
        const FrameRun& run = runs[r];
        const std::string name = run_name(run);
        const ShownFrame shown{name, &shown_ids[r], &run.offset.uv, &run.depth_after,
                               &run.offset.flags};
        const TruthComparison c =
            compare_to_truth(truth, shown, gb, engine.depth, engine.normal, band, table,
                             engine.camera.inverse_view_projection, w, h);
        std::printf("%-20s %9zu %9.3g %9.3g %9.3g %9.3g %9.3g %9.3g %10zu %8zu %8zu\n",
                    name.c_str(), c.compared_pixels, c.uv_err_texels.mean, c.uv_err_texels.p95,
                    c.uv_err_texels.max, c.depth_err.mean, c.depth_err.p95, c.depth_err.max,
                    c.mismatch, c.mismatch_band, c.mismatch_interior);
        // Per material, off the silhouette band: flat against curved surfaces.
        nlohmann::json per_material = nlohmann::json::array();
        for (const LoadedMaterial& m : table) {
            std::vector<double> errors;
            for (size_t k = 0; k < c.uv_error.size(); ++k)
                if (!band[k] && std::isfinite(c.uv_error[k]) &&
                    shown_ids[r][k] == static_cast<float>(m.spec.id))
                    errors.push_back(c.uv_error[k]);
            const ErrorStats e = error_stats(errors);
            per_material.push_back(
                {{"id", m.spec.id},
                 {"name", m.spec.name},
                 {"interior_pixels", e.count},
                 {"uv_err_texels", {{"mean", e.mean}, {"p95", e.p95}, {"max", e.max}}}});
            if (r == 0)
                std::printf("  %-18s %9zu %9.3g %9.3g %9.3g  (interior)\n",
                            (std::to_string(m.spec.id) + " " + m.spec.name).c_str(), e.count,
                            e.mean, e.p95, e.max);
        }
        modes.push_back({{"mode", name},
                         {"materials", per_material},
                         {"compared_pixels", c.compared_pixels},
                         {"uv_err_texels", summary_json(c.uv_err_texels)},
                         {"depth_err", summary_json(c.depth_err)},
                         {"coverage_mismatch",
                          {{"pixels", c.mismatch},
                           {"silhouette_band", c.mismatch_band},
                           {"interior", c.mismatch_interior}}}});
        if (!run.projection_count.empty()) {
            // Triplanar pixels off the band, where one projection covers them and in the blends.
            std::vector<double> errors[2];
            for (size_t k = 0; k < c.uv_error.size(); ++k)
                if (!band[k] && std::isfinite(c.uv_error[k]) && run.projection_count[k] > 0.0f)
                    errors[run.projection_count[k] > 1.0f].push_back(c.uv_error[k]);
            for (int blend = 0; blend < 2; ++blend) {
                const ErrorStats e = error_stats(errors[blend]);
                modes.back()[blend ? "blend" : "one_projection"] = {
                    {"pixels", e.count},
                    {"uv_err_texels", {{"mean", e.mean}, {"p95", e.p95}, {"max", e.max}}}};
                std::printf("  %-18s %9zu %9.3g %9.3g %9.3g  (triplanar, interior)\n",
                            blend ? "blend" : "one projection", e.count, e.mean, e.p95, e.max);
            }
        }
        if (r == 0)
            for (size_t k = 0; k < bound.size(); ++k)
                if (std::isfinite(c.uv_error[k]) && std::isfinite(bound[k]))
                    bounds.push_back(bound[k]);
        if (run.mode == FrameMode::Deferred) {
            tiles.push_back({name + " uv error vs the displaced mesh (log, white = 16 texels)",
                             heat_map(w, h, c.uv_error, 16.0f)});
            Rgb8 overlay = mismatch_overlay(w, h, run.color, c.mismatched, truth, shown_ids[r],
                                            run.offset.flags);
            // Each deferred variant's alone too, for close-ups of its outlines.
            write_image(cmd.out_dir + "/coverage-" + name + ".png", overlay);
            tiles.push_back({name + " coverage vs the truth: red truth only, blue frame only, "
                                    "magenta other surface",
                             std::move(overlay)});
        }
    }
    // Tessellation as the competitor: coarser lattices of the same displaced mesh, each drawn and
    // timed by the same raster and measured against the truth.
    nlohmann::json levels = nlohmann::json::array();
    const std::vector<std::uint32_t> no_flags(static_cast<size_t>(w) * h, 0u);
    std::printf("%-20s %12s %10s %10s %28s %10s\n", "tessellation", "triangles", "MiB", "raster ms",
                "uv texels mean/p95/max", "mismatch");
    std::vector<float> lattice = {8.0f, 4.0f, 2.0f, 1.0f};
    if (cmd.truth_level < 1.0f) lattice.push_back(cmd.truth_level);
    for (float level : lattice) {
        progress_line("truth: tessellation at " + texels_text(level) + " texels per quad");
        TessellationOptions lo = options;
        lo.texels_per_quad = level;
        const bool own = level == cmd.truth_level;
        const Tessellation t = own ? Tessellation() : displace_scene(scene, table, lo);
        const GeometryFrame g = triplanar_truth_uv(
            renderer.render_geometry(own ? tess.scene : t.scene, cmd.repeats), first, table);
        std::vector<cl_float2> uv(static_cast<size_t>(w) * h);
        for (size_t k = 0; k < uv.size(); ++k) uv[k] = {{g.uv[2 * k], g.uv[2 * k + 1]}};
        const ShownFrame shown{"tessellation", &g.material, &uv, &g.depth, &no_flags, &g.normal};
        const TruthComparison c =
            compare_to_truth(truth, shown, gb, engine.depth, engine.normal, band, table,
                             engine.camera.inverse_view_projection, w, h);
        const size_t triangles = own ? tess.triangles : t.triangles;
        const size_t bytes = own ? tess.bytes : t.bytes;
        progress_line("");
        std::printf("%-20s %12zu %10.1f %10.2f %9.3g %9.3g %9.3g %10zu\n",
                    ("  " + texels_text(level) + " texels/quad").c_str(), triangles,
                    bytes / 1048576.0, g.raster_ms, c.uv_err_texels.mean, c.uv_err_texels.p95,
                    c.uv_err_texels.max, c.mismatch);
        levels.push_back({{"texels_per_quad", level},
                          {"triangles", triangles},
                          {"raster_ms", g.raster_ms},
                          {"bytes", bytes},
                          {"uv_err_texels", summary_json(c.uv_err_texels)},
                          {"coverage_mismatch",
                           {{"pixels", c.mismatch},
                            {"silhouette_band", c.mismatch_band},
                            {"interior", c.mismatch_interior}}}});
    }
    // The per-pixel methods over the same frame (every material the same method, its defaults),
    // costed as the G-buffer draw of the base meshes plus the offset pass: what a pixel's uv'
    // costs each way.
    nlohmann::json pixel_methods = nlohmann::json::array();
    for (const char* name :
         {"none", "parallax-limited", "steep", "pom", "relief", "secant", "exact"}) {
        progress_line(std::string("truth: the frame with ") + name);
        const std::vector<MethodParams> one(table.size(), resolve_params(find_method(name), {}));
        FrameRenderer f(rt, scene, table, one, w, h, ShadeSettings{});
        const FrameRun run = f.render(FrameMode::Deferred, false, cmd.repeats);
        const std::vector<float> ids = f.gbuffer().material;
        const ShownFrame shown{name, &ids, &run.offset.uv, &run.depth_after, &run.offset.flags};
        const TruthComparison c =
            compare_to_truth(truth, shown, gb, engine.depth, engine.normal, band, table,
                             engine.camera.inverse_view_projection, w, h);
        progress_line("");
        pixel_methods.push_back({{"method", name},
                                 {"gbuffer_ms", run.ms.gbuffer},
                                 {"offset_ms", run.ms.offset},
                                 {"offset_kernel_ms", run.offset_kernel_ms},
                                 {"uv_err_texels", summary_json(c.uv_err_texels)},
                                 {"coverage_mismatch",
                                  {{"pixels", c.mismatch},
                                   {"silhouette_band", c.mismatch_band},
                                   {"interior", c.mismatch_interior}}}});
    }
    const ErrorStats b = error_stats(bounds);
    // No pixel with a bound (only triplanar relief shown): null, not a bound of 0.
    const auto bound_json = [&](double v) {
        return b.count ? nlohmann::json(v) : nlohmann::json();
    };
    if (b.count)
        std::printf("truth's own bound: mean %.3g, p95 %.3g, max %.3g texels over %zu pixels\n",
                    b.mean, b.p95, b.max, b.count);
    else
        std::printf("truth's own bound: not derived for any pixel compared\n");
    nlohmann::json meshes = nlohmann::json::array();
    for (const TessellatedMesh& m : tess.meshes)
        meshes.push_back(
            {{"name", m.name},
             {"material", m.material},
             {"base_triangles", m.base_triangles},
             {"triangles", m.triangles},
             {"height_bound",
              std::isfinite(m.height_bound) ? nlohmann::json(m.height_bound) : nlohmann::json()}});
    return {
        {"texels_per_quad", cmd.truth_level},
        {"triangles", tess.triangles},
        {"bytes", tess.bytes},
        {"build_ms", tess.build_ms},
        {"raster_ms", truth.raster_ms},
        {"bound_texels", bound_json(b.p95)},
        {"bound_texels_stats",
         {{"mean", bound_json(b.mean)}, {"p95", bound_json(b.p95)}, {"max", bound_json(b.max)}}},
        {"meshes", meshes},
        {"modes", modes},
        {"tessellation", levels},
        {"pixel_methods", pixel_methods},
        {"raster_on", renderer.gl_renderer()},
        {"passes_on", rt->device_name()},
        {"notes", notes}};
}

// --sun's "ELEVATION,AZIMUTH" as the world direction toward the light (y up, azimuth from +x
// toward +z). Throws UsageError naming --sun.
std::array<float, 3> sun_direction(const std::string& text, double& elevation, double& azimuth) {
    const size_t comma = text.find(',');
    size_t used_e = 0, used_a = 0;
    try {
        if (comma == std::string::npos) throw std::invalid_argument("no comma");
        elevation = std::stod(text.substr(0, comma), &used_e);
        azimuth = std::stod(text.substr(comma + 1), &used_a);
    } catch (const std::exception&) {
        used_e = 0;
    }
    if (used_e == 0 || used_e != comma || used_a != text.size() - comma - 1 ||
        !(elevation > 0.0 && elevation <= 90.0) || !std::isfinite(azimuth))
        throw UsageError(
            "--sun: expected ELEVATION,AZIMUTH in degrees, elevation in (0, 90], got '" + text +
            "'");
    const double e = elevation * M_PI / 180.0, a = azimuth * M_PI / 180.0;
    return {float(std::cos(e) * std::cos(a)), float(std::sin(e)), float(std::cos(e) * std::sin(a))};
}

// The sun's view of the scene through the deferred passes (light_camera: orthographic over the
// scene): the displaced shadow map and the base's, written beside the frame; its sheet tile.
nlohmann::json light_view(const FrameCommand& cmd, const Scene& scene,
                          const std::vector<LoadedMaterial>& table,
                          const std::vector<MethodParams>& methods,
                          const std::shared_ptr<Runtime>& rt, const ShadeSettings& shading,
                          const EngineCamera& camera, const std::vector<float>& frame_depth,
                          std::vector<std::pair<std::string, Rgb8> >& tiles) {
    double elevation = 0, azimuth = 0;
    const std::array<float, 3> toward = sun_direction(cmd.sun, elevation, azimuth);
    Scene lit = scene;
    lit.camera = light_camera(scene, toward);
    const int n = cmd.shadow_size;
    FrameRenderer light(rt, lit, table, methods, n, n, shading);
    const FrameRun run = light.render(FrameMode::Deferred, false, cmd.repeats);
    const std::vector<float>& base = light.depth_before();
    const std::string d = cmd.out_dir + "/";
    write_depth_exr(d + "shadow-map.exr", n, n, run.depth_after);
    write_depth_exr(d + "shadow-map-base.exr", n, n, base);
    // The relief's depth below the base along the light's ray, in world units.
    const double range = lit.camera.far_plane - lit.camera.near_plane;
    std::vector<double> moved;
    for (size_t k = 0; k < base.size(); ++k)
        if (base[k] < 1.0f) moved.push_back((run.depth_after[k] - base[k]) * range);
    const ErrorStats relief = error_stats(moved);
    std::printf(
        "sun at %.1f, %.1f degrees: %dx%d shadow map over %zu covered pixels in %.2f ms (offset "
        "%.2f); the relief moves it by up to %.4g m (p95 %.4g)\n",
        elevation, azimuth, n, n, moved.size(), run.ms.total, run.ms.offset, relief.max,
        relief.p95);
    tiles.push_back(
        {"the sun's view: displaced shadow map against the base's (log, white = "
         "16e-4 of its depth range)",
         depth_change_image(n, n, base, run.depth_after)});
    // The receivers' test of the shown frame's points (after its depth offset) against the map,
    // 3 x 3 taps; the kernel takes GL's rows, bottom first.
    const int w = cmd.width, h = cmd.height;
    auto upload = [&](const std::vector<float>& v) {
        return cl::Buffer(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                          v.size() * sizeof(float), const_cast<float*>(v.data()));
    };
    const std::vector<float> depth_rows = flip_row_order(frame_depth, w, h);
    const std::vector<float> map_rows = flip_row_order(run.depth_after, n, n);
    const cl::Buffer depth_buffer = upload(depth_rows), map_buffer = upload(map_rows);
    const cl::Buffer mask_buffer(rt->context(), CL_MEM_WRITE_ONLY, size_t(w) * h * sizeof(float));
    ShadowMaskInputs in;
    in.width = w;
    in.height = h;
    in.camera = camera;
    in.camera.first_row = FirstRow::Bottom;
    in.depth = depth_buffer;
    in.map = light.shadow_map_view(map_buffer);
    ShadowMaskPass(rt).enqueue(in, {mask_buffer}).wait();
    std::vector<float> mask(size_t(w) * h);
    rt->queue().enqueueReadBuffer(mask_buffer, CL_TRUE, 0, mask.size() * sizeof(float),
                                  mask.data());
    mask = flip_row_order(mask, w, h);
    size_t covered = 0, shadowed = 0;
    Rgb8 picture{w, h, std::vector<std::uint8_t>(mask.size() * 3)};
    for (size_t k = 0; k < mask.size(); ++k) {
        const bool drawn = frame_depth[k] < 1.0f;
        covered += drawn;
        shadowed += drawn && mask[k] < 0.5f;
        const std::uint8_t g = drawn ? std::uint8_t(40 + 215 * mask[k]) : 0;
        picture.rgb[3 * k] = picture.rgb[3 * k + 1] = picture.rgb[3 * k + 2] = g;
    }
    std::printf("the frame's points against it (3 x 3 taps): %zu of %zu in shadow\n", shadowed,
                covered);
    write_image(d + "shadow-mask.png", picture);
    tiles.push_back(
        {"the frame's points against the sun's displaced map (white lit, dark in "
         "shadow; in the shading with --shadows map)",
         picture});
    return {{"sun_deg", {elevation, azimuth}},
            {"toward_light", toward},
            {"size", n},
            {"half_extent_m", lit.camera.ortho_half_height},
            {"depth_range_m", range},
            {"covered_pixels", moved.size()},
            {"passes", pass_json(run)},
            {"relief_depth_m", {{"p95", relief.p95}, {"max", relief.max}}},
            {"frame_pixels_in_shadow", shadowed}};
}

}  // namespace

int run_frame(const FrameCommand& cmd) {
    // Options first: nothing is read or rendered before they are checked.
    if (!cmd.sets.empty() && cmd.method.empty()) throw UsageError("--set needs --method");
    const bool gltf = is_gltf_path(cmd.scene);
    if (!gltf && cmd.scene != "room")
        throw UsageError("--scene: '" + cmd.scene +
                         "' is neither the built-in 'room' nor a .gltf or .glb file");
    Camera camera;
    if (!cmd.camera.empty()) camera = as_usage([&] { return parse_camera(cmd.camera); });
    std::array<float, 3> sun{};
    if (!cmd.sun.empty()) {
        double elevation = 0, azimuth = 0;
        sun = sun_direction(cmd.sun, elevation, azimuth);
    }
    const ShadowChoice shadows = parse_shadows(cmd.shadows);
    if (shadows.map && cmd.sun.empty())
        throw UsageError("--shadows " + cmd.shadows + ": a shadow map needs the sun (--sun)");
    MethodParams override_params;
    if (!cmd.method.empty()) {
        override_params = as_usage([&] {
            std::map<std::string, std::string> overrides;
            for (const std::string& s : cmd.sets) parse_assignment(s, overrides);
            return resolve_params(find_method(cmd.method), overrides);
        });
        if (cmd.forward)
            if (const std::string why = forward_method_unsupported(override_params); !why.empty())
                throw UsageError("--forward: " + why);
    }
    // The room's maps and table (a glTF scene's table lies beside it).
    const std::string data_dir =
        gltf ? "" : (cmd.data_dir.empty() ? default_data_dir() : cmd.data_dir);
    std::string table_file = cmd.materials;
    if (table_file.empty())
        table_file = gltf ? std::filesystem::path(cmd.scene).replace_extension(".json").string()
                          : data_dir + "/room.json";
    const std::vector<MaterialSpec> specs = read_material_table(table_file);
    Scene scene = gltf ? load_gltf_scene(cmd.scene, specs, table_file) : builtin_room(data_dir);
    if (!cmd.camera.empty()) {
        // The eye, target and field of view from --camera; the scene's depth range is kept.
        scene.camera.eye = camera.eye;
        scene.camera.target = camera.target;
        scene.camera.fov_y_deg = camera.fov_y_deg;
    }
    // The sun lights the frame it casts shadows in.
    if (!cmd.sun.empty()) scene.light = {LightKind::Directional, sun};
    std::vector<MethodParams> methods;
    std::vector<size_t> auto_slots;  // chosen on the frame's own G-buffer, below
    for (const MaterialSpec& s : specs) {
        if (override_params.method) {
            methods.push_back(override_params);
            continue;
        }
        if (s.method == "auto") {
            auto_slots.push_back(methods.size());
            methods.push_back(resolve_params(find_method("none"), {}));
            continue;
        }
        methods.push_back(resolve_params(find_method(s.method), s.params));
        // Checked here too, before any map is read or a context made.
        if (cmd.forward)
            if (const std::string why = forward_unsupported(s, methods.back()); !why.empty())
                throw Error(why);
    }
    for (const Mesh& m : scene.meshes) {
        bool known = m.material == 0;
        for (const MaterialSpec& s : specs) known |= s.id == m.material;
        if (!known)
            throw Error("mesh '" + m.name + "' has material id " + std::to_string(m.material) +
                        ", which " + table_file + " does not list");
    }
    const std::vector<LoadedMaterial> table = load_materials(specs);
    std::error_code ec;
    std::filesystem::create_directories(cmd.out_dir, ec);
    if (ec) throw Error("cannot create output folder '" + cmd.out_dir + "': " + ec.message());

    auto rt = Runtime::create(cmd.device);
    show_progress(*rt);
    ShadeSettings shading;
    shading.shadow = shadow_mode(shadows.march);
    if (!auto_slots.empty()) {
        // auto calibrates each material on its own pixels of this frame, so the G-buffer is
        // drawn once first (its materials traced with none).
        FrameRenderer probe(rt, scene, table, methods, cmd.width, cmd.height, shading);
        probe.render(FrameMode::Deferred, false, 1);
        for (size_t s : auto_slots) {
            const MaterialSpec& spec = table[s].spec;
            // With --forward both frames run the same method: one with a GLSL version.
            AutoOptions options;
            if (cmd.forward) {
                options.admits = [](const MethodParams& p) {
                    return forward_method_unsupported(p).empty();
                };
                options.admits_text = "with a GLSL version (--forward)";
            }
            const AutoChoice a = choose_method(rt, table[s], probe.explicit_gbuffer(), options);
            methods[s] = a.chosen.params;
            std::printf(
                "material %d (%s): auto, %s <= %g texels -> %s (of %zu candidates on %zu "
                "of its pixels)\n",
                spec.id, spec.name.c_str(), budget_statistic_name(spec.budget), spec.budget.texels,
                method_text(methods[s]).c_str(), a.candidates.size(), a.pixels);
        }
    }
    FrameRenderer renderer(rt, scene, table, methods, cmd.width, cmd.height, shading);
    std::optional<ShadowMapSettings> shown_map;
    if (shadows.map) {
        shown_map = ShadowMapSettings();
        shown_map->size = cmd.shadow_size;
        renderer.set_shadow_map(shown_map);
    }
    const FrameRun deferred = renderer.render(FrameMode::Deferred, false, cmd.repeats);
    const int w = cmd.width, h = cmd.height;
    const OffsetResult exact = renderer.exact();
    const GBuffer gb = renderer.explicit_gbuffer();  // the deferred frame's, exact's
    const EngineScene engine = renderer.gbuffer();   // the deferred frame's, for the files
    const std::vector<float>& deferred_uv = engine.uv;
    const size_t covered = renderer.covered_pixels();

    std::vector<FrameRun> runs = {deferred};
    std::vector<std::vector<float> > shown_ids = {engine.material};  // the ids each run shows
    if (cmd.curvature) {
        renderer.set_curvature(true);
        runs.push_back(renderer.render(FrameMode::Deferred, false, cmd.repeats));
        renderer.set_curvature(false);
        shown_ids.push_back(runs.back().material);
    }
    if (cmd.layers == 2) {
        renderer.set_curvature(cmd.curvature);
        renderer.set_layers(2);
        runs.push_back(renderer.render(FrameMode::Deferred, false, cmd.repeats));
        renderer.set_layers(1);
        renderer.set_curvature(false);
        shown_ids.push_back(runs.back().material);
        std::printf(
            "two layers: %zu pixels show the surface behind, %zu show neither (the "
            "background)\n",
            runs.back().behind_pixels, runs.back().missed_pixels);
    }
    // final.png's run: the two-layer frame with --layers 2, else the curved one with --curvature;
    // the forward runs follow.
    const size_t shown_at = runs.size() - 1, forward_at = runs.size();
    if (cmd.forward) {
        // With --curvature the forward peer traces over the curved base too.
        renderer.set_curvature(cmd.curvature);
        for (bool prepass : {false, true}) {
            runs.push_back(renderer.render(FrameMode::Forward, prepass, cmd.repeats));
            shown_ids.push_back(runs.back().material);
            // Where the forward shader dropped a fragment (the tile mask, a ray that left the
            // curved base) the pixel shows the surface behind it (flagged BEHIND, as the
            // two-layer frame's), or none after a pre-pass.
            const std::vector<float>& uv = renderer.gbuffer().uv;
            for (size_t k = 0; k < gb.pixels(); ++k)
                if (std::memcmp(&uv[2 * k], &deferred_uv[2 * k], 2 * sizeof(float)) != 0)
                    runs.back().offset.flags[k] |=
                        std::isnan(uv[2 * k]) ? OM_FLAG_EMPTY : OM_FLAG_BEHIND;
        }
        renderer.set_curvature(false);
    }
    std::printf("frame: %s scene %dx%d, %zu materials; GL: %s; OpenCL: %s; %s\n",
                scene.name.c_str(), w, h, table.size(), renderer.gl_renderer().c_str(),
                rt->device_name().c_str(), renderer.interop().c_str());
    if (const std::array<size_t, 3>& p = deferred.projections; p[0] + p[1] + p[2] > 0) {
        const double all = double(p[0] + p[1] + p[2]);
        std::printf(
            "triplanar: %zu pixels, traced in one projection %.1f %%, two %.1f %%, three %.1f %%\n",
            p[0] + p[1] + p[2], 100.0 * p[0] / all, 100.0 * p[1] / all, 100.0 * p[2] / all);
    }
    std::printf("%-22s %9s %9s %9s %9s %9s %9s %9s %9s %10s\n", "mode", "G-buffer", "to CL",
                "reconstr", "offset", "shade", "depth off", "to GL", "total", "frag/px");
    nlohmann::json modes = nlohmann::json::array();
    std::vector<std::vector<float> > errors;
    for (const FrameRun& r : runs) {
        const std::string name =
            r.mode == FrameMode::Forward && r.prepass ? "forward + pre-pass" : run_name(r);
        const double overdraw = covered ? double(r.shaded_fragments) / double(covered) : 0.0;
        std::printf("%-22s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %10.2f\n", name.c_str(),
                    r.ms.gbuffer, r.ms.to_device, r.ms.reconstruct, r.ms.offset, r.ms.shade,
                    r.ms.depth_offset, r.ms.to_gl, r.ms.total, overdraw);
        // Against exact on the first layer: only where the frame shows the first layer's surface.
        OffsetResult first_layer = r.offset;
        for (std::uint32_t& f : first_layer.flags)
            if (f & OM_FLAG_BEHIND) f |= OM_FLAG_EMPTY;
        std::vector<float> err;
        const std::vector<MaterialError> stats =
            material_errors(gb, first_layer, exact, table, &err);
        errors.push_back(err);
        nlohmann::json mats = nlohmann::json::array();
        for (size_t s = 0; s < table.size(); ++s)
            mats.push_back({{"id", table[s].spec.id},
                            {"name", table[s].spec.name},
                            {"method", methods[s].method->name},
                            {"method_text", method_text(methods[s])},
                            {"auto", table[s].spec.method == "auto"},
                            {"pixels", stats[s].pixels},
                            {"fetches_per_pixel", stats[s].fetches},
                            {"mean_err_texels", stats[s].error.mean},
                            {"p95_err_texels", stats[s].error.p95},
                            {"max_err_texels", stats[s].error.max}});
        nlohmann::json mode = {{"mode", name},
                               {"passes", pass_json(r)},
                               {"offset_kernel_ms", r.offset_kernel_ms},
                               {"shaded_fragments", r.shaded_fragments},
                               {"shaded_fragments_per_covered_pixel", overdraw},
                               {"materials", mats}};
        const size_t projected = r.projections[0] + r.projections[1] + r.projections[2];
        if (projected > 0)
            mode["triplanar"] = {{"pixels", projected},
                                 {"one_projection", r.projections[0]},
                                 {"two_projections", r.projections[1]},
                                 {"three_projections", r.projections[2]}};
        modes.push_back(mode);
    }
    std::printf("%4s %-10s %-10s %8s", "id", "material", "method", "pixels");
    for (const FrameRun& r : runs)
        std::printf("  %s", r.mode == FrameMode::Deferred ? (r.layers == 2 ? "2 layers mean/p95"
                                                             : r.curved    ? "curved mean/p95"
                                                                           : "deferred mean/p95")
                            : r.prepass                   ? "fwd+pre mean/p95"
                                                          : "forward mean/p95");
    std::printf("  (texels vs exact)\n");
    for (size_t s = 0; s < table.size(); ++s) {
        std::printf("%4d %-10s %-10s %8zu", table[s].spec.id, table[s].spec.name.c_str(),
                    methods[s].method->name.c_str(),
                    modes[0]["materials"][s]["pixels"].get<size_t>());
        for (size_t r = 0; r < runs.size(); ++r)
            std::printf("  %8.4f /%7.4f", modes[r]["materials"][s]["mean_err_texels"].get<double>(),
                        modes[r]["materials"][s]["p95_err_texels"].get<double>());
        std::printf("\n");
    }

    const std::string d = cmd.out_dir + "/";
    nlohmann::json truth_doc;
    std::vector<std::pair<std::string, Rgb8> > truth_tiles;
    if (cmd.truth) {
        truth_doc = truth_section(cmd, scene, table, rt, renderer, gb, engine, runs, shown_ids,
                                  truth_tiles);
        if (!cmd.sun.empty() && truth_doc.contains("modes"))
            truth_doc["shadow_mismatch"] = shadow_truth_section(
                cmd, scene, table, methods, rt, renderer, shading, shown_map, truth_tiles);
    }
    const FrameRun& shown = runs[shown_at];
    write_image(d + "final.png", to_srgb8(w, h, shown.color));
    save_engine_gbuffer(d + "gbuffer.exr", engine);
    write_depth_exr(d + "depth-before.exr", w, h, engine.depth);
    write_depth_exr(d + "depth-after.exr", w, h, shown.depth_after);
    std::vector<std::pair<std::string, Rgb8> > tiles = {
        {"deferred frame (offset pass on the OpenCL device)", to_srgb8(w, h, deferred.color)},
        {"uv error vs exact (log, white = 16 texels)", heat_map(w, h, errors[0], 16.0f)},
        {"depth offset written back (log, white = 16e-4)",
         depth_change_image(w, h, engine.depth, deferred.depth_after)}};
    if (!deferred.projection_count.empty()) {
        // Triplanar pixels by the projections traced: one grey, two orange, three red; the frame
        // dimmed beneath.
        Rgb8 picture = to_srgb8(w, h, deferred.color);
        const std::uint8_t shade[4][3] = {
            {0, 0, 0}, {150, 150, 150}, {245, 150, 40}, {220, 40, 40}};
        for (size_t k = 0; k < deferred.projection_count.size(); ++k) {
            const int c = static_cast<int>(deferred.projection_count[k]);
            for (int i = 0; i < 3; ++i) {
                std::uint8_t& v = picture.rgb[3 * k + i];
                v = c == 0 ? std::uint8_t(v / 3) : std::uint8_t((v + 2 * shade[c][i]) / 3);
            }
        }
        write_image(d + "triplanar.png", picture);
        tiles.push_back(
            {"triplanar projections traced: one (grey), two (orange), three (red)", picture});
    }
    if (cmd.curvature)
        tiles.push_back(
            {"deferred over the curved base (--curvature; rays that leave the relief "
             "show the background)",
             to_srgb8(w, h, runs[1].color)});
    if (cmd.layers == 2)
        tiles.push_back(
            {"deferred with the layer behind (--layers 2): what the rays that leave "
             "show",
             to_srgb8(w, h, shown.color)});
    if (cmd.forward) {
        write_image(d + "final-forward.png", to_srgb8(w, h, runs[forward_at].color));
        tiles.push_back({"forward frame (the methods in the fragment shader)",
                         to_srgb8(w, h, runs[forward_at].color)});
        tiles.push_back({"forward uv error vs exact", heat_map(w, h, errors[forward_at], 16.0f)});
    }
    nlohmann::json sun_doc;
    if (!cmd.sun.empty())
        sun_doc = light_view(cmd, scene, table, methods, rt, shading, engine.camera,
                             shown.depth_after, tiles);
    tiles.insert(tiles.end(), truth_tiles.begin(), truth_tiles.end());
    write_image(d + "frame-sheet.png", contact_sheet(tiles, 2));
    if (!truth_tiles.empty()) write_image(d + "truth-sheet.png", contact_sheet(truth_tiles, 2));
    nlohmann::json doc = {{"scene", scene.name},
                          {"width", w},
                          {"height", h},
                          {"gl_renderer", renderer.gl_renderer()},
                          {"opencl_device", rt->device_name()},
                          {"interop", renderer.interop()},
                          {"covered_pixels", covered},
                          {"repeats", cmd.repeats},
                          {"table", table_file},
                          {"modes", modes}};
    if (cmd.truth) doc["truth"] = truth_doc;
    if (!cmd.sun.empty()) doc["shadow_map"] = sun_doc;
    std::ofstream(d + "frame.json") << doc.dump(2) << "\n";
    const bool measured = cmd.truth && truth_doc.contains("modes");
    if (measured) run_chart_script("plot_truth.py", {d + "frame.json", d + "truth-pareto.png"});
    std::printf(
        "wrote %s{final.png,%sframe-sheet.png,gbuffer.exr,depth-before.exr,"
        "depth-after.exr,frame.json%s}\n",
        d.c_str(), cmd.forward ? "final-forward.png," : "",
        measured ? ",truth-sheet.png,truth-pareto.png,coverage-*.png" : "");
    return 0;
}

#endif

}  // namespace offsetmap::cli
