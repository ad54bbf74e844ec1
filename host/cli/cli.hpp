// Pieces shared by the CLI's subcommands.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "offsetmap/evaluation.hpp"

namespace offsetmap::cli {

// Options that describe the relief and its material, shared by render and demo.
struct ReliefOptions {
    std::string height_map;
    bool depth_map = false;
    int channel = 0;
    std::string normal_map;
    bool flip_green = false;
    std::string albedo;
    PassSettings pass;
    std::string address = "wrap";
    std::string grazing = "clamp";
    std::vector<float> lod_fade_texels;  // footprint LOD: low high
    std::vector<float> light;  // x y z, tangent space, when the G-buffer has none
    std::string device;
    std::string shadows = "none";
    ShadeSettings shade;

    void add_to(CLI::App& app, bool height_map_required);
    PassSettings settings() const;         // pass with the address mode applied
    ShadeSettings shade_settings() const;  // shading with light and shadow options applied
};

// Scene source options, shared by gbuffer, render and demo.
struct SceneOptions {
    std::string scene = "plane";
    PlaneScene plane;
    SweepScene sweep;
    RandomScene random;
    int width = 0, height = 0;  // 0: the scene's default

    void add_to(CLI::App& app);
    GBuffer make() const;
};

// Every method on one scene: shaded, uv-error and fetch-count images, contact sheet, table.
int run_compare(const std::string& out_dir, const ReliefOptions& relief, const SceneOptions& scene,
                int repeats);

// What every analysis command takes: where to write, which methods, whether to draw charts.
struct AnalysisOptions {
    std::string out_dir;
    std::vector<std::string> methods;  // empty: every method
    bool charts = true;

    void add_to(CLI::App& app);
};

struct SweepCommand : AnalysisOptions {
    std::vector<std::string> maps;  // image files; default: the sweep maps in data_dir
    std::string data_dir = "data";
    bool quick = false;
    int repeats = 5;
    SweepCommand() { out_dir = "out/sweep"; }
};
int run_sweep_command(const SweepCommand& cmd, const ReliefOptions& relief);

struct FailureCommand : AnalysisOptions {
    int samples = 256;
    FailureCommand() { out_dir = "out/failure"; }
};
int run_failure_command(const FailureCommand& cmd, const ReliefOptions& relief);

struct TemporalCommand : AnalysisOptions {
    int frames = 24;
    TemporalCommand() { out_dir = "out/temporal"; }
};
int run_temporal_command(const TemporalCommand& cmd, const ReliefOptions& relief);

// Runs bench/<script> with Debian's Python (matplotlib); false (with a warning) when it cannot.
bool run_chart_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace offsetmap::cli
