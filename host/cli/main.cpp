// offsetmap: command-line front end (methods, gbuffer, render, demo).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "om_shared.h"

namespace offsetmap::cli {

void ReliefOptions::add_to(CLI::App& app, bool required) {
    auto* hm = app.add_option("--height-map", height_map, "height map image (PNG, TIFF, EXR, ...)");
    if (required) hm->required();
    app.add_flag("--depth-map", depth_map, "the file stores depth (white = deep)");
    app.add_option("--channel", channel, "channel of the height map to use")
        ->check(CLI::NonNegativeNumber);
    app.add_option("--normal-map", normal_map,
                   "tangent-space normal map (default: derived from heights)");
    app.add_flag("--flip-green", flip_green, "normal map authored DirectX-style (green = -y)");
    app.add_option("--albedo", albedo, "albedo image (default: a neutral checker)");
    app.add_option("--scale", pass.scale, "depth scale s in uv units")->capture_default_str();
    app.add_option("--reference-plane", pass.reference_plane,
                   "height r of the polygon in [0,1] (1: relief below the polygon)")
        ->capture_default_str();
    app.add_option("--grazing-min-deg", pass.min_elevation_deg,
                   "views below this elevation are raised to it (the grazing rule)")
        ->capture_default_str();
    app.add_option("--lod-threshold", pass.lod.threshold,
                   "turn Tatarchuk's LOD on: mip level past which only normal mapping remains")
        ->each([this](const std::string&) { pass.lod.enabled = true; });
    app.add_option("--lod-fade", pass.lod.fade, "LOD: levels over which the effect fades out")
        ->capture_default_str();
    app.add_option("--lod-min-detail", pass.lod.min_detail,
                   "LOD: step-count factor at the threshold")
        ->capture_default_str();
    app.add_flag("--lod-footprint", pass.lod.footprint,
                 "LOD on, footprint mode: steps = texels the ray crosses at the pixel's level")
        ->each([this](const std::string&) { pass.lod.enabled = true; });
    app.add_option("--lod-fade-texels", lod_fade_texels,
                   "footprint LOD: fade over [low high] texels")
        ->expected(2);
    app.add_option("--grazing", grazing,
                   "grazing policy: clamp (raise to --grazing-min-deg), limit (Welsh's offset "
                   "limiting for every method), cap (footprint <= --max-offset texels)")
        ->check(CLI::IsMember({"clamp", "limit", "cap"}))
        ->capture_default_str();
    app.add_option("--max-offset", pass.max_offset_texels,
                   "cap policy: longest ray footprint (texels)")
        ->capture_default_str();
    app.add_flag(
        "--tile-mask", pass.out_of_tile_mask,
        "flag and discard pixels whose uv' leaves [0,1] (silhouettes on non-tiling surfaces)");
    app.add_option("--address", address, "height addressing")
        ->check(CLI::IsMember({"wrap", "clamp"}))
        ->capture_default_str();
    app.add_option("--light", light,
                   "tangent-space light direction x y z (replaces the G-buffer's L)")
        ->expected(3);
    app.add_option("--device", device, "OpenCL platform/device name substring ($OFFSETMAP_DEVICE)");
    app.add_option("--shadows", shadows, "relief self-shadows in the shaded image")
        ->check(CLI::IsMember({"none", "hard", "soft"}))
        ->capture_default_str();
    app.add_option("--shadow-steps", shade.shadow_steps, "samples along the light ray")
        ->check(CLI::Range(1, 256))
        ->capture_default_str();
    app.add_option("--light-size", shade.light_size_deg, "soft shadows: light's angular size (deg)")
        ->check(CLI::Range(0.01, 90.0))
        ->capture_default_str();
}

ShadeSettings ReliefOptions::shade_settings() const {
    ShadeSettings s = shade;
    if (light.size() == 3) std::copy(light.begin(), light.end(), s.light);
    s.shadow = shadows == "hard"   ? ShadowMode::Hard
               : shadows == "soft" ? ShadowMode::Soft
                                   : ShadowMode::None;
    return s;
}

PassSettings ReliefOptions::settings() const {
    PassSettings s = pass;
    s.address = address == "clamp" ? AddressMode::Clamp : AddressMode::Wrap;
    if (lod_fade_texels.size() == 2) {
        s.lod.fade_texels_lo = lod_fade_texels[0];
        s.lod.fade_texels_hi = lod_fade_texels[1];
    }
    s.grazing = grazing == "limit" ? GrazingPolicy::Limit
                : grazing == "cap" ? GrazingPolicy::Cap
                                   : GrazingPolicy::Clamp;
    validate(s);
    return s;
}

void SceneOptions::add_to(CLI::App& app) {
    app.add_option("--scene", scene, "G-buffer source")
        ->check(CLI::IsMember({"plane", "sweep", "random"}))
        ->capture_default_str();
    app.add_option("--width", width, "image width (plane, random)")->check(CLI::PositiveNumber);
    app.add_option("--height", height, "image height (plane, random)")->check(CLI::PositiveNumber);
    app.add_option("--camera-height", plane.camera_height, "plane: camera height in tiles")
        ->capture_default_str();
    app.add_option("--pitch", plane.pitch_deg, "plane: look-down angle in degrees")
        ->capture_default_str();
    app.add_option("--yaw", plane.yaw_deg, "plane: heading in degrees")->capture_default_str();
    app.add_option("--fov", plane.fov_deg, "plane: vertical field of view in degrees")
        ->capture_default_str();
    app.add_option("--elevations", sweep.elevations, "sweep: elevation rows")
        ->capture_default_str();
    app.add_option("--azimuths", sweep.azimuths, "sweep: azimuth columns")->capture_default_str();
    app.add_option("--patch", sweep.patch, "sweep: pixels per patch side")->capture_default_str();
    app.add_option("--seed", random.seed, "random: seed")->capture_default_str();
    app.add_option("--elev-min", random.min_elevation_deg, "sweep/random: lowest view elevation")
        ->capture_default_str();
    app.add_option("--elev-max", random.max_elevation_deg, "sweep/random: highest view elevation")
        ->capture_default_str();
}

GBuffer SceneOptions::make() const {
    if (scene == "plane") {
        PlaneScene p = plane;
        if (width) p.width = width;
        if (height) p.height = height;
        return make_scene(p);
    }
    if (scene == "sweep") {
        SweepScene s = sweep;
        s.min_elevation_deg = random.min_elevation_deg;
        s.max_elevation_deg = random.max_elevation_deg;
        return make_scene(s);
    }
    RandomScene r = random;
    if (width) r.width = width;
    if (height) r.height = height;
    return make_scene(r);
}

}  // namespace offsetmap::cli

using namespace offsetmap;
using namespace offsetmap::cli;

namespace {

void print_methods(bool json) {
    if (json) {
        nlohmann::json out = nlohmann::json::array();
        for (const auto& m : methods()) {
            nlohmann::json params = nlohmann::json::array();
            for (const auto& p : m.params)
                params.push_back({{"name", p.name},
                                  {"default", p.default_value},
                                  {"min", p.min_value},
                                  {"max", p.max_value},
                                  {"integer", p.integer},
                                  {"doc", p.doc}});
            out.push_back({{"name", m.name},
                           {"summary", m.summary},
                           {"reference", m.reference},
                           {"precomputed", m.precompute ? m.precompute->doc : "none"},
                           {"kernel", "kernels/methods/" + m.kernel_file},
                           {"params", params}});
        }
        std::cout << out.dump(2) << "\n";
        return;
    }
    for (const auto& m : methods()) {
        std::cout << m.name << "\n    " << m.summary << "\n    source: " << m.reference
                  << "\n    precomputed: " << (m.precompute ? m.precompute->doc : "none") << "\n";
        for (const auto& p : m.params)
            std::cout << "    --set " << p.name << "=" << p.default_value << "  [" << p.min_value
                      << ", " << p.max_value << "]" << (p.integer ? " integer" : "") << "  "
                      << p.doc << "\n";
    }
}

int render(const ReliefOptions& relief, const SceneOptions& scene_opts, const std::string& gbuffer,
           const std::string& method, const std::vector<std::string>& sets,
           const std::string& uv_out, const std::string& color_out, const std::string& error_out) {
    std::map<std::string, std::string> overrides;
    for (const auto& s : sets) parse_assignment(s, overrides);
    PassSettings settings = relief.settings();
    // Parameter errors before any file is read; resolved once, here.
    const MethodParams params = resolve_params(find_method(method), overrides);

    HeightMap map = load_height_map(relief.height_map, {relief.channel, relief.depth_map});
    if (map.clamped)
        std::cerr << "offsetmap: warning: " << map.clamped << " heights in '" << relief.height_map
                  << "' were outside [0,1] and were clamped\n";
    GBuffer gb = gbuffer.empty() ? scene_opts.make() : load_gbuffer(gbuffer);
    if (relief.light.size() == 3) gb.light.clear();  // an explicit light wins
    Image4 normals, albedo;
    if (!relief.normal_map.empty()) normals = load_normal_map(relief.normal_map, relief.flip_green);
    if (!relief.albedo.empty()) albedo = load_image4(relief.albedo);

    auto rt = Runtime::create(relief.device);
    DeviceHeightField field =
        upload(*rt, map, settings, relief.normal_map.empty() ? nullptr : &normals);
    DeviceGBuffer dg = upload(*rt, gb);
    OffsetPass pass(rt, params);
    OffsetResult result = run_offset(*rt, pass, dg, field, settings, 1);

    size_t traced_n = 0;
    for (auto f : result.flags) traced_n += traced(f);
    std::printf("%s on %s: %dx%d pixels, %zu traced, %.2f fetches/pixel, kernel %.3f ms\n",
                method.c_str(), rt->device_name().c_str(), gb.width, gb.height, traced_n,
                mean_fetches(result), result.median_kernel_ms());

    if (!uv_out.empty()) write_uv_exr(uv_out, result);
    if (!color_out.empty()) {
        ShadePass shade(rt);
        ShadeSettings ss = relief.shade_settings();
        DeviceImage dalbedo;
        if (!relief.albedo.empty()) dalbedo = upload(*rt, albedo);
        auto rgba = run_shade(*rt, shade, result, dg, field,
                              relief.albedo.empty() ? nullptr : &dalbedo, settings, ss);
        write_image(color_out, to_srgb8(gb.width, gb.height, rgba));
    }
    if (!error_out.empty()) {
        OffsetPass exact(rt, "exact");
        OffsetResult ref = run_offset(*rt, exact, dg, field, settings, 1);
        std::vector<float> err;
        ErrorStats st = uv_error(result, ref, map.width, map.height, &err);
        write_image(error_out, heat_map(gb.width, gb.height, err, 16.0f));
        std::printf("uv error vs exact (texels): mean %.4f, p95 %.4f, max %.4f, >1 texel %.2f%%\n",
                    st.mean, st.p95, st.max, 100.0 * st.wrong_share);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"offsetmap: per-pixel displacement mapping as an OpenCL pass over a G-buffer"};
    app.require_subcommand(1);

    auto* cmd_methods = app.add_subcommand("methods", "list the methods and their parameters");
    bool json = false;
    cmd_methods->add_flag("--json", json, "machine-readable output");

    auto* cmd_gbuffer = app.add_subcommand("gbuffer", "write a G-buffer EXR from a scene source");
    SceneOptions gb_scene;
    std::string gb_out;
    gb_scene.add_to(*cmd_gbuffer);
    cmd_gbuffer->add_option("-o,--output", gb_out, "output EXR file")->required();

    auto* cmd_render = app.add_subcommand("render", "run one method's offset pass (and shading)");
    ReliefOptions relief;
    SceneOptions scene;
    std::string gbuffer, method, uv_out, color_out, error_out;
    std::vector<std::string> sets;
    relief.add_to(*cmd_render, true);
    scene.add_to(*cmd_render);
    cmd_render->add_option("--method", method, "method name (see 'offsetmap methods')")->required();
    cmd_render->add_option("--set", sets, "method parameter key=value (repeatable)");
    cmd_render->add_option("--gbuffer", gbuffer, "G-buffer EXR (instead of --scene)");
    cmd_render->add_option("--uv-out", uv_out, "EXR with u v depth fetches flags");
    cmd_render->add_option("--color-out", color_out, "shaded image (PNG)");
    cmd_render->add_option("--error-out", error_out,
                           "heat map of uv error in texels against exact (PNG; log scale to 16)");

    auto* cmd_compare =
        app.add_subcommand("compare", "every method on one scene: contact sheet + table");
    ReliefOptions cmp_relief;
    SceneOptions cmp_scene;
    std::string cmp_out = "out/compare";
    int repeats = 5;
    cmp_relief.shadows = "soft";
    cmp_relief.add_to(*cmd_compare, true);
    cmp_scene.plane.width = 640;
    cmp_scene.plane.height = 360;
    cmp_scene.add_to(*cmd_compare);
    cmd_compare->add_option("-o,--out", cmp_out, "output folder")->capture_default_str();
    cmd_compare->add_option("--repeats", repeats, "timed runs per method (median reported)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();

    auto* cmd_sweep =
        app.add_subcommand("sweep", "accuracy against cost over every method's settings");
    ReliefOptions sweep_relief;
    SweepCommand sweep;
    sweep_relief.add_to(*cmd_sweep, false);
    sweep.add_to(*cmd_sweep);
    cmd_sweep->add_option("--maps", sweep.maps, "height maps (default: the sweep maps in --data)");
    cmd_sweep->add_option("--data", sweep.data_dir, "folder of the default maps")
        ->capture_default_str();
    cmd_sweep->add_flag("--quick", sweep.quick,
                        "3 maps, smaller views, 3 timed runs (about a minute)");
    cmd_sweep->add_option("--repeats", sweep.repeats, "timed runs per point")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();

    auto* cmd_failure =
        app.add_subcommand("failure-map", "error over view elevation x depth scale");
    ReliefOptions failure_relief;
    FailureCommand failure;
    failure_relief.add_to(*cmd_failure, true);
    failure.add_to(*cmd_failure);
    cmd_failure->add_option("--samples", failure.samples, "random views per cell")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();

    auto* cmd_temporal =
        app.add_subcommand("temporal", "frame-to-frame stability along a camera path");
    ReliefOptions temporal_relief;
    TemporalCommand temporal;
    temporal_relief.add_to(*cmd_temporal, true);
    temporal.add_to(*cmd_temporal);
    cmd_temporal->add_option("--frames", temporal.frames, "frames on the path")
        ->check(CLI::Range(2, 1000))
        ->capture_default_str();

    auto* cmd_demo = app.add_subcommand(
        "demo", "compare + quick sweep + failure map on the default data -> one folder");
    ReliefOptions demo_relief;
    std::string demo_out = "out/demo", demo_data = "data";
    demo_relief.shadows = "soft";
    demo_relief.add_to(*cmd_demo, false);
    cmd_demo->add_option("-o,--out", demo_out, "output folder")->capture_default_str();
    cmd_demo->add_option("--data", demo_data, "folder of the default maps")->capture_default_str();

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        if (*cmd_methods) print_methods(json);
        if (*cmd_gbuffer) save_gbuffer(gb_out, gb_scene.make());
        if (*cmd_render)
            return render(relief, scene, gbuffer, method, sets, uv_out, color_out, error_out);
        if (*cmd_compare) return run_compare(cmp_out, cmp_relief, cmp_scene, repeats);
        if (*cmd_sweep) return run_sweep_command(sweep, sweep_relief);
        if (*cmd_failure) return run_failure_command(failure, failure_relief);
        if (*cmd_temporal) return run_temporal_command(temporal, temporal_relief);
        if (*cmd_demo) {
            if (demo_relief.height_map.empty()) demo_relief.height_map = demo_data + "/rocks.png";
            SceneOptions scene;
            scene.plane.width = 640;
            scene.plane.height = 360;
            run_compare(demo_out, demo_relief, scene, 5);
            SweepCommand quick;
            quick.data_dir = demo_data;
            quick.out_dir = demo_out;
            quick.quick = true;
            run_sweep_command(quick, demo_relief);
            FailureCommand fm;
            fm.out_dir = demo_out;
            fm.samples = 128;
            run_failure_command(fm, demo_relief);
            TemporalCommand tc;
            tc.out_dir = demo_out;
            tc.frames = 12;
            return run_temporal_command(tc, demo_relief);
        }
    } catch (const offsetmap::Error& e) {
        std::cerr << "offsetmap: error: " << e.what() << "\n";
        return 1;
    } catch (const cl::Error& e) {
        std::cerr << "offsetmap: error: OpenCL call " << e.what()
                  << " failed: " << describe_cl_error(e.err()) << "\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "offsetmap: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
