// A material frame measured: its run, each material's error against the exact hit, and the
// frame as a sweep case (every method at every setting for the whole frame, and the table's mix).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/auto_method.hpp"
#include "offsetmap/material_table.hpp"
#include "offsetmap/sweep.hpp"

namespace offsetmap {

struct MaterialFrameRun {
    std::unique_ptr<MaterialFrame> pass;
    OffsetResult result;  // kernel_ms: classification and dispatches, per timed run
};

// The table with `methods` (one per material) over `gbuffer`: one warm-up run, then `repeats`
// timed ones.
MaterialFrameRun run_materials(std::shared_ptr<Runtime> runtime,
                               const std::vector<LoadedMaterial>& table,
                               const std::vector<MethodParams>& methods,
                               const DeviceGBuffer& gbuffer, int tile_rows = kDefaultTileRows,
                               int repeats = 5);

// The table with every material traced by `exact`: the reference.
OffsetResult run_materials_exact(std::shared_ptr<Runtime> runtime,
                                 const std::vector<LoadedMaterial>& table,
                                 const DeviceGBuffer& gbuffer);
// The same over a frame's materials as they are on the device (their fields shared, not uploaded
// again).
OffsetResult run_materials_exact(std::shared_ptr<Runtime> runtime, const MaterialFrame& frame,
                                 const DeviceGBuffer& gbuffer);

struct MaterialError {
    size_t pixels = 0, traced = 0;
    double fetches = 0;  // per traced pixel
    ErrorStats error;    // in texels of the material's own map
};
// Per material (table order); `per_pixel` (optional) gets each pixel's error in its material's
// texels, NaN where untraced or id 0.
std::vector<MaterialError> material_errors(const GBuffer& gbuffer, const OffsetResult& result,
                                           const OffsetResult& exact,
                                           const std::vector<LoadedMaterial>& table,
                                           std::vector<float>* per_pixel = nullptr);

// Frames timed in turns (one warm-up each, then `rounds` rounds running every frame once): the
// median kernel time of each (classification and dispatches), so that frames compared as a ratio
// share the machine's load. Needs a profiling queue (zeros without).
std::vector<double> time_frames_in_turns(Runtime& runtime,
                                         const std::vector<MaterialFrame*>& frames,
                                         const DeviceGBuffer& gbuffer, int rounds = 7);

// Each material's cost in the frame: `frame` run over `gbuffer` with every other material's pixels
// set to id 0, the median over `repeats` runs (the materials in turns) of its one dispatch's kernel
// time per pixel of that material (ns; 0 for a material without pixels, or without a profiling
// queue).
std::vector<double> material_ns_per_pixel(Runtime& runtime, MaterialFrame& frame,
                                          const GBuffer& gbuffer, int repeats = 5);

// The frame as a sweep case: one record per method (those named in `only`, or all) and setting of
// the registry's grids, run for
// every material at once, and one for the table's own methods (method "per-material"). Map
// "materials", views `views_name`; the uv error pools every material's pixels in their own
// texels; worst_material_p95 is the largest of the materials' p95. With `bound`, a setting whose
// precomputed data exceeds it on any material (precomputed_within_bound) is left out, as auto
// leaves it out.
std::vector<SweepRecord> sweep_material_frame(
    std::shared_ptr<Runtime> runtime, const std::vector<LoadedMaterial>& table,
    const std::vector<MethodParams>& chosen, const GBuffer& gbuffer, const std::string& views_name,
    int repeats = 5, const std::function<void(const std::string&)>& progress = nullptr,
    const std::vector<std::string>& only = {}, const AutoOptions* bound = nullptr);

}  // namespace offsetmap
