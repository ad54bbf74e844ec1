#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "offsetmap/passes.hpp"

namespace offsetmap {

// An offset pass's outputs read back to the host.
struct OffsetResult {
    int width = 0;
    int height = 0;
    std::vector<cl_float2> uv;
    std::vector<float> depth;
    std::vector<std::uint32_t> fetches;
    std::vector<std::uint32_t> flags;
    std::vector<double> kernel_ms;  // one per timed run (empty without a profiling queue)

    double median_kernel_ms() const;
};

// Runs `pass` `repeats` times (the first result is kept; all runs are timed) and reads back all
// outputs. Allocates the output buffers on the runtime's context.
OffsetResult run_offset(Runtime& runtime, OffsetPass& pass, const DeviceGBuffer& gbuffer,
                        const DeviceHeightField& field, const PassSettings& settings,
                        int repeats = 1);

// The same for a material frame: each run's time is its classification's and dispatches' kernel
// time together.
OffsetResult run_material_frame(Runtime& runtime, MaterialFrame& frame,
                                const DeviceGBuffer& gbuffer, int repeats = 1);

// Shades uv' from `result` and returns linear RGBA per pixel.
std::vector<cl_float4> run_shade(Runtime& runtime, ShadePass& pass, const OffsetResult& result,
                                 const DeviceGBuffer& gbuffer, const DeviceHeightField& field,
                                 const DeviceImage* albedo, const PassSettings& settings,
                                 const ShadeSettings& shade);

// uv error in texels of the height map, over pixels both results traced.
struct ErrorStats {
    size_t count = 0;
    double mean = 0, p95 = 0, max = 0;
    double wrong_share = 0;  // share of pixels off by more than one texel
};

// The statistics of per-pixel errors.
ErrorStats error_stats(std::vector<double> errors);

// Per-pixel |uv - uv_ref| in texels (NaN where either result passed the pixel through, or where
// `include`, when given, refuses the pixel index), and stats.
ErrorStats uv_error(const OffsetResult& result, const OffsetResult& reference, int field_width,
                    int field_height, std::vector<float>* per_pixel = nullptr,
                    const std::function<bool(size_t)>& include = nullptr);

// True when the pixel was traced (not empty, invalid or back-facing).
bool traced(std::uint32_t flags);

// Height fetches per traced pixel (the cost measure every tool reports), and the most one made.
size_t traced_pixels(const OffsetResult& result);  // pixels with traced(flags)
double mean_fetches(const OffsetResult& result);
double max_fetches(const OffsetResult& result);

}  // namespace offsetmap
