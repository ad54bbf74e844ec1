#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/passes.hpp"

namespace offsetmap {

// One accuracy-vs-cost measurement: a method at one setting on one height map and view set.
struct SweepRecord {
    std::string method;
    std::string setting;  // describe_setting() of the overrides
    std::string map;
    std::string views;
    ErrorStats uv;           // uv error in texels against exact
    double depth_error = 0;  // mean |t - t_exact| in texels of the map, along the ray
    double psnr_db = 0;      // shaded image against the one shaded at exact uv' (sRGB)
    double fetches_mean = 0;
    double fetches_max = 0;
    double ns_per_pixel = 0;  // median kernel time over traced and untraced pixels
    double kernel_ms = 0;     // median kernel time
    size_t precomputed_bytes = 0;
    double precompute_ms = 0;
    double worst_material_p95 = 0;  // material frames: the largest of the materials' p95
};

struct NamedMap {
    std::string name;
    HeightMap map;
};

struct NamedViews {
    std::string name;
    GBuffer gbuffer;
};

struct SweepOptions {
    PassSettings settings;
    int repeats = 5;                   // timed runs after one warm-up (median reported)
    std::vector<std::string> methods;  // empty: every method
    bool defaults_only = false;        // each method at its defaults only (no grid)
    std::function<void(const std::string&)> progress;  // one line per step
};

// Runs every method over its sweep grid (registry) on every map and view set; `exact` is the
// reference (its own record has zero error and its real cost).
std::vector<SweepRecord> run_sweep(std::shared_ptr<Runtime> runtime,
                                   const std::vector<NamedMap>& maps,
                                   const std::vector<NamedViews>& views,
                                   const SweepOptions& options);

void write_sweep_csv(const std::string& path, const std::vector<SweepRecord>& records);
void write_sweep_json(const std::string& path, const std::vector<SweepRecord>& records,
                      const std::string& device, const PassSettings& settings);

// PSNR in dB of two linear RGBA images over pixels with alpha > 0 in `reference`, after sRGB
// encoding; 99 dB when they are equal.
double psnr_srgb(const std::vector<cl_float4>& image, const std::vector<cl_float4>& reference);

}  // namespace offsetmap
