// Pieces shared by the CLI's subcommands.
#pragma once
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/evaluation.hpp"

namespace offsetmap::cli {

// Exit codes: 0 done, 1 an input or runtime error (a file, the device, memory), 2 a usage error.
inline constexpr int kExitError = 1;
inline constexpr int kExitUsage = 2;

// A bad, unknown, conflicting or ignored option (exit 2). Every other Error exits 1.
class UsageError : public Error {
  public:
    using Error::Error;
};

// Runs `f`, turning the library's Errors (its checks of settings and method parameters) into
// UsageErrors: what it rejects came from the command line.
template <typename F>
auto as_usage(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const UsageError&) {
        throw;
    } catch (const Error& e) {
        throw UsageError(e.what());
    }
}

enum class MapOption { Required, Optional, None };

// Options that describe the relief and how the pass runs over it.
struct ReliefOptions {
    std::string height_map;
    bool depth_map = false;
    int channel = 0;
    PassSettings pass;
    std::string address = "wrap";
    std::string height_storage = "auto";
    std::string grazing = "clamp";
    std::vector<float> lod_fade_texels;  // footprint LOD: low high
    std::string device;

    // `scale`: false for a command that sweeps the depth scale itself (--scale is then refused).
    void add_to(CLI::App& app, MapOption map, bool scale = true);
    // The pass settings the options give; throws UsageError for a bad combination.
    PassSettings settings() const;
    HeightLoadOptions load_options() const { return {channel, depth_map}; }

  private:
    CLI::Option* scale_ = nullptr;
    bool scale_swept_ = false;
};

// Options of the shaded image: normals, albedo, light and shadows.
struct ShadingOptions {
    std::string normal_map;
    bool flip_green = false;
    std::string albedo;
    std::vector<float> light;  // x y z, tangent space, replaces the G-buffer's L
    std::string shadows = "none";
    ShadeSettings shade;

    void add_to(CLI::App& app);
    ShadeSettings shade_settings() const;

    // The normal map and albedo files given, read (before any device work).
    struct Files {
        Image4 normals, albedo;  // 0 x 0 when not given
        const Image4* normal_map() const { return normals.width ? &normals : nullptr; }
        // The albedo uploaded into `storage`; null when there is none.
        const DeviceImage* upload_albedo(Runtime& runtime, DeviceImage& storage) const;
    };
    Files read_files() const;
    // The first shading option given on the command line ("" when none).
    std::string first_given() const;

  private:
    std::vector<CLI::Option*> options_;
};

// --shadows' value (none, hard, soft) as the shade pass takes it.
ShadowMode shadow_mode(const std::string& name);

// Where the G-buffer comes from: a built-in scene, or (with `file`) a G-buffer EXR.
struct SceneOptions {
    std::string scene = "plane";
    PlaneScene plane;
    SweepScene sweep;
    RandomScene random;
    int width = 0, height = 0;  // 0: the scene's default
    std::string gbuffer;        // a G-buffer file instead of a scene

    void add_to(CLI::App& app, bool file = false);
    // Throws UsageError for a scene option beside --gbuffer, or an option of another scene.
    void check() const;
    GBuffer make() const;          // the scene, or the file read
    std::string describe() const;  // "plane scene 640x360" or "G-buffer 'file'"

  private:
    struct Known {
        CLI::Option* option;
        std::vector<std::string> scenes;  // the scenes it applies to
    };
    std::vector<Known> options_;
};

// A folder of the repository (data, bench) found from the program, not the working directory:
// $env, then beside the build folder or the installed binary, then the checkout it was built from;
// it must hold `marker`. Throws Error naming where it looked.
std::string find_beside_program(const std::string& folder, const std::string& marker,
                                const char* env);
// The default maps (data/).
std::string default_data_dir();

// Shows a slow step's progress on stderr: on a terminal a carriage-return line (cleared with ""),
// otherwise a plain line each (the empty one dropped).
void progress_line(const std::string& line);
// Runtime progress (precomputes) on stderr: on a terminal a line updated in place once a step has
// run for half a second; otherwise a line every ten seconds once it has run for two.
void show_progress(Runtime& runtime);

// "pom min_samples=8 max_samples=32": a method with every parameter's value.
std::string method_text(const MethodParams& p);
// "kernel 0.128 ms", or where the device gives no kernel times (Runtime::profiling) says so.
std::string kernel_time_text(double ms);

// `offsetmap frame`: a rasterized frame around the pass (and the forward peer).
struct FrameCommand {
    std::string scene = "room";
    std::string materials;  // default: the scene's table
    std::string camera;
    int width = 1920, height = 1080;
    std::string method;
    std::vector<std::string> sets;
    bool forward = false;
    bool curvature = false;     // also the deferred frame over the curved base (its final.png)
    bool uv_metric = false;     // the curved frames with the uv metric plane beside it
    int layers = 1;             // 2: also the deferred frame with the G-buffer's layer behind
    bool truth = false;         // the displaced mesh as the truth, every frame against it
    float truth_level = 0.5f;   // its lattice, texels per quad
    std::string sun;            // "ELEVATION,AZIMUTH" (degrees): also the light's displaced view
    std::string spot;           // "X,Y,Z,AX,AY,AZ,INNER,OUTER": a spot light instead (degrees)
    int shadow_size = 1024;     // its shadow map, square
    int shadow_truth_size = 0;  // --truth's own shadow map (0: shadow_size)
    std::string out_dir = "out/frame";
    int repeats = 3;
    std::string shadows = "none";
    std::string device;
    std::string data_dir;

    void add_to(CLI::App& app);
};
int run_frame(const FrameCommand& cmd);

// A frame of many materials (render --materials, the demo): the table, the outputs asked for.
struct MaterialsJob {
    std::string table;  // the JSON file
    std::string uv_out, color_out, error_out, ids_out;
    std::string out_dir;  // when set: materials-frame.png, materials-sheet.png, materials.json
    bool explain = false;
    // Also every method at every setting of its grid for the whole frame: the cheapest single
    // one at the table's worst-material p95 (on by default with out_dir).
    bool compare_single = false;
    int tile_rows = kDefaultTileRows;
    int repeats = 5;
};
int run_materials_job(const MaterialsJob& job, const ReliefOptions& relief,
                      const ShadingOptions& shading, const SceneOptions& scene);

// Every method on one scene: shaded, uv-error and fetch-count images, contact sheet, table.
int run_compare(const std::string& out_dir, const ReliefOptions& relief,
                const ShadingOptions& shading, const SceneOptions& scene, int repeats);

// What every analysis command takes: where to write, which methods, whether to draw charts.
struct AnalysisOptions {
    std::string out_dir;
    std::vector<std::string> methods;  // empty: every method
    bool charts = true;

    void add_to(CLI::App& app);
};

struct SweepCommand : AnalysisOptions {
    std::vector<std::string> maps;  // image files; default: the sweep maps in data_dir
    std::string data_dir;           // default: default_data_dir()
    std::string gbuffer;    // a G-buffer file as the only view set (default: camera, random)
    std::string materials;  // a material table: its frame as one more case
    bool quick = false;
    int repeats = 5;
    SweepCommand() { out_dir = "out/sweep"; }
};
int run_sweep_command(const SweepCommand& cmd, const ReliefOptions& relief);

struct FailureCommand : AnalysisOptions {
    int samples = 256;
    std::string gbuffer;  // a G-buffer file whose views replace the random ones
    FailureCommand() { out_dir = "out/failure"; }
};
int run_failure_command(const FailureCommand& cmd, const ReliefOptions& relief);

struct TemporalCommand : AnalysisOptions {
    int frames = 24;
    TemporalCommand() { out_dir = "out/temporal"; }
};
int run_temporal_command(const TemporalCommand& cmd, const ReliefOptions& relief);

// One subcommand: its options, added to the subcommand it makes (`app`), and what it does.
struct Command {
    virtual ~Command() = default;
    virtual void add_to(CLI::App& parent) = 0;
    virtual int run() = 0;  // the exit code
    CLI::App* app = nullptr;
};
// Every subcommand, in the order `offsetmap --help` lists them.
std::vector<std::unique_ptr<Command>> make_commands();
std::unique_ptr<Command> demo_command();

// Runs tools/bench/<script> with Debian's Python (matplotlib); false (with a warning) when it
// cannot.
bool run_chart_script(const std::string& script, const std::vector<std::string>& args);

}  // namespace offsetmap::cli
