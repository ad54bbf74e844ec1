// Method "auto": the cheapest method and setting whose error on a material's own map, at its
// settings and over the views the frame shows it at, meets the material's error budget.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/material_table.hpp"

namespace offsetmap {

// One method and setting measured on the calibration set.
struct AutoCandidate {
    MethodParams params;
    std::string setting;      // describe_setting() of its overrides
    ErrorStats error;         // uv error in texels against the exact hit (double precision)
    double ns_per_pixel = 0;  // median kernel time per calibration pixel (0 without profiling)
    double fetches = 0;       // mean height fetches per traced pixel
};

struct AutoChoice {
    AutoCandidate chosen;
    AutoCandidate runner_up;  // the next cheapest within the budget; params.method null if none
    std::vector<AutoCandidate> candidates;  // every one measured, in the registry's order
    bool by_time = true;  // cost was ns per pixel (else fetches: no profiling queue)
    bool cached = false;  // the measurements came from the cache
    size_t pixels = 0;    // calibration pixels timed
    size_t samples = 0;   // of those, compared with the exact hit
    size_t skipped = 0;   // candidates not tried: their precomputed data is over the bound
};

struct AutoOptions {
    size_t pixels = 32768;  // the material's on-screen pixels timed (evenly taken in screen order)
    size_t samples = 8192;  // of those, traced in double precision for the error
    size_t least_timed = 65536;  // the pixels repeated to at least this many for the timing
    int repeats = 7;             // timed rounds over all candidates, after one untimed run each
    // Candidates whose precomputed data would take more than this many times the map's height
    // pyramid (and more than the floor) are not tried: sphere's larger distance maps hold up to
    // 64 MiB whatever the map's size, for any material that chose them.
    double precomputed_per_pyramid = 4.0;
    size_t precomputed_floor_bytes = size_t(1) << 20;
    // Where measurements are kept between runs: "" for $OFFSETMAP_CACHE_DIR, else
    // $XDG_CACHE_HOME/offsetmap, else ~/.cache/offsetmap; "-" keeps none.
    std::string cache_dir;
    // Only candidates this admits may be chosen (every one is still measured and cached), and
    // `admits_text` says which in the error when none meets the budget ("with a GLSL version").
    std::function<bool(const MethodParams&)> admits;
    std::string admits_text;
};

// Whether the method at `setting` keeps its precomputed data for `map` within the options' bound
// (always, for a method without any).
bool precomputed_within_bound(const MethodInfo& method,
                              const std::map<std::string, std::string>& setting,
                              const HeightMap& map, const PassSettings& settings,
                              const AutoOptions& options = {});

// The error statistic the budget names, and its name ("mean" or "p95").
double budget_statistic(const ErrorBudget& budget, const ErrorStats& error);
const char* budget_statistic_name(const ErrorBudget& budget);

// Calibrates `material` on the pixels of `frame` that carry its id (its views and uv; a random
// set of views from 10 to 90 degrees when it has none): every method at every setting of its
// sweep grid (the registry) whose precomputed data is within the bound, timed on the device and
// compared with the exact hit. Measurements
// are cached by the map's content, the material's settings, the device and the frame's elevation
// histogram. Throws Error naming the material and the best error reached when no candidate meets
// its budget.
AutoChoice choose_method(std::shared_ptr<Runtime> runtime, const LoadedMaterial& material,
                         const GBuffer& frame, const AutoOptions& options = {});

}  // namespace offsetmap
