// `offsetmap sweep` and `offsetmap failure-map`: accuracy against cost over every method's
// settings, and error over view elevation x depth scale, as CSV, JSON and matplotlib charts.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include "cli.hpp"

#ifndef OFFSETMAP_SCRIPT_DIR
#define OFFSETMAP_SCRIPT_DIR "bench"
#endif

namespace offsetmap::cli {
namespace {

std::string shell_quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

void progress_line(const std::string& line) {
    std::fprintf(stderr, "\r\033[K%s", line.c_str());
    std::fflush(stderr);
}

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

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
    const char* env = std::getenv("OFFSETMAP_SCRIPT_DIR");
    std::string path = std::string(env ? env : OFFSETMAP_SCRIPT_DIR) + "/" + script;
    if (!std::filesystem::exists(path)) {
        std::cerr << "offsetmap: warning: chart script '" << path
                  << "' not found (set OFFSETMAP_SCRIPT_DIR to the repository's bench/); charts "
                     "skipped\n";
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
    std::vector<std::string> files = cmd.maps;
    if (files.empty()) {
        const char* sweep_maps[] = {"bumps", "sines", "rocks", "noise", "spikes", "text", "stairs"};
        const char* quick_maps[] = {"bumps", "rocks", "spikes"};
        if (cmd.quick)
            for (const char* m : quick_maps) files.push_back(cmd.data_dir + "/" + m + ".png");
        else
            for (const char* m : sweep_maps) files.push_back(cmd.data_dir + "/" + m + ".png");
    }
    std::vector<NamedMap> maps;
    for (const auto& f : files)
        maps.push_back({stem(f), load_height_map(f, {relief.channel, relief.depth_map})});
    PlaneScene plane;
    plane.width = cmd.quick ? 320 : 640;
    plane.height = cmd.quick ? 180 : 360;
    RandomScene random;
    random.width = random.height = cmd.quick ? 96 : 256;
    std::vector<NamedViews> views = {{"camera", make_scene(plane)}, {"random", make_scene(random)}};
    make_dir(cmd.out_dir);

    auto rt = Runtime::create(relief.device);
    SweepOptions o;
    o.settings = settings;
    o.repeats = cmd.quick ? std::min(cmd.repeats, 3) : cmd.repeats;
    o.methods = cmd.methods;
    o.progress = progress_line;
    std::vector<SweepRecord> records = run_sweep(rt, maps, views, o);
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
    if (o.settings.min_elevation_deg > 1.0f)
        throw Error("the failure map goes down to 1 degree: --grazing-min-deg must be <= 1");
    HeightMap map = load_height_map(relief.height_map, {relief.channel, relief.depth_map});
    make_dir(cmd.out_dir);
    auto rt = Runtime::create(relief.device);
    auto cells = run_failure_map(rt, map, o);
    std::fprintf(stderr, "\n");
    write_failure_csv(cmd.out_dir + "/failure.csv", cells);
    std::printf("failure map: %zu cells, wrote %s/failure.csv\n", cells.size(),
                cmd.out_dir.c_str());
    if (cmd.charts)
        run_chart_script("plot_failure.py",
                         {cmd.out_dir + "/failure.csv", cmd.out_dir + "/failure-map.png",
                          "Failure maps on " + stem(relief.height_map) +
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
    HeightMap map = load_height_map(relief.height_map, {relief.channel, relief.depth_map});
    make_dir(cmd.out_dir);
    auto rt = Runtime::create(relief.device);
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
