#ifdef OFFSETMAP_HAVE_RENDERER
#include "request.hpp"

#include <cmath>
#include <filesystem>
#include <map>

#include "offsetmap/renderer/gltf.hpp"

namespace offsetmap::cli {

using namespace offsetmap::renderer;

ShadowChoice parse_shadows(const std::string& value) {
    ShadowChoice c;
    c.map = value.rfind("map", 0) == 0;
    c.march = !c.map ? value : value == "map+hard" ? "hard" : value == "map+soft" ? "soft" : "none";
    return c;
}

namespace {

// An option's comma-separated numbers, each read whole; none where one is not a number.
std::vector<double> numbers(const std::string& text) {
    std::vector<double> v;
    try {
        for (size_t at = 0; at <= text.size();) {
            const size_t comma = std::min(text.find(',', at), text.size());
            const std::string part = text.substr(at, comma - at);
            size_t used = 0;
            v.push_back(std::stod(part, &used));
            if (used != part.size()) return {};
            at = comma + 1;
        }
    } catch (const std::exception&) {
        return {};
    }
    return v;
}

}  // namespace

Sun parse_sun(const std::string& text) {
    Sun sun;
    const std::vector<double> v = numbers(text);
    if (v.size() == 2) sun.elevation = v[0], sun.azimuth = v[1];
    if (v.size() != 2 || !(sun.elevation > 0.0 && sun.elevation <= 90.0) ||
        !std::isfinite(sun.azimuth))
        throw UsageError(
            "--sun: expected ELEVATION,AZIMUTH in degrees, elevation in (0, 90], got '" + text +
            "'");
    const double e = sun.elevation * M_PI / 180.0, a = sun.azimuth * M_PI / 180.0;
    sun.toward = {float(std::cos(e) * std::cos(a)), float(std::sin(e)),
                  float(std::cos(e) * std::sin(a))};
    return sun;
}

EngineLight parse_spot(const std::string& text) {
    const std::vector<double> v = numbers(text);
    const auto finite = [&] {
        for (double x : v)
            if (!std::isfinite(x)) return false;
        return true;
    };
    if (v.size() != 8 || !finite() || !(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] > 0.0) ||
        !(v[6] >= 0.0 && v[6] <= v[7] && v[7] > 0.0 && v[7] < 90.0))
        throw UsageError(
            "--spot: expected X,Y,Z,AX,AY,AZ,INNER,OUTER: a position, an axis not zero and the "
            "cone's half-angles in degrees, 0 <= INNER <= OUTER < 90 and OUTER > 0, got '" +
            text + "'");
    EngineLight spot;
    spot.kind = LightKind::Spot;
    spot.vector = {float(v[0]), float(v[1]), float(v[2])};
    spot.axis = {float(v[3]), float(v[4]), float(v[5])};
    spot.cone_inner = float(v[6] * M_PI / 180.0);
    spot.cone_outer = float(v[7] * M_PI / 180.0);
    return spot;
}

namespace {

// --method with its --set overrides (a method for every material), or none.
MethodParams override_method(const FrameCommand& cmd) {
    if (!cmd.sets.empty() && cmd.method.empty()) throw UsageError("--set needs --method");
    if (cmd.method.empty()) return {};
    const MethodParams p = as_usage([&] {
        std::map<std::string, std::string> overrides;
        for (const std::string& s : cmd.sets) parse_assignment(s, overrides);
        return resolve_params(find_method(cmd.method), overrides);
    });
    if (cmd.forward)
        if (const std::string why = forward_method_unsupported(p); !why.empty())
            throw UsageError("--forward: " + why);
    return p;
}

// The options that need no file: the scene's kind, the camera, the sun and the shadows.
void check_options(const FrameCommand& cmd, FrameRequest& r) {
    if (!is_gltf_path(cmd.scene) && cmd.scene != "room")
        throw UsageError("--scene: '" + cmd.scene +
                         "' is neither the built-in 'room' nor a .gltf or .glb file");
    if (!cmd.camera.empty()) as_usage([&] { return parse_camera(cmd.camera); });
    if (!cmd.sun.empty()) r.sun = parse_sun(cmd.sun);
    if (!cmd.spot.empty()) r.spot = parse_spot(cmd.spot);
    if (r.sun && r.spot) throw UsageError("--spot: the frame has one light; --sun is another");
    r.shadows = parse_shadows(cmd.shadows);
    if (r.shadows.map && !r.sun && !r.spot)
        throw UsageError("--shadows " + cmd.shadows +
                         ": a shadow map needs the sun (--sun) or a spot (--spot)");
    r.shading.shadow = shadow_mode(r.shadows.march);
    if (r.shadows.map) {
        r.shadow_map = ShadowMapSettings();
        r.shadow_map->size = cmd.shadow_size;
    }
}

// Each entry's method (`auto` none until chosen), every refusal of the forward peer and of the
// layer behind named before a map is read.
void resolve_methods(const FrameCommand& cmd, const std::vector<MaterialSpec>& specs,
                     FrameRequest& r) {
    const MethodParams forced = override_method(cmd);
    for (const MaterialSpec& s : specs) {
        r.any_triplanar |= s.triplanar.enabled;
        if (cmd.layers == 2 && s.triplanar.enabled)
            throw UsageError("--layers 2: the layer behind does not trace triplanar materials; " +
                             r.table_file + " makes material " + std::to_string(s.id) + " (" +
                             s.name + ") one");
        if (forced.method) {
            r.methods.push_back(forced);
        } else if (s.method == "auto") {
            r.auto_slots.push_back(r.methods.size());
            r.methods.push_back(resolve_params(find_method("none"), {}));
        } else {
            r.methods.push_back(resolve_params(find_method(s.method), s.params));
            if (cmd.forward)
                if (const std::string why = forward_unsupported(s, r.methods.back()); !why.empty())
                    throw Error(why);
        }
    }
}

// The room's or the glTF file's scene, with --camera's view and --sun's light.
Scene read_scene(const FrameCommand& cmd, const std::vector<MaterialSpec>& specs,
                 const std::string& data_dir, const FrameRequest& r) {
    Scene scene = is_gltf_path(cmd.scene) ? load_gltf_scene(cmd.scene, specs, r.table_file)
                                          : builtin_room(data_dir);
    if (!cmd.camera.empty()) {
        // The eye, target and field of view from --camera; the scene's depth range is kept.
        const Camera camera = parse_camera(cmd.camera);
        scene.camera.eye = camera.eye;
        scene.camera.target = camera.target;
        scene.camera.fov_y_deg = camera.fov_y_deg;
    }
    // The sun lights the frame it casts shadows in.
    if (r.sun) scene.light = {LightKind::Directional, r.sun->toward};
    if (r.spot) scene.light = *r.spot;
    for (const Mesh& m : scene.meshes) {
        bool known = m.material == 0;
        for (const MaterialSpec& s : specs) known |= s.id == m.material;
        if (!known)
            throw Error("mesh '" + m.name + "' has material id " + std::to_string(m.material) +
                        ", which " + r.table_file + " does not list");
    }
    if (cmd.forward && scene.camera.orthographic)
        throw Error(cmd.scene +
                    ": the forward peer (--forward) draws perspective views only; the "
                    "scene's camera is orthographic");
    return scene;
}

}  // namespace

FrameRequest read_frame_request(const FrameCommand& cmd) {
    FrameRequest r;
    r.cmd = &cmd;
    check_options(cmd, r);
    // The room's maps and table (a glTF scene's table lies beside it).
    const bool gltf = is_gltf_path(cmd.scene);
    const std::string data_dir =
        gltf ? "" : (cmd.data_dir.empty() ? default_data_dir() : cmd.data_dir);
    r.table_file = cmd.materials;
    if (r.table_file.empty())
        r.table_file = gltf ? std::filesystem::path(cmd.scene).replace_extension(".json").string()
                            : data_dir + "/room.json";
    const std::vector<MaterialSpec> specs = read_material_table(r.table_file);
    resolve_methods(cmd, specs, r);
    r.scene = read_scene(cmd, specs, data_dir, r);
    r.table = load_materials(specs);
    std::error_code ec;
    std::filesystem::create_directories(cmd.out_dir, ec);
    if (ec) throw Error("cannot create output folder '" + cmd.out_dir + "': " + ec.message());
    return r;
}

}  // namespace offsetmap::cli
#endif
