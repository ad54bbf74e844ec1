// `offsetmap frame`: a rasterized deferred frame around the pass (OpenGL through EGL for the
// G-buffer, the OpenCL passes for offset and shading, the depth offset written back), and with
// --forward the forward peer: the same methods in the G-buffer pass's fragment shader.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/gltf.hpp"
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
    app.add_option("-o,--out", out_dir, "output folder")->capture_default_str();
    app.add_option("--repeats", repeats, "timed frames per mode (median reported)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    app.add_option("--shadows", shadows, "self-shadows of the relief in the shading")
        ->check(CLI::IsMember({"none", "hard", "soft"}))
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

nlohmann::json pass_json(const FrameRun& r) {
    return {{"gbuffer_ms", r.ms.gbuffer},
            {"to_device_ms", r.ms.to_device},
            {"reconstruct_ms", r.ms.reconstruct},
            {"offset_ms", r.ms.offset},
            {"shade_ms", r.ms.shade},
            {"to_gl_ms", r.ms.to_gl},
            {"depth_offset_ms", r.ms.depth_offset},
            {"total_ms", r.ms.total}};
}

// Depth offset as a picture: grey where unchanged, darker where pushed away from the eye.
Rgb8 depth_change_image(int w, int h, const std::vector<float>& before,
                        const std::vector<float>& after) {
    std::vector<float> change(before.size());
    for (size_t k = 0; k < change.size(); ++k)
        change[k] = before[k] >= 1.0f ? std::nanf("") : std::abs(after[k] - before[k]) * 1e4f;
    return heat_map(w, h, change, 16.0f);
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
    shading.shadow = shadow_mode(cmd.shadows);
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
    const FrameRun deferred = renderer.render(FrameMode::Deferred, false, cmd.repeats);
    const int w = cmd.width, h = cmd.height;
    const OffsetResult exact = renderer.exact();
    const GBuffer gb = renderer.explicit_gbuffer();  // the deferred frame's, exact's
    const EngineScene engine = renderer.gbuffer();   // the deferred frame's, for the files
    const std::vector<float>& deferred_uv = engine.uv;
    const size_t covered = renderer.covered_pixels();

    std::vector<FrameRun> runs = {deferred};
    if (cmd.forward) {
        for (bool prepass : {false, true}) {
            runs.push_back(renderer.render(FrameMode::Forward, prepass, cmd.repeats));
            // Where the forward shader dropped a fragment (the tile mask) the pixel shows the
            // surface behind it, or none after a pre-pass: errors are compared only where both
            // frames show the same surface (the same uv in their G-buffers).
            const std::vector<float>& uv = renderer.gbuffer().uv;
            for (size_t k = 0; k < gb.pixels(); ++k)
                if (std::memcmp(&uv[2 * k], &deferred_uv[2 * k], 2 * sizeof(float)) != 0)
                    runs.back().offset.flags[k] |= OM_FLAG_EMPTY;
        }
    }
    std::printf("frame: %s scene %dx%d, %zu materials; GL: %s; OpenCL: %s; %s\n",
                scene.name.c_str(), w, h, table.size(), renderer.gl_renderer().c_str(),
                rt->device_name().c_str(), renderer.interop().c_str());
    std::printf("%-22s %9s %9s %9s %9s %9s %9s %9s %9s %10s\n", "mode", "G-buffer", "to CL",
                "reconstr", "offset", "shade", "depth off", "to GL", "total", "frag/px");
    nlohmann::json modes = nlohmann::json::array();
    std::vector<std::vector<float> > errors;
    for (const FrameRun& r : runs) {
        const std::string name = r.mode == FrameMode::Deferred
                                     ? "deferred"
                                     : (r.prepass ? "forward + pre-pass" : "forward");
        const double overdraw = covered ? double(r.shaded_fragments) / double(covered) : 0.0;
        std::printf("%-22s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %10.2f\n", name.c_str(),
                    r.ms.gbuffer, r.ms.to_device, r.ms.reconstruct, r.ms.offset, r.ms.shade,
                    r.ms.depth_offset, r.ms.to_gl, r.ms.total, overdraw);
        std::vector<float> err;
        const std::vector<MaterialError> stats = material_errors(gb, r.offset, exact, table, &err);
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
        modes.push_back({{"mode", name},
                         {"passes", pass_json(r)},
                         {"offset_kernel_ms", r.offset_kernel_ms},
                         {"shaded_fragments", r.shaded_fragments},
                         {"shaded_fragments_per_covered_pixel", overdraw},
                         {"materials", mats}});
    }
    std::printf("%4s %-10s %-10s %8s", "id", "material", "method", "pixels");
    for (const FrameRun& r : runs)
        std::printf("  %s", r.mode == FrameMode::Deferred ? "deferred mean/p95"
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
    write_image(d + "final.png", to_srgb8(w, h, deferred.color));
    save_engine_gbuffer(d + "gbuffer.exr", engine);
    write_depth_exr(d + "depth-before.exr", w, h, engine.depth);
    write_depth_exr(d + "depth-after.exr", w, h, deferred.depth_after);
    std::vector<std::pair<std::string, Rgb8> > tiles = {
        {"deferred frame (offset pass on the OpenCL device)", to_srgb8(w, h, deferred.color)},
        {"uv error vs exact (log, white = 16 texels)", heat_map(w, h, errors[0], 16.0f)},
        {"depth offset written back (log, white = 16e-4)",
         depth_change_image(w, h, engine.depth, deferred.depth_after)}};
    if (cmd.forward) {
        write_image(d + "final-forward.png", to_srgb8(w, h, runs[1].color));
        tiles.push_back(
            {"forward frame (the methods in the fragment shader)", to_srgb8(w, h, runs[1].color)});
        tiles.push_back({"forward uv error vs exact", heat_map(w, h, errors[1], 16.0f)});
    }
    write_image(d + "frame-sheet.png", contact_sheet(tiles, 2));
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
    std::ofstream(d + "frame.json") << doc.dump(2) << "\n";
    std::printf(
        "wrote %s{final%s.png,frame-sheet.png,gbuffer.exr,depth-before.exr,"
        "depth-after.exr,frame.json}\n",
        d.c_str(), cmd.forward ? ",final-forward" : "");
    return 0;
}

#endif

}  // namespace offsetmap::cli
