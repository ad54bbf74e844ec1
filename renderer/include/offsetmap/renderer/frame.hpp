// A rendered deferred frame around the pass: the scene rasterized by OpenGL into the engine-shaped
// G-buffer, the reconstruct, offset (the material frame) and shade passes on the OpenCL device,
// the pixel depth offset written back into the depth buffer. Or the forward peer: the same scene
// with each material's method in the G-buffer pass's fragment shader and the same shading.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/material_table.hpp"
#include "offsetmap/renderer/scene.hpp"
#include "offsetmap/scenes.hpp"
#include "offsetmap/shade_pass.hpp"
#include "offsetmap/shadow_mask_pass.hpp"

namespace offsetmap::renderer {

enum class FrameMode { Deferred, Forward };

// Wall-clock milliseconds of each pass of one frame (each ends in a finish), medians over the
// timed frames. GL -> CL and CL -> GL go through the host (see FrameRenderer::interop).
struct PassTimes {
    double gbuffer = 0;       // the G-buffer pass (forward: with the methods traced in it)
    double to_device = 0;     // G-buffer planes read by GL into mapped CL buffers (one copy)
    double reconstruct = 0;   // tangent-space V and L
    double offset = 0;        // the material frame (classification, count read-back, dispatches)
    double shade = 0;         // per-material shading
    double depth_offset = 0;  // the pixel depth offset (a CL kernel)
    double shadow_mask = 0;   // with a shadow map: the receivers' test (a CL kernel)
    double to_gl = 0;         // colour and depth written to GL from mapped CL buffers
    double total = 0;         // the whole frame, end to end (with a shadow map, its light's too)
};

struct FrameRun {
    FrameMode mode = FrameMode::Deferred;
    bool prepass = false;
    bool curved = false;  // over the curved base (set_curvature), deferred or forward
    int layers = 1;       // deferred: 2 with the layer behind (set_layers)
    // Two layers: pixels that show the second layer's surface (OM_FLAG_BEHIND), and pixels the
    // first layer does not show whose second shows nothing either (the background's).
    size_t behind_pixels = 0, missed_pixels = 0;
    // Triplanar materials (deferred): their pixels traced in one, two and three projections.
    std::array<size_t, 3> projections{};
    std::vector<float> projection_count;  // per pixel: 1 to 3, 0 where not triplanar (or empty)
    // Per pixel: the projection (0-5) the G-buffer holds, its largest; -1 where not triplanar.
    std::vector<std::int8_t> first_projection;
    PassTimes ms;
    double offset_kernel_ms = 0;  // deferred: the material frame's kernel time (profiling)
    double shade_kernel_ms = 0;   // the shade kernel's time (profiling; 0 where not timed)
    size_t to_device_bytes = 0;   // what a frame moves from GL to CL, and back to GL
    size_t to_gl_bytes = 0;
    // Fragments the G-buffer pass's shader ran on (depth-tested first; forward: each one traced)
    std::int64_t shaded_fragments = 0;
    OffsetResult offset;             // uv', depth t, fetches, flags (forward: flags EMPTY or 0)
    std::vector<cl_float4> color;    // linear RGBA
    std::vector<float> depth_after;  // window depth after the offset (GL convention)
    // The material id each pixel shows: the G-buffer's, the layer behind's where BEHIND.
    std::vector<float> material;
    // With a shadow map (set_shadow_map): the light's passes that drew it each frame (the
    // G-buffer, the planes' move, reconstruct, offset and depth offset; total their sum), and per
    // pixel the lit fraction its test gave and the visibility the shading used (the smaller of it
    // and the self-shadow march). Empty without one.
    PassTimes shadow_map_ms;
    std::vector<float> shadow_mask, light_visibility;
    // Frames rendered (the warm-up's included) and the light's views drawn for them: one a
    // frame with a shadow map, none without.
    int frames = 0, light_draws = 0;
};

// A shadow map of the scene's directional light (or spot), drawn through the same deferred passes
// from the light's orthographic view over the scene (light_camera; a spot's perspective view,
// spot_camera).
struct ShadowMapSettings {
    int size = 2048;     // texels a side, [16, 8192]
    int pcf_radius = 1;  // the receivers' filter: (2 r + 1)^2 taps, [0, 8]
    // The relief in the map (the light's offset and depth offset) and in the receivers' depth;
    // false: both the base meshes' (a renderer whose shadows know nothing of the relief).
    bool displaced = true;
};

// The shadow map a frame last drew (FrameRenderer::light_maps): the light's view's window depth
// (GL), rows top first, of the base meshes and after the relief's offset.
struct LightMaps {
    int size = 0;
    std::vector<float> base, displaced;
    // The light's view: NDC -> world (column-major; NDC y = +1 at row 0 of these rows).
    std::array<float, 16> inverse_view_projection{};
};

// A scene drawn by the G-buffer raster alone (the truth's displaced meshes, a tessellation level),
// rows top first.
struct GeometryFrame {
    std::vector<float> uv;        // 2 a pixel, NaN where nothing was drawn
    std::vector<float> depth;     // GL window depth, 1 where nothing was drawn
    std::vector<float> material;  // the id a pixel, 0 where nothing or no relief was drawn
    std::vector<float> density;   // uv density (world units per uv unit)
    std::vector<float> normal;    // 3 a pixel: the base mesh's interpolated world normal
    // 3 a pixel where a triplanar truth mesh is drawn (TessellatedMesh::triplanar): the base
    // point its vertices' tangents carry, interpolated; NaN elsewhere.
    std::vector<float> base_point;
    double raster_ms = 0;  // the G-buffer draw, median of the timed ones
};

class FrameRenderer {
  public:
    // Creates the GL context (throws Error naming what is missing), uploads the scene and the
    // materials (`methods`: one per table entry). Rows of every output are top first.
    FrameRenderer(std::shared_ptr<Runtime> runtime, const Scene& scene,
                  const std::vector<LoadedMaterial>& table,
                  const std::vector<MethodParams>& methods, int width, int height,
                  const ShadeSettings& shading);
    ~FrameRenderer();

    // One warm-up frame, then `repeats` timed ones; the last frame's outputs. Each timed frame
    // moves across the host only what an engine's frame would: the G-buffer planes to the device,
    // the colour and the offset pass's t back to GL. Forward needs every material's method to have
    // a GLSL version (forward_unsupported).
    FrameRun render(FrameMode mode, bool prepass, int repeats);
    // After a deferred render: its shade and offset kernels run again `repeats` times on the same
    // buffers, their median kernel times (ms; 0 where events carry no times): a kernel's A/B.
    std::pair<double, double> rerun_kernels(int repeats);
    // The shading of the frames rendered after this call.
    void set_shading(const ShadeSettings& shading);
    // Deferred frames rendered after this call with `on` carry the base's curvature (the raster's
    // seventh target, moved with the other planes) to the offset pass, which then traces the
    // relief over the curved base and flags the rays that leave it SILHOUETTE (docs/design.md);
    // forward frames trace over it in the fragment shader and discard those rays' fragments.
    void set_curvature(bool on);
    // Curved deferred frames rendered after this call with `on` also carry the uv's metric (the
    // G-buffer's uv metric plane: the mesh's dP/du, dP/dv and their rates, drawn in a second
    // pass at GL_EQUAL; docs/design.md, "The uv metric"); off, the curvature plane's stretch
    // alone, as before. Forward frames over the curved base trace with it in the fragment
    // shader; the light's view does not take it.
    void set_uv_metric(bool on);
    // Deferred frames rendered after this call with 2 also draw the G-buffer's second layer
    // (depth peeling: each pixel's nearest surface behind the first, every plane the passes read)
    // and trace it where the first shows nothing of its relief (MaterialFrame's LayerBehind); 1
    // goes back to one layer. Throws Error for another count. The first layer is traced first and
    // the second drawn, moved and reconstructed only at the pixels it left (where none did, not at
    // all); with `whole`, over the whole frame (the same frame, bit for bit, at the whole layer's
    // cost: what an engine pays that draws its layers before it traces).
    void set_layers(int layers, bool whole = false);
    // Deferred frames rendered after this call with settings test each pixel's point against a
    // shadow map of the scene's light (ShadowMaskPass), drawn once a render before its frames,
    // and shade with it beside the self-shadow march (ShadeInputs::shadow_mask); the forward peer
    // has no shadow map. Without settings (the default) frames are as before, bit for bit. Throws
    // Error when the scene's light is neither directional nor a spot, or a setting is out of range.
    void set_shadow_map(const std::optional<ShadowMapSettings>& settings);

    // After a render: the G-buffer as the engine wrote it (depth GL, rows top first, with ids and
    // uv derivatives), its reconstruction, and the depth before the offset.
    const EngineScene& gbuffer() const { return engine_; }
    const GBuffer& explicit_gbuffer() const { return explicit_; }
    const std::vector<float>& depth_before() const { return engine_.depth; }
    size_t covered_pixels() const;
    // The camera's world -> clip matrix (column-major, GL conventions): a shadow map's light view
    // for the receivers' test (ShadowMaskPass).
    std::array<float, 16> view_projection() const;
    // The camera as the device passes take this renderer's planes: GL's depth, rows bottom first
    // (GL's; gbuffer() holds them top first).
    EngineCamera pass_camera() const;
    // After a deferred render with a shadow map: the light's view that frame drew (the map the
    // shading read). Throws Error when no shadow map was drawn.
    LightMaps light_maps() const;
    // This renderer's depth after the offset (a light's renderer: its displaced shadow map), rows
    // bottom first, as the receivers' test reads it (ShadowMaskPass).
    ShadowMapView shadow_map_view(const cl::Buffer& depth) const;
    // "host copies" (and why) or the sharing used between GL and CL.
    const std::string& interop() const { return interop_; }
    std::string gl_renderer() const;
    // The table traced exactly over the deferred G-buffer: every method's reference.
    OffsetResult exact() const;
    // `scene` (this frame's meshes displaced, renderer/truth.hpp) drawn from this frame's camera
    // into the same G-buffer targets: one warm-up draw, then `repeats` timed ones.
    GeometryFrame render_geometry(const Scene& scene, int repeats);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    EngineScene engine_;
    GBuffer explicit_;
    std::string interop_;
};

// Methods the forward shader has (renderer/shaders/relief.glsl): none, parallax, pom, steep (lod
// 0), relief. Empty when supported, else why not.
std::string forward_method_unsupported(const MethodParams& params);
// The same for one material of a table: "" or the one-line error naming the material.
std::string forward_unsupported(const MaterialSpec& material, const MethodParams& params);

}  // namespace offsetmap::renderer

namespace offsetmap::renderer {
// Rows top first to bottom first (GL's, as the kernels of this library take them) or back, `c`
// values a pixel.
std::vector<float> flip_row_order(const std::vector<float>& in, int width, int height, int c = 1);
// One float channel "depth" (rows top first); throws Error naming the file.
void write_depth_exr(const std::string& path, int width, int height,
                     const std::vector<float>& depth);
}  // namespace offsetmap::renderer
