// The CLI's subcommands, each a struct: its options, added to its own CLI::App, and its run.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli.hpp"
#include "offsetmap/shared.h"

namespace offsetmap::cli {
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

struct MethodsCli : Command {
    bool json = false;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("methods", "list the methods and their parameters");
        app->add_flag("--json", json, "machine-readable output");
    }
    int run() override {
        print_methods(json);
        return 0;
    }
};

struct DevicesCli : Command {
    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand(
            "devices",
            "list the OpenCL devices: type, lanes and image or buffer path the passes use");
    }
    int run() override {
        print_devices();
        return 0;
    }
};

struct GbufferCli : Command {
    SceneOptions scene;
    std::string out;
    std::vector<int> ids;
    std::string depth;             // the engine form's depth convention ("": the explicit form)
    std::vector<float> curvature;  // kuu kuv kvv [stretch] at every pixel, or none

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("gbuffer", "write a G-buffer EXR from a scene source");
        scene.add_to(*app);
        app->add_option("-o,--output", out, "output EXR file")->required();
        app->add_option("--material-ids", ids,
                        "write a material channel: each uv tile one of these ids (0: no relief)")
            ->check(CLI::Range(0, kMaxMaterialId));
        // The engine form: depth, camera, tangent frame and uv, as an engine writes its G-buffer.
        app->add_option("--engine-form", depth,
                        "write the plane scene in the engine form (depth, camera, frame, uv) with "
                        "this depth convention; render reconstructs V from it")
            ->check(CLI::IsMember({"gl", "zero-one", "reversed"}));
        // A uniformly curved base (a sphere, cylinder or saddle of the relief's own size) without
        // a mesh: the curved trace on a synthetic G-buffer.
        app->add_option("--curvature", curvature,
                        "write curvature channels: kuu kuv kvv in uv units, and optionally the "
                        "uv's stretch, the same at every pixel")
            ->expected(3, 4);
    }
    int run() override {
        scene.check();
        for (float c : curvature)
            if (!std::isfinite(c)) throw UsageError("--curvature takes finite numbers");
        if (depth.empty()) {
            GBuffer gb = scene.make();
            if (!ids.empty()) lay_out_materials(gb, ids);
            if (!curvature.empty())
                gb.curvature.assign(gb.pixels(), {{curvature[0], curvature[1], curvature[2],
                                                   curvature.size() > 3 ? curvature[3] : 1.0f}});
            save_gbuffer(out, gb);
            return 0;
        }
        if (scene.scene != "plane")
            throw UsageError("--engine-form writes the plane scene, not --scene " + scene.scene);
        PlaneScene p = scene.plane;
        if (scene.width) p.width = scene.width;
        if (scene.height) p.height = scene.height;
        const DepthConvention d = depth == "gl"         ? DepthConvention::GL
                                  : depth == "zero-one" ? DepthConvention::ZeroToOne
                                                        : DepthConvention::Reversed;
        EngineScene e = make_engine_scene(p, d);
        if (!ids.empty()) {  // laid out by each pixel's uv, as the explicit form's
            GBuffer at;
            at.resize(e.width, e.height, false, false);
            for (size_t k = 0; k < at.pixels(); ++k) at.uv[k] = {{e.uv[2 * k], e.uv[2 * k + 1]}};
            lay_out_materials(at, ids);
            e.material = at.material;
        }
        if (!curvature.empty()) {
            for (size_t k = 0; k < e.pixels(); ++k)
                e.curvature.insert(e.curvature.end(), curvature.begin(), curvature.begin() + 3);
            if (curvature.size() > 3) e.uv_stretch.assign(e.pixels(), curvature[3]);
        }
        save_engine_gbuffer(out, e);
        return 0;
    }
};

struct RenderCli : Command {
    ReliefOptions relief;
    ShadingOptions shading;
    SceneOptions scene;
    RenderRequest req;
    MaterialsJob materials;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("render", "run one method's offset pass (and shading)");
        relief.add_to(*app, MapOption::Optional);
        shading.add_to(*app);
        scene.add_to(*app, true);
        app->add_option("--method", req.method,
                        "method name (see 'offsetmap methods'); required without --materials");
        app->add_option("--materials", materials.table,
                        "material table (JSON): per material id its map, settings and method "
                        "(or auto by error budget); the G-buffer's ids pick them");
        app->add_flag("--explain", materials.explain,
                      "--materials: each material's method, its error and cost, the "
                      "runner-up");
        app->add_flag("--compare-single", materials.compare_single,
                      "--materials: also run each method at each setting for the whole frame "
                      "and report the cheapest one at the table's worst-material p95 error");
        app->add_option("--tile-rows", materials.tile_rows,
                        "--materials: tile height (tiles are 16 pixels wide)")
            ->check(CLI::Range(1, 64))
            ->capture_default_str();
        app->add_option("--report", materials.out_dir,
                        "--materials: write materials-frame.png, materials-sheet.png (frame, "
                        "ids, method per pixel, error) and materials.json here; implies "
                        "--compare-single");
        app->add_option("--ids-out", materials.ids_out,
                        "--materials: the material ids as a picture (PNG)");
        app->add_option("--set", req.sets, "method parameter key=value (repeatable)");
        app->add_option("--uv-out", req.uv_out, "EXR with u v depth fetches flags");
        app->add_option("--color-out", req.color_out, "shaded image (PNG)");
        app->add_option("--error-out", req.error_out,
                        "heat map of uv error in texels against exact (PNG; log scale to 16)");
    }
    int run() override {
        if (materials.table.empty()) {
            if (relief.height_map.empty())
                throw UsageError("render needs --height-map (or --materials FILE.json)");
            if (req.method.empty())
                throw UsageError("render needs --method (or --materials FILE.json)");
            for (const auto& [given, name] : {std::pair{materials.explain, "--explain"},
                                              {materials.compare_single, "--compare-single"},
                                              {!materials.ids_out.empty(), "--ids-out"},
                                              {!materials.out_dir.empty(), "--report"},
                                              {app->count("--tile-rows") > 0, "--tile-rows"}})
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
};

struct CompareCli : Command {
    ReliefOptions relief;
    ShadingOptions shading;
    SceneOptions scene;
    std::string out = "out/compare";
    int repeats = 5;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("compare", "every method on one scene: contact sheet + table");
        shading.shadows = "soft";
        relief.add_to(*app, MapOption::Required);
        shading.add_to(*app);
        scene.plane.width = 640;
        scene.plane.height = 360;
        scene.add_to(*app, true);
        app->add_option("-o,--out", out, "output folder")->capture_default_str();
        app->add_option("--repeats", repeats, "timed runs per method (median reported)")
            ->check(CLI::Range(1, 100))
            ->capture_default_str();
    }
    int run() override { return run_compare(out, relief, shading, scene, repeats); }
};

struct SweepCli : Command {
    ReliefOptions relief;
    SweepCommand sweep;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("sweep", "accuracy against cost over every method's settings");
        relief.add_to(*app, MapOption::None);
        sweep.add_to(*app);
        app->add_option("--maps", sweep.maps, "height maps (default: the sweep maps in --data)");
        app->add_option("--data", sweep.data_dir,
                        "folder of the default maps (default: the data/ found beside the "
                        "program)");
        app->add_option("--gbuffer", sweep.gbuffer,
                        "G-buffer EXR: the one view set (default: a camera and random views)");
        app->add_option("--materials", sweep.materials,
                        "material table (JSON): its frame on the camera view as one more case "
                        "(map 'materials'), every method for all materials and the table's own");
        app->add_flag("--quick", sweep.quick,
                      "3 maps, smaller views, 3 timed runs (about a minute)");
        app->add_option("--repeats", sweep.repeats, "timed runs per point")
            ->check(CLI::Range(1, 100))
            ->capture_default_str();
    }
    int run() override { return run_sweep_command(sweep, relief); }
};

struct FailureCli : Command {
    ReliefOptions relief;
    FailureCommand failure;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("failure-map", "error over view elevation x depth scale");
        relief.add_to(*app, MapOption::Required, false);
        failure.add_to(*app);
        app->add_option("--samples", failure.samples, "views per cell (at most, with --gbuffer)")
            ->check(CLI::Range(1, 65536))
            ->capture_default_str();
        app->add_option("--gbuffer", failure.gbuffer,
                        "a G-buffer file (e.g. offsetmap frame's gbuffer.exr): its pixels' "
                        "views, binned by elevation, instead of random ones");
    }
    int run() override { return run_failure_command(failure, relief); }
};

struct TemporalCli : Command {
    ReliefOptions relief;
    TemporalCommand temporal;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand("temporal", "frame-to-frame stability along a camera path");
        relief.add_to(*app, MapOption::Required);
        temporal.add_to(*app);
        app->add_option("--frames", temporal.frames, "frames on the path")
            ->check(CLI::Range(2, 1000))
            ->capture_default_str();
    }
    int run() override { return run_temporal_command(temporal, relief); }
};

struct FrameCli : Command {
    FrameCommand frame;

    void add_to(CLI::App& parent) override {
        app = parent.add_subcommand(
            "frame",
            "a rasterized deferred frame (OpenGL G-buffer) around the pass; --forward: the "
            "fragment-shader peer");
        frame.add_to(*app);
    }
    int run() override { return run_frame(frame); }
};

}  // namespace

std::vector<std::unique_ptr<Command>> make_commands() {
    std::vector<std::unique_ptr<Command>> out;
    out.push_back(std::make_unique<MethodsCli>());
    out.push_back(std::make_unique<DevicesCli>());
    out.push_back(std::make_unique<GbufferCli>());
    out.push_back(std::make_unique<RenderCli>());
    out.push_back(std::make_unique<CompareCli>());
    out.push_back(std::make_unique<SweepCli>());
    out.push_back(std::make_unique<FailureCli>());
    out.push_back(std::make_unique<TemporalCli>());
    out.push_back(std::make_unique<FrameCli>());
    out.push_back(demo_command());
    return out;
}

}  // namespace offsetmap::cli
