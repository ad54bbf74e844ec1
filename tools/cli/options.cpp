// The option groups the subcommands share, and the checks that refuse ignored or conflicting ones.
#include <algorithm>

#include "cli.hpp"

namespace offsetmap::cli {

void ReliefOptions::add_to(CLI::App& app, MapOption map, bool scale) {
    if (map != MapOption::None) {
        auto* hm =
            app.add_option("--height-map", height_map, "height map image (PNG, TIFF, EXR, ...)");
        if (map == MapOption::Required) hm->required();
        app.add_flag("--depth-map", depth_map, "the file stores depth (white = deep)");
    }
    app.add_option("--channel", channel, "channel of the height map to use")
        ->check(CLI::Range(0, 1023));
    scale_ = app.add_option("--scale", pass.scale, "depth scale s in uv units");
    if (scale) scale_->capture_default_str();
    scale_swept_ = !scale;
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
    app.add_option("--height-storage", height_storage,
                   "heights as float, unorm16 (rounded to 1/65535, faster reads), or auto (unorm16 "
                   "where that loses nothing: 8- and 16-bit maps)")
        ->check(CLI::IsMember({"auto", "float", "unorm16"}))
        ->capture_default_str();
    app.add_option("--device", device, "OpenCL platform/device name substring ($OFFSETMAP_DEVICE)");
}

PassSettings ReliefOptions::settings() const {
    if (scale_swept_ && scale_->count())
        throw UsageError("--scale does not apply here: this command sweeps the depth scale itself");
    PassSettings s = pass;
    s.address = address == "clamp" ? AddressMode::Clamp : AddressMode::Wrap;
    if (lod_fade_texels.size() == 2) {
        s.lod.fade_texels_lo = lod_fade_texels[0];
        s.lod.fade_texels_hi = lod_fade_texels[1];
    }
    s.heights = height_storage == "float"     ? HeightStorage::Float
                : height_storage == "unorm16" ? HeightStorage::Unorm16
                                              : HeightStorage::Auto;
    s.grazing = grazing == "limit" ? GrazingPolicy::Limit
                : grazing == "cap" ? GrazingPolicy::Cap
                                   : GrazingPolicy::Clamp;
    as_usage([&] { validate(s); });
    return s;
}

void ShadingOptions::add_to(CLI::App& app) {
    options_ = {
        app.add_option("--normal-map", normal_map,
                       "tangent-space normal map (default: derived from heights)"),
        app.add_flag("--flip-green", flip_green, "normal map authored DirectX-style (green = -y)"),
        app.add_option("--albedo", albedo, "albedo image (default: a neutral checker)"),
        app.add_option("--light", light,
                       "tangent-space light direction x y z (replaces the G-buffer's L)")
            ->expected(3),
        app.add_option("--shadows", shadows, "relief self-shadows in the shaded image")
            ->check(CLI::IsMember({"none", "hard", "soft"}))
            ->capture_default_str(),
        app.add_option("--shadow-steps", shade.shadow_steps, "samples along the light ray")
            ->check(CLI::Range(1, 256))
            ->capture_default_str(),
        app.add_option("--light-size", shade.light_size_deg,
                       "soft shadows: light's angular size (deg)")
            ->check(CLI::Range(0.01, 90.0))
            ->capture_default_str(),
    };
}

ShadeSettings ShadingOptions::shade_settings() const {
    ShadeSettings s = shade;
    if (light.size() == 3) std::copy(light.begin(), light.end(), s.light);
    s.shadow = shadow_mode(shadows);
    return s;
}

ShadowMode shadow_mode(const std::string& name) {
    return name == "hard" ? ShadowMode::Hard : name == "soft" ? ShadowMode::Soft : ShadowMode::None;
}

ShadingOptions::Files ShadingOptions::read_files() const {
    Files files;
    if (!normal_map.empty()) files.normals = load_normal_map(normal_map, flip_green);
    if (!albedo.empty()) files.albedo = load_image4(albedo);
    return files;
}

const DeviceImage* ShadingOptions::Files::upload_albedo(Runtime& runtime,
                                                        DeviceImage& storage) const {
    if (!albedo.width) return nullptr;
    storage = upload(runtime, albedo);
    return &storage;
}

std::string ShadingOptions::first_given() const {
    for (const auto* o : options_)
        if (o->count()) return o->get_name();
    return "";
}

void SceneOptions::add_to(CLI::App& app, bool file) {
    const std::vector<std::string> plane_random = {"plane", "random"}, plane_only = {"plane"},
                                   sweep_only = {"sweep"}, sweep_random = {"sweep", "random"},
                                   random_only = {"random"};
    auto known = [&](CLI::Option* o, const std::vector<std::string>& scenes) {
        options_.push_back({o, scenes});
        return o;
    };
    const std::vector<std::string> all = {"plane", "sweep", "random"};
    known(app.add_option("--scene", scene, "G-buffer source")
              ->check(CLI::IsMember(all))
              ->capture_default_str(),
          all);
    known(app.add_option("--width", width, "image width (plane, random)")
              ->check(CLI::Range(1, kMaxGBufferSide)),
          plane_random);
    known(app.add_option("--height", height, "image height (plane, random)")
              ->check(CLI::Range(1, kMaxGBufferSide)),
          plane_random);
    known(app.add_option("--camera-height", plane.camera_height, "plane: camera height in tiles")
              ->check(CLI::Range(1e-6, 1e6))
              ->capture_default_str(),
          plane_only);
    known(app.add_option("--pitch", plane.pitch_deg, "plane: look-down angle in degrees")
              ->check(CLI::Range(-90.0, 90.0))
              ->capture_default_str(),
          plane_only);
    known(app.add_option("--yaw", plane.yaw_deg, "plane: heading in degrees")
              ->check(CLI::Range(-360.0, 360.0))
              ->capture_default_str(),
          plane_only);
    known(app.add_option("--fov", plane.fov_deg, "plane: vertical field of view in degrees")
              ->check(CLI::Range(1.0, 179.0))
              ->capture_default_str(),
          plane_only);
    known(app.add_option("--elevations", sweep.elevations, "sweep: elevation rows")
              ->check(CLI::Range(1, 1024))
              ->capture_default_str(),
          sweep_only);
    known(app.add_option("--azimuths", sweep.azimuths, "sweep: azimuth columns")
              ->check(CLI::Range(1, 1024))
              ->capture_default_str(),
          sweep_only);
    known(app.add_option("--patch", sweep.patch, "sweep: pixels per patch side")
              ->check(CLI::Range(1, 1024))
              ->capture_default_str(),
          sweep_only);
    known(app.add_option("--seed", random.seed, "random: seed")->capture_default_str(),
          random_only);
    known(app.add_option("--elev-min", random.min_elevation_deg,
                         "sweep/random: lowest view elevation")
              ->check(CLI::Range(0.0, 90.0))
              ->capture_default_str(),
          sweep_random);
    known(app.add_option("--elev-max", random.max_elevation_deg,
                         "sweep/random: highest view elevation")
              ->check(CLI::Range(0.0, 90.0))
              ->capture_default_str(),
          sweep_random);
    if (file) app.add_option("--gbuffer", gbuffer, "G-buffer EXR (instead of --scene)");
}

void SceneOptions::check() const {
    for (const auto& k : options_) {
        if (!k.option->count()) continue;
        const std::string name = k.option->get_name();
        if (!gbuffer.empty())
            throw UsageError(name +
                             " sets up a built-in scene; it cannot be used with --gbuffer, " +
                             "whose file is the G-buffer");
        if (std::find(k.scenes.begin(), k.scenes.end(), scene) == k.scenes.end()) {
            std::string list;
            for (const auto& s : k.scenes) list += (list.empty() ? "" : " or ") + s;
            throw UsageError(name + " applies to --scene " + list + ", not to --scene " + scene);
        }
    }
    if (random.min_elevation_deg > random.max_elevation_deg)
        throw UsageError("--elev-min (" + std::to_string(random.min_elevation_deg) +
                         ") is above --elev-max (" + std::to_string(random.max_elevation_deg) +
                         ")");
}

GBuffer SceneOptions::make() const {
    if (!gbuffer.empty()) return load_gbuffer(gbuffer);
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

std::string SceneOptions::describe() const {
    if (!gbuffer.empty()) return "G-buffer '" + gbuffer + "'";
    return scene + " scene";
}

}  // namespace offsetmap::cli
