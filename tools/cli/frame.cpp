// `offsetmap frame`: a rasterized deferred frame around the pass (OpenGL through EGL for the
// G-buffer, the OpenCL passes for offset and shading, the depth offset written back), and with
// --forward the forward peer: the same methods in the G-buffer pass's fragment shader.
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "frame/report.hpp"
#include "frame/request.hpp"
#include "frame/runs.hpp"
#include "frame/shadow_truth.hpp"
#include "frame/sun.hpp"
#include "frame/truth.hpp"
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
    app.add_flag("--uv-metric", uv_metric,
                 "with --curvature: the curved frames also carry the uv's metric (dP/du, dP/dv "
                 "and their rates: stretch, skew and their change across the footprint; "
                 "docs/design.md, \"The uv metric\")");
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
    app.add_option("--spot", spot,
                   "X,Y,Z,AX,AY,AZ,INNER,OUTER: a spot light at (X, Y, Z) shining along (AX, AY, "
                   "AZ), whole within INNER degrees of its axis and fading to nothing at OUTER "
                   "(< 90): the frame's light, and with --shadows map its displaced shadow map "
                   "from its perspective view (instead of --sun)");
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

int run_frame(const FrameCommand& cmd) {
    // Every option and input checked, the table and scene read: nothing renders before.
    FrameRequest request = read_frame_request(cmd);
    auto rt = Runtime::create(cmd.device);
    show_progress(*rt);
    FrameRuns runs = render_runs(request, rt);
    std::vector<std::vector<float> > errors;
    nlohmann::json doc = {{"scene", request.scene.name},
                          {"width", cmd.width},
                          {"height", cmd.height},
                          {"gl_renderer", runs.renderer->gl_renderer()},
                          {"opencl_device", rt->device_name()},
                          {"interop", runs.renderer->interop()},
                          {"covered_pixels", runs.covered},
                          {"repeats", cmd.repeats},
                          {"table", request.table_file},
                          {"modes", modes_section(request, runs, *rt, errors)}};
    Tiles tiles = write_frame_pictures(request, runs, errors);
    if (request.sun || request.spot) doc["shadow_map"] = sun_section(request, runs, tiles);
    Tiles truth_tiles;
    if (cmd.truth) {
        doc["truth"] = truth_section(request, rt, runs, truth_tiles);
        if (request.sun && doc["truth"].contains("modes"))
            doc["truth"]["shadow_mismatch"] = shadow_truth_section(request, rt, runs, truth_tiles);
    }
    const std::string d = cmd.out_dir + "/";
    tiles.insert(tiles.end(), truth_tiles.begin(), truth_tiles.end());
    write_image(d + "frame-sheet.png", contact_sheet(tiles, 2));
    if (!truth_tiles.empty()) write_image(d + "truth-sheet.png", contact_sheet(truth_tiles, 2));
    std::ofstream(d + "frame.json") << doc.dump(2) << "\n";
    const bool measured = cmd.truth && doc["truth"].contains("modes");
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
