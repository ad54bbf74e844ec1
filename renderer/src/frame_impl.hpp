// FrameRenderer's state, shared by the files of its stages (stages/): the camera's raster and
// planes, the core passes it runs, and the stages it orders.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "offsetmap/depth_offset_pass.hpp"
#include "offsetmap/material_frame.hpp"
#include "offsetmap/renderer/context.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/shadow_mask_pass.hpp"
#include "offsetmap/timing.hpp"
#include "raster.hpp"
#include "stages/behind.hpp"
#include "stages/light.hpp"
#include "stages/planes.hpp"

namespace offsetmap::renderer {

// What one render() keeps across its frames, for the read-back after them.
struct FrameScratch {
    std::vector<float> t_gl;  // forward: the offset plane's t
    std::vector<cl_float2> forward_uv;
    std::vector<std::uint32_t> forward_fetches;
    std::vector<double> offset_kernel, shade_kernel;
    PassTimes light;      // the light's stage in the last frame
    int light_draws = 0;  // its draws in this render
};

// Each pass's median over `times` (zeros for none).
PassTimes median_times(const std::vector<PassTimes>& times);

// An offset result's planes from GL's rows (bottom first) to top first.
void flip_result(OffsetResult& r);

struct FrameRenderer::Impl {
    std::shared_ptr<Runtime> rt;
    std::unique_ptr<GlContext> gl;
    std::unique_ptr<Raster> raster;
    View view;
    EngineLight light;
    int width = 0, height = 0;
    std::vector<LoadedMaterial> table;
    std::vector<MethodParams> methods;
    std::vector<ForwardMaterial> forward;
    std::unique_ptr<MaterialFrame> frame;
    std::unique_ptr<ReconstructPass> reconstruct;
    std::unique_ptr<DepthOffsetPass> depth_offset;
    ShadeSettings shading;
    // The engine G-buffer's planes with the uv density (GL reads into them; read-write: with a
    // layer behind, its pixels take that layer's depth, ids, uv density and curvature in place),
    // the explicit G-buffer (its curvature bound only while set_curvature is on), the outputs
    // (colour and depth after, which GL takes back from mapped memory).
    GBufferPlanes planes;
    DeviceGBuffer dg;
    OffsetTargets targets;
    cl::Buffer rgba, depth_after;
    // A table with triplanar materials: their pixels' other projections, weights and normals.
    std::optional<TriplanarPlanes> triplanar;
    Scene scene;
    int layers = 1;
    bool whole_behind = false;            // set_layers's `whole`
    std::unique_ptr<BehindStage> behind;  // set_layers(2), made at first use
    // The shadow map (set_shadow_map): the light's stage, the receivers' test, its outputs.
    struct Shadows {
        ShadowMapSettings settings;
        std::unique_ptr<LightStage> light;
        std::unique_ptr<ShadowMaskPass> test;
        cl::Buffer mask, visibility;
        bool drawn = false;  // the light's stage holds a map
    };
    std::unique_ptr<Shadows> shadows;

    size_t pixels() const { return static_cast<size_t>(width) * height; }
    EngineCamera camera() const { return pass_camera_of(view); }

    // The frame's stages, in order; each blocks and returns or adds its passes' times.
    PassTimes render_frame(const FrameRun& run, bool prepass, FrameScratch& s);
    void draw_and_move(const FrameRun& run, bool prepass, FrameScratch& s, Stopwatch& clock,
                       PassTimes& t);
    void offset(const FrameRun& run, const EngineGBuffer& g, FrameScratch& s, Stopwatch& clock,
                PassTimes& t);
    void light_and_shade(const FrameRun& run, FrameScratch& s, Stopwatch& clock, PassTimes& t);
    // Forward with triplanar materials: the shading takes the fragment shader's projections in
    // the order the reconstruct pass gave each pixel.
    void order_forward_projections(FrameScratch& s);
    // After the timed frames: the last frame's outputs, rows top first (stages/readback.cpp).
    void read_back(FrameRun& run, bool prepass, FrameScratch& s, EngineScene& engine,
                   GBuffer& explicit_gbuffer);
};

// Rows bottom first (GL) to top first, `c` values a pixel (an empty plane stays empty).
template <typename T>
std::vector<T> flip_rows(const std::vector<T>& in, int width, int height, int c) {
    std::vector<T> out(in.size());
    const size_t row = static_cast<size_t>(width) * c;
    if (in.empty()) return out;
    for (int y = 0; y < height; ++y)
        std::copy_n(in.begin() + row * (height - 1 - y), row, out.begin() + row * y);
    return out;
}

}  // namespace offsetmap::renderer
