// offsetmap: command-line front end (methods, gbuffer, render, demo).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <new>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "om_shared.h"

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
                                  {"at_most", p.at_most},
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
                      << ", " << p.max_value << "]" << (p.integer ? " integer" : "")
                      << (p.at_most.empty() ? "" : ", <= " + p.at_most) << "  " << p.doc << "\n";
    }
}

// Each OpenCL device with what the passes would do there: its type, the pixels a work-item of the
// lane methods takes, heights through images or buffers; the default choice marked.
void print_devices() {
    const std::vector<DeviceEntry> all = list_devices();
    const char* env = std::getenv("OFFSETMAP_DEVICE");
    const int chosen = choose_device(all, env ? env : "");
    if (all.empty()) std::cout << "no OpenCL platform\n";
    for (size_t k = 0; k < all.size(); ++k) {
        const DeviceEntry& e = all[k];
        if (!e.device()) {
            std::cout << "  " << e.name << ": no devices\n";
            continue;
        }
        const cl_device_type t = e.device.getInfo<CL_DEVICE_TYPE>();
        const std::string type = (t & CL_DEVICE_TYPE_GPU)           ? "GPU"
                                 : (t & CL_DEVICE_TYPE_CPU)         ? "CPU"
                                 : (t & CL_DEVICE_TYPE_ACCELERATOR) ? "accelerator"
                                                                    : "other";
        const int lanes = Runtime::default_lanes(e.device);
        std::string version = e.device.getInfo<CL_DEVICE_VERSION>();
        version.erase(version.find_last_not_of(" \t\r\n") + 1);
        std::cout << (static_cast<int>(k) == chosen ? "* " : "  ") << e.name << ": " << type << ", "
                  << version << ", " << e.device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>()
                  << " compute units; " << lanes << (lanes == 1 ? " pixel" : " pixels")
                  << " a work-item, heights from "
                  << (Runtime::default_images(e.device) ? "images" : "buffers")
                  << (e.device.getInfo<CL_DEVICE_IMAGE_SUPPORT>() ? "" : " (no image support)")
                  << "\n";
    }
    std::cout << "(* the default choice"
              << (env && *env ? std::string(", $OFFSETMAP_DEVICE=") + env : std::string()) +
                     "; OFFSETMAP_LANES and OFFSETMAP_IMAGES override lanes and images)\n";
}

struct RenderRequest {
    std::string method;
    std::vector<std::string> sets;
    std::string uv_out, color_out, error_out;
};

int render(const ReliefOptions& relief, const ShadingOptions& shading, const SceneOptions& scene,
           const RenderRequest& req) {
    // Every option checked before any file is read.
    scene.check();
    const PassSettings settings = relief.settings();
    const MethodParams params = as_usage([&] {
        std::map<std::string, std::string> overrides;
        for (const auto& s : req.sets) parse_assignment(s, overrides);
        return resolve_params(find_method(req.method), overrides);
    });
    if (req.color_out.empty() && !shading.first_given().empty())
        throw UsageError(shading.first_given() +
                         " changes only the shaded image: add --color-out FILE");

    HeightMap map = load_height_map(relief.height_map, relief.load_options());
    if (map.clamped)
        std::cerr << "offsetmap: warning: " << map.clamped << " heights in '" << relief.height_map
                  << "' were outside [0,1] and were clamped\n";
    GBuffer gb = scene.make();
    if (shading.light.size() == 3) gb.light.clear();  // an explicit light wins
    const ShadingOptions::Files files = shading.read_files();

    auto rt = Runtime::create(relief.device);
    show_progress(*rt);
    DeviceHeightField field = upload(*rt, map, settings, files.normal_map());
    DeviceGBuffer dg = upload(*rt, gb);
    OffsetPass pass(rt, params);
    OffsetResult result = run_offset(*rt, pass, dg, field, settings, 1);

    const size_t traced_n = traced_pixels(result);
    if (traced_n == 0)
        std::printf(
            "%s on %s: %dx%d pixels, none traced (every pixel is empty, back-facing or "
            "invalid), %s\n",
            req.method.c_str(), rt->device_name().c_str(), gb.width, gb.height,
            kernel_time_text(result.median_kernel_ms()).c_str());
    else
        std::printf("%s on %s: %dx%d pixels, %zu traced, %.2f fetches/pixel, %s, %s heights\n",
                    req.method.c_str(), rt->device_name().c_str(), gb.width, gb.height, traced_n,
                    mean_fetches(result), kernel_time_text(result.median_kernel_ms()).c_str(),
                    field.packed ? "unorm16" : "float");

    if (!req.uv_out.empty()) write_uv_exr(req.uv_out, result);
    if (!req.color_out.empty()) {
        ShadePass shade(rt);
        ShadeSettings ss = shading.shade_settings();
        DeviceImage dalbedo;
        auto rgba = run_shade(*rt, shade, result, dg, field, files.upload_albedo(*rt, dalbedo),
                              settings, ss);
        write_image(req.color_out, to_srgb8(gb.width, gb.height, rgba));
    }
    if (!req.error_out.empty()) {
        OffsetPass exact(rt, "exact");
        OffsetResult ref = run_offset(*rt, exact, dg, field, settings, 1);
        std::vector<float> err;
        ErrorStats st = uv_error(result, ref, map.width, map.height, &err);
        write_image(req.error_out, heat_map(gb.width, gb.height, err, 16.0f));
        if (st.count == 0)
            std::printf("uv error vs exact: no pixel traced by both, nothing to compare\n");
        else
            std::printf(
                "uv error vs exact (texels): mean %.4f, p95 %.4f, max %.4f, >1 texel %.2f%%\n",
                st.mean, st.p95, st.max, 100.0 * st.wrong_share);
    }
    return 0;
}

// Levenshtein distance, for "did you mean".
size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] != b[j - 1])});
            diag = up;
        }
    }
    return row[b.size()];
}

// "" when argv names a command (or asks for help); else the one-line complaint.
std::string check_command(const CLI::App& app, int argc, char** argv) {
    std::string names, nearest;
    size_t best = 3;  // suggest only close names
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
        names += (names.empty() ? "" : ", ") + sub->get_name();
        if (argc > 1) {
            size_t d = edit_distance(argv[1], sub->get_name());
            if (d < best) best = d, nearest = sub->get_name();
        }
    }
    if (argc < 2) return "no command given; the commands are: " + names;
    const std::string first = argv[1];
    if (!first.empty() && first[0] == '-') return "";
    for (const auto* sub : app.get_subcommands([](const CLI::App*) { return true; }))
        if (sub->get_name() == first) return "";
    return "unknown command '" + first + "'" +
           (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
           "; the commands are: " + names;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"offsetmap: per-pixel displacement mapping as an OpenCL pass over a G-buffer"};
    app.require_subcommand(1);

    auto* cmd_methods = app.add_subcommand("methods", "list the methods and their parameters");
    bool json = false;
    cmd_methods->add_flag("--json", json, "machine-readable output");

    auto* cmd_devices = app.add_subcommand(
        "devices", "list the OpenCL devices: type, lanes and image or buffer path the passes use");

    auto* cmd_gbuffer = app.add_subcommand("gbuffer", "write a G-buffer EXR from a scene source");
    SceneOptions gb_scene;
    std::string gb_out;
    gb_scene.add_to(*cmd_gbuffer);
    cmd_gbuffer->add_option("-o,--output", gb_out, "output EXR file")->required();
    std::vector<int> gb_ids;
    cmd_gbuffer
        ->add_option("--material-ids", gb_ids,
                     "write a material channel: each uv tile one of these ids (0: no relief)")
        ->check(CLI::Range(0, kMaxMaterialId));
    // The engine form: depth, camera, tangent frame and uv, as an engine writes its G-buffer.
    std::string gb_depth;
    cmd_gbuffer
        ->add_option("--engine-form", gb_depth,
                     "write the plane scene in the engine form (depth, camera, frame, uv) with "
                     "this depth convention; render reconstructs V from it")
        ->check(CLI::IsMember({"gl", "zero-one", "reversed"}));

    auto* cmd_render = app.add_subcommand("render", "run one method's offset pass (and shading)");
    ReliefOptions relief;
    ShadingOptions shading;
    SceneOptions scene;
    RenderRequest req;
    MaterialsJob materials;
    relief.add_to(*cmd_render, MapOption::Optional);
    shading.add_to(*cmd_render);
    scene.add_to(*cmd_render, true);
    cmd_render->add_option("--method", req.method,
                           "method name (see 'offsetmap methods'); required without --materials");
    cmd_render->add_option("--materials", materials.table,
                           "material table (JSON): per material id its map, settings and method "
                           "(or auto by error budget); the G-buffer's ids pick them");
    cmd_render->add_flag("--explain", materials.explain,
                         "--materials: each material's method, its error and cost, the "
                         "runner-up");
    cmd_render->add_flag("--compare-single", materials.compare_single,
                         "--materials: also run each method at each setting for the whole frame "
                         "and report the cheapest one at the table's worst-material p95 error");
    cmd_render
        ->add_option("--tile-rows", materials.tile_rows,
                     "--materials: tile height (tiles are 16 pixels wide)")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    cmd_render->add_option("--report", materials.out_dir,
                           "--materials: write materials-frame.png, materials-sheet.png (frame, "
                           "ids, method per pixel, error) and materials.json here; implies "
                           "--compare-single");
    cmd_render->add_option("--ids-out", materials.ids_out,
                           "--materials: the material ids as a picture (PNG)");
    cmd_render->add_option("--set", req.sets, "method parameter key=value (repeatable)");
    cmd_render->add_option("--uv-out", req.uv_out, "EXR with u v depth fetches flags");
    cmd_render->add_option("--color-out", req.color_out, "shaded image (PNG)");
    cmd_render->add_option("--error-out", req.error_out,
                           "heat map of uv error in texels against exact (PNG; log scale to 16)");

    auto* cmd_compare =
        app.add_subcommand("compare", "every method on one scene: contact sheet + table");
    ReliefOptions cmp_relief;
    ShadingOptions cmp_shading;
    SceneOptions cmp_scene;
    std::string cmp_out = "out/compare";
    int repeats = 5;
    cmp_shading.shadows = "soft";
    cmp_relief.add_to(*cmd_compare, MapOption::Required);
    cmp_shading.add_to(*cmd_compare);
    cmp_scene.plane.width = 640;
    cmp_scene.plane.height = 360;
    cmp_scene.add_to(*cmd_compare, true);
    cmd_compare->add_option("-o,--out", cmp_out, "output folder")->capture_default_str();
    cmd_compare->add_option("--repeats", repeats, "timed runs per method (median reported)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();

    auto* cmd_sweep =
        app.add_subcommand("sweep", "accuracy against cost over every method's settings");
    ReliefOptions sweep_relief;
    SweepCommand sweep;
    sweep_relief.add_to(*cmd_sweep, MapOption::None);
    sweep.add_to(*cmd_sweep);
    cmd_sweep->add_option("--maps", sweep.maps, "height maps (default: the sweep maps in --data)");
    cmd_sweep->add_option("--data", sweep.data_dir,
                          "folder of the default maps (default: the data/ found beside the "
                          "program)");
    cmd_sweep->add_option("--gbuffer", sweep.gbuffer,
                          "G-buffer EXR: the one view set (default: a camera and random views)");
    cmd_sweep->add_option("--materials", sweep.materials,
                          "material table (JSON): its frame on the camera view as one more case "
                          "(map 'materials'), every method for all materials and the table's own");
    cmd_sweep->add_flag("--quick", sweep.quick,
                        "3 maps, smaller views, 3 timed runs (about a minute)");
    cmd_sweep->add_option("--repeats", sweep.repeats, "timed runs per point")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();

    auto* cmd_failure =
        app.add_subcommand("failure-map", "error over view elevation x depth scale");
    ReliefOptions failure_relief;
    FailureCommand failure;
    failure_relief.add_to(*cmd_failure, MapOption::Required, false);
    failure.add_to(*cmd_failure);
    cmd_failure
        ->add_option("--samples", failure.samples, "views per cell (at most, with --gbuffer)")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    cmd_failure->add_option("--gbuffer", failure.gbuffer,
                            "a G-buffer file (e.g. offsetmap frame's gbuffer.exr): its pixels' "
                            "views, binned by elevation, instead of random ones");

    auto* cmd_temporal =
        app.add_subcommand("temporal", "frame-to-frame stability along a camera path");
    ReliefOptions temporal_relief;
    TemporalCommand temporal;
    temporal_relief.add_to(*cmd_temporal, MapOption::Required);
    temporal.add_to(*cmd_temporal);
    cmd_temporal->add_option("--frames", temporal.frames, "frames on the path")
        ->check(CLI::Range(2, 1000))
        ->capture_default_str();

    auto* cmd_frame = app.add_subcommand(
        "frame",
        "a rasterized deferred frame (OpenGL G-buffer) around the pass; --forward: the "
        "fragment-shader peer");
    FrameCommand frame;
    frame.add_to(*cmd_frame);

    auto* cmd_demo = app.add_subcommand(
        "demo",
        "compare + quick sweep + failure map + material frame on the default data, then the "
        "rendered room (frame/) and the error on its views (rendered/) -> one folder");
    ReliefOptions demo_relief;
    ShadingOptions demo_shading;
    std::string demo_out = "out/demo", demo_data;
    demo_shading.shadows = "soft";
    demo_relief.add_to(*cmd_demo, MapOption::Optional);
    demo_shading.add_to(*cmd_demo);
    cmd_demo->add_option("-o,--out", demo_out, "output folder")->capture_default_str();
    cmd_demo->add_option("--data", demo_data,
                         "folder of the default maps (default: the data/ found beside the "
                         "program)");

    // Usage errors exit 2 with one line; the library's own errors exit 1 (docs/conventions.md, "Exit codes").
    auto fail = [](int code, const std::string& message) {
        std::cerr << "offsetmap: error: " << message << "\n";
        return code;
    };
    if (std::string bad = check_command(app, argc, argv); !bad.empty())
        return fail(kExitUsage, bad);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
        return fail(kExitUsage,
                    std::string(e.what()) + " (see 'offsetmap " + argv[1] + " --help')");
    }
    // A bad file gives one message, the Error's, not also the decoder's own line.
    quiet_decoders(true);
    try {
        if (*cmd_methods) print_methods(json);
        if (*cmd_devices) print_devices();
        if (*cmd_gbuffer) {
            gb_scene.check();
            if (gb_depth.empty()) {
                GBuffer gb = gb_scene.make();
                if (!gb_ids.empty()) lay_out_materials(gb, gb_ids);
                save_gbuffer(gb_out, gb);
            } else {
                if (gb_scene.scene != "plane")
                    throw UsageError("--engine-form writes the plane scene, not --scene " +
                                     gb_scene.scene);
                PlaneScene p = gb_scene.plane;
                if (gb_scene.width) p.width = gb_scene.width;
                if (gb_scene.height) p.height = gb_scene.height;
                const DepthConvention d = gb_depth == "gl"         ? DepthConvention::GL
                                          : gb_depth == "zero-one" ? DepthConvention::ZeroToOne
                                                                   : DepthConvention::Reversed;
                EngineScene e = make_engine_scene(p, d);
                if (!gb_ids.empty()) {  // laid out by each pixel's uv, as the explicit form's
                    GBuffer at;
                    at.resize(e.width, e.height, false, false);
                    for (size_t k = 0; k < at.pixels(); ++k)
                        at.uv[k] = {{e.uv[2 * k], e.uv[2 * k + 1]}};
                    lay_out_materials(at, gb_ids);
                    e.material = at.material;
                }
                save_engine_gbuffer(gb_out, e);
            }
        }
        if (*cmd_frame) return run_frame(frame);
        if (*cmd_render) {
            if (materials.table.empty()) {
                if (relief.height_map.empty())
                    throw UsageError("render needs --height-map (or --materials FILE.json)");
                if (req.method.empty())
                    throw UsageError("render needs --method (or --materials FILE.json)");
                for (const auto& [given, name] :
                     {std::pair{materials.explain, "--explain"},
                      {materials.compare_single, "--compare-single"},
                      {!materials.ids_out.empty(), "--ids-out"},
                      {!materials.out_dir.empty(), "--report"},
                      {cmd_render->count("--tile-rows") > 0, "--tile-rows"}})
                    if (given) throw UsageError(std::string(name) + " applies to --materials");
                return render(relief, shading, scene, req);
            }
            if (!req.method.empty() || !req.sets.empty())
                throw UsageError(std::string(req.method.empty() ? "--set" : "--method") +
                                 " belongs to one material: with --materials each entry of the "
                                 "table names its method and params");
            materials.uv_out = req.uv_out;
            materials.color_out = req.color_out;
            materials.error_out = req.error_out;
            return run_materials_job(materials, relief, shading, scene);
        }
        if (*cmd_compare) return run_compare(cmp_out, cmp_relief, cmp_shading, cmp_scene, repeats);
        if (*cmd_sweep) return run_sweep_command(sweep, sweep_relief);
        if (*cmd_failure) return run_failure_command(failure, failure_relief);
        if (*cmd_temporal) return run_temporal_command(temporal, temporal_relief);
        if (*cmd_demo) {
            if (demo_data.empty()) demo_data = default_data_dir();
            if (demo_relief.height_map.empty()) demo_relief.height_map = demo_data + "/rocks.png";
            SceneOptions scene;
            scene.plane.width = 640;
            scene.plane.height = 360;
            run_compare(demo_out, demo_relief, demo_shading, scene, 5);
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
            run_temporal_command(tc, demo_relief);
            // A frame of four materials (data/materials.json), three of them by error budget.
            MaterialsJob mj;
            mj.table = demo_data + "/materials.json";
            mj.out_dir = demo_out;
            mj.explain = true;
            ReliefOptions mrelief;
            mrelief.device = demo_relief.device;
            ShadingOptions mshading;
            mshading.shadows = "soft";
            SceneOptions mscene;
            mscene.plane.width = 640;
            mscene.plane.height = 360;
            mscene.plane.camera_height = 0.9;  // high enough to see a dozen material tiles
            mscene.plane.pitch_deg = 28.0;
            run_materials_job(mj, mrelief, mshading, mscene);
            // The rasterized room around the pass, deferred and forward (frame/).
            FrameCommand fc;
            fc.data_dir = demo_data;
            fc.out_dir = demo_out + "/frame";
            fc.width = 960;
            fc.height = 540;
            fc.forward = true;
            fc.shadows = "hard";
            fc.device = demo_relief.device;
            try {
                run_frame(fc);
                // Error on real geometry (rendered/): the failure map over a rendered frame's
                // views, and a sweep on its G-buffer (the bricks everywhere, then the room's own
                // materials), on a frame small enough to sweep.
                FrameCommand small = fc;
                small.width = 320;
                small.height = 180;
                small.forward = false;
                small.repeats = 1;
                small.shadows = "none";
                small.out_dir = demo_out + "/rendered";
                run_frame(small);
                FailureCommand rf;
                rf.out_dir = small.out_dir;
                rf.samples = 128;
                rf.gbuffer = small.out_dir + "/gbuffer.exr";
                run_failure_command(rf, demo_relief);
                SweepCommand rs;
                rs.out_dir = small.out_dir;
                rs.gbuffer = rf.gbuffer;
                rs.maps = {demo_data + "/rocks.png"};
                rs.materials = demo_data + "/room.json";
                rs.methods = {"parallax", "steep", "relief", "pom", "cone", "exact"};
                rs.repeats = 3;
                return run_sweep_command(rs, demo_relief);
            } catch (const UsageError&) {
                throw;
            } catch (const offsetmap::Error& e) {  // the rest of the demo stands without GL
                std::printf("demo: no rendered frame: %s\n", e.what());
                return 0;
            }
        }
    } catch (const UsageError& e) {
        return fail(kExitUsage, e.what());
    } catch (const offsetmap::Error& e) {
        return fail(kExitError, e.what());
    } catch (const cl::Error& e) {
        return fail(kExitError, std::string("OpenCL call ") + e.what() +
                                    " failed: " + describe_cl_error(e.err()));
    } catch (const std::bad_alloc&) {
        return fail(kExitError, "out of memory");
    } catch (const std::exception& e) {
        return fail(kExitError, e.what());
    }
    return 0;
}
