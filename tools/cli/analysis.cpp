// `offsetmap sweep` and `offsetmap failure-map`: accuracy against cost over every method's
// settings, and error over view elevation x depth scale, as CSV, JSON and matplotlib charts.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "cli.hpp"

namespace offsetmap::cli {
namespace {

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// Unknown method names are usage errors, found before any file is read.
void select_methods_checked(const std::vector<std::string>& names) {
    as_usage([&] { return select_methods(names); });
}

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// "folder/file": enough of a path to tell one frame's G-buffer from another's.
std::string short_path(const std::string& path) {
    const std::filesystem::path p(path);
    return (p.parent_path().filename() / p.filename()).string();
}

void make_dir(const std::string& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw Error("cannot create output folder '" + dir + "': " + ec.message());
}

}  // namespace

void AnalysisOptions::add_to(CLI::App& app) {
    app.add_option("-o,--out", out_dir, "output folder")->capture_default_str();
    app.add_option("--methods", methods, "methods (default: all)");
    app.add_flag("!--no-charts", charts, "skip the matplotlib charts");
}

bool run_chart_script(const std::string& script, const std::vector<std::string>& args) {
    std::string path;
    try {
        path = find_beside_program("tools/bench", script, "OFFSETMAP_SCRIPT_DIR") + "/" + script;
    } catch (const Error& e) {
        std::cerr << "offsetmap: warning: charts skipped: " << e.what() << "\n";
        return false;
    }
    // Debian's python3-matplotlib lives in the system interpreter, which may not be first on PATH.
    std::string python =
        std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
    std::string cmd = python + " " + shell_quote(path);
    for (const auto& a : args) cmd += " " + shell_quote(a);
    std::fflush(stdout);  // our lines first, then the script's
    if (std::system(cmd.c_str()) != 0) {
        std::cerr << "offsetmap: warning: drawing charts failed (" << cmd
                  << "); install python3-matplotlib\n";
        return false;
    }
    return true;
}

int run_sweep_command(const SweepCommand& cmd, const ReliefOptions& relief) {
    PassSettings settings = relief.settings();
    select_methods_checked(cmd.methods);
    if (!cmd.maps.empty() && !cmd.data_dir.empty())
        throw UsageError(
            "--data names the folder of the default maps; it cannot be used with "
            "--maps, which names the maps");
    if (!cmd.gbuffer.empty() && cmd.quick)
        throw UsageError("--quick shrinks the built-in views; it cannot be used with --gbuffer");
    std::vector<std::string> files = cmd.maps;
    if (files.empty()) {
        const std::string data = cmd.data_dir.empty() ? default_data_dir() : cmd.data_dir;
        const char* sweep_maps[] = {"bumps", "sines", "rocks", "noise", "spikes", "text", "stairs"};
        const char* quick_maps[] = {"bumps", "rocks", "spikes"};
        if (cmd.quick)
            for (const char* m : quick_maps) files.push_back(data + "/" + m + ".png");
        else
            for (const char* m : sweep_maps) files.push_back(data + "/" + m + ".png");
    }
    std::vector<NamedMap> maps;
    for (const auto& f : files)
        maps.push_back({stem(f), load_height_map(f, relief.load_options())});
    std::vector<NamedViews> views;
    if (!cmd.gbuffer.empty()) {
        views.push_back({short_path(cmd.gbuffer), load_gbuffer(cmd.gbuffer)});
    } else {
        PlaneScene plane;
        plane.width = cmd.quick ? 320 : 640;
        plane.height = cmd.quick ? 180 : 360;
        RandomScene random;
        random.width = random.height = cmd.quick ? 96 : 256;
        views = {{"camera", make_scene(plane)}, {"random", make_scene(random)}};
    }
    make_dir(cmd.out_dir);

    auto rt = Runtime::create(relief.device);
    show_progress(*rt);
    SweepOptions o;
    o.settings = settings;
    o.repeats = cmd.quick ? std::min(cmd.repeats, 3) : cmd.repeats;
    o.methods = cmd.methods;
    o.progress = progress_line;
    std::vector<SweepRecord> records = run_sweep(rt, maps, views, o);
    if (!cmd.materials.empty()) {
        // The frame of the table's materials: on a G-buffer file with ids (a rendered frame's),
        // its own; else on the camera view, each material a tile of its own.
        const std::vector<LoadedMaterial> table =
            load_materials(read_material_table(cmd.materials, settings));
        const bool own_ids =
            !views.empty() && !cmd.gbuffer.empty() && views.front().gbuffer.has_material();
        GBuffer gb;
        if (own_ids) {
            gb = views.front().gbuffer;
        } else {
            PlaneScene plane;
            plane.width = cmd.quick ? 320 : 640;
            plane.height = cmd.quick ? 180 : 360;
            plane.camera_height = 0.9;
            plane.pitch_deg = 28.0;
            gb = make_scene(plane);
            std::vector<int> ids;
            for (const auto& m : table) ids.push_back(m.spec.id);
            lay_out_materials(gb, ids);
        }
        std::vector<MethodParams> chosen;
        for (const auto& m : table)
            chosen.push_back(m.spec.method == "auto"
                                 ? choose_method(rt, m, gb).chosen.params
                                 : resolve_params(find_method(m.spec.method), m.spec.params));
        const auto frame =
            sweep_material_frame(rt, table, chosen, gb, own_ids ? views.front().name : "camera",
                                 o.repeats, o.progress, cmd.methods);
        records.insert(records.end(), frame.begin(), frame.end());
    }
    std::fprintf(stderr, "\n");
    write_sweep_csv(cmd.out_dir + "/sweep.csv", records);
    write_sweep_json(cmd.out_dir + "/sweep.json", records, rt->device_name(), settings);
    std::printf("sweep: %zu points on %s, wrote %s/sweep.csv and sweep.json\n", records.size(),
                rt->device_name().c_str(), cmd.out_dir.c_str());
    if (cmd.charts) run_chart_script("plot_sweep.py", {cmd.out_dir + "/sweep.json", cmd.out_dir});
    return 0;
}

int run_failure_command(const FailureCommand& cmd, const ReliefOptions& relief) {
    FailureMapOptions o;
    o.settings = relief.settings();
    o.samples = cmd.samples;
    o.methods = cmd.methods;
    o.progress = progress_line;
    select_methods_checked(cmd.methods);
    if (o.settings.min_elevation_deg > 1.0f)
        throw UsageError("the failure map goes down to 1 degree: --grazing-min-deg must be <= 1");
    HeightMap map = load_height_map(relief.height_map, relief.load_options());
    make_dir(cmd.out_dir);
    auto rt = Runtime::create(relief.device);
    show_progress(*rt);
    GBuffer views;
    if (!cmd.gbuffer.empty()) {
        views = load_gbuffer(cmd.gbuffer, kDefaultReadLimitBytes, rt);
        o.views = &views;
    }
    auto cells = run_failure_map(rt, map, o);
    std::fprintf(stderr, "\n");
    write_failure_csv(cmd.out_dir + "/failure.csv", cells);
    size_t compared = 0;
    for (const FailureCell& c : cells) compared = std::max(compared, c.uv.count);
    std::printf("failure map: %zu cells%s, wrote %s/failure.csv\n", cells.size(),
                cmd.gbuffer.empty() ? ""
                                    : (" over the views of " + cmd.gbuffer + " (up to " +
                                       std::to_string(compared) + " pixels a cell)")
                                          .c_str(),
                cmd.out_dir.c_str());
    if (cmd.charts)
        run_chart_script(
            "plot_failure.py",
            {cmd.out_dir + "/failure.csv", cmd.out_dir + "/failure-map.png",
             "Failure maps on " + stem(relief.height_map) +
                 (cmd.gbuffer.empty() ? "" : " over the views of " + short_path(cmd.gbuffer)) +
                 " (grazing policy: " + relief.grazing + ")"});
    return 0;
}

int run_temporal_command(const TemporalCommand& cmd, const ReliefOptions& relief) {
    TemporalOptions o;
    o.settings = relief.settings();
    o.frames = cmd.frames;
    o.methods = cmd.methods;
    o.start.width = 480;
    o.start.height = 270;
    o.progress = progress_line;
    select_methods_checked(cmd.methods);
    HeightMap map = load_height_map(relief.height_map, relief.load_options());
    make_dir(cmd.out_dir);
    auto rt = Runtime::create(relief.device);
    show_progress(*rt);
    auto records = run_temporal(rt, map, o);
    std::fprintf(stderr, "\n");
    write_temporal_csv(cmd.out_dir + "/temporal.csv", records);
    std::printf("temporal stability over %d frames (texels, mean of frame pairs):\n", cmd.frames);
    std::vector<std::string> order;
    for (const auto& r : records)
        if (std::find(order.begin(), order.end(), r.method) == order.end())
            order.push_back(r.method);
    for (const auto& m : order) {
        double mean = 0, pop = 0;
        int n = 0;
        for (const auto& r : records)
            if (r.method == m) mean += r.mean, pop += r.pop_share, ++n;
        std::printf("  %-18s %10.4f   %6.2f%% of pixels pop\n", m.c_str(), mean / n,
                    100.0 * pop / n);
    }
    if (cmd.charts)
        run_chart_script("plot_temporal.py",
                         {cmd.out_dir + "/temporal.csv", cmd.out_dir + "/temporal.png"});
    return 0;
}

}  // namespace offsetmap::cli
