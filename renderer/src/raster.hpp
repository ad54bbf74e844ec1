// The GL side of a frame: the scene's meshes on the GPU (or llvmpipe), the G-buffer pass into
// float render targets (deferred, or forward with each material's method in the fragment shader),
// an optional depth pre-pass, fragment-shader invocation counts, and the frame's results written
// back (colour, and the depth after the pixel depth offset).
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "gl.hpp"
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/renderer/scene.hpp"
#include "offsetmap/settings.hpp"
#include "offsetmap/triplanar.hpp"

namespace offsetmap::renderer {

// A material as the forward shader traces it (uniforms and the height texture).
struct ForwardMaterial {
    int id = 0;
    Texture heights;  // R32F, level 0, linear filtering, repeat or clamp-to-edge
    int method = 0;   // glsl_method: its OM_GLSL_* (renderer/shaders/relief.glsl)
    std::array<float, 4> params{};
    float scale = 0.0f, ref = 1.0f, min_vz = 0.0f;
    bool limit = false;
    bool tile_mask = false;  // forward discards fragments whose uv' leaves the tile:
    std::array<float, 4> tile_bounds{0.0f, 0.0f, 1.0f, 1.0f};  // PassSettings::tile_bounds
    // A triplanar material: world_scale, sharpness, cutoff, 1 (else zeros).
    std::array<float, 4> triplanar{};
};

// The value relief.glsl's u_method takes for a method with a GLSL version (its registry row's
// `glsl`), else -1; and the defines that name those values, OM_GLSL_<glsl> (every shader's).
int glsl_method(const MethodInfo& method);
std::string glsl_method_defines();
// The height texture and uniforms that trace `method` on `map` with `settings`, as the kernels
// do (the same parameters in registry order, grazing rule and address mode).
ForwardMaterial forward_material(int id, const HeightMap& map, const PassSettings& settings,
                                 const MethodParams& method, const Triplanar& triplanar = {});
// Sets relief.glsl's uniforms on the current program `p` (u_method none's, no relief, for null) and
// binds the height texture to unit 0.
void bind_forward_material(const Program& p, const ForwardMaterial* fm);

// The G-buffer's planes as read back: rows bottom first (GL's), floats.
struct RasterPlanes {
    std::vector<float> depth;     // window depth, 1 per pixel
    std::vector<float> normal;    // 4 (world normal, 0)
    std::vector<float> tangent;   // 4 (world tangent, handedness)
    std::vector<float> uv;        // 2
    std::vector<float> material;  // 2: id, uv density
    std::vector<float> offset;    // forward: 4 (uv', t, fetches); empty otherwise
};

// Where read_into puts each plane (GL's rows, bottom first): depth 1, normal 4, tangent 4, uv 2,
// material id 1 and uv density 1 floats a pixel; the curvature 4 (k_uu, k_uv, k_vv, 0), read only
// where given (after a draw with `curvature`).
struct PlanePointers {
    float* depth = nullptr;
    float* normal = nullptr;
    float* tangent = nullptr;
    float* uv = nullptr;
    float* material = nullptr;
    float* density = nullptr;
    float* curvature = nullptr;
};

struct View {
    std::array<float, 16> view_projection{};          // column-major
    std::array<float, 16> inverse_view_projection{};  // column-major
    Vec3 eye{};  // the eye's position, or (orthographic) the unit direction toward it
    bool orthographic = false;
    // A light's view: back faces drawn too (a single-sided wall the light sees from behind still
    // casts; the offset pass flags them BACKFACING and leaves their depth).
    bool two_sided = false;
};
View make_view(const Camera& camera, int width, int height);

class Raster {
  public:
    Raster(const Scene& scene, int width, int height);

    // Draws the G-buffer (forward: with `materials` traced per fragment; a material missing from
    // the list is drawn without relief). With `prepass`, depth first and then the G-buffer at
    // GL_EQUAL. Blocks until GL is done.
    // The uv derivatives' target is filled only with `derivatives` (read_uv_derivatives), the
    // curvature's only with `curvature` (read_curvature). With `curved` forward traces over the
    // curved base and discards the rays that leave it, as the tile mask's.
    void draw(const View& view, const std::vector<ForwardMaterial>* forward, bool prepass,
              bool derivatives = false, bool curvature = false, bool curved = false);
    // The draws after this call clear and write only `region` (GL's rows, bottom first): the rest
    // of every target keeps what it holds. Null: the whole frame again.
    void set_scissor(const PixelRegion* region);
    // The G-buffer's second layer (deferred): at each pixel the nearest surface behind `front`'s
    // last draw (depth peeling against its depth target), into this raster's targets; `front`
    // draws the same scene at the same size. With `pixels` (indices in GL's rows, bottom first)
    // only those: no target is cleared elsewhere, the peel's test runs in a depth-only pass and
    // the G-buffer's fragments meet its depth at GL_EQUAL, so a layer needed along the
    // silhouettes costs about their fragments and the box's rasterization, not the frame's.
    void draw_behind(const View& view, const Raster& front, bool curvature,
                     const std::vector<std::uint32_t>* pixels = nullptr);
    // The same draw with the fragments that pass the depth test counted (an atomic counter in a
    // variant of the shader, so the timed draws carry no counter): the fragments the G-buffer
    // shader, and forward the method, runs on.
    std::int64_t count_fragments(const View& view, const std::vector<ForwardMaterial>* forward,
                                 bool prepass, bool curved = false);
    // The last draw's planes the passes read (forward's offset plane only after a forward draw).
    RasterPlanes read(bool forward) const;
    // The forward draw's offset plane: 4 per pixel (uv', t, fetches).
    std::vector<float> read_offset() const;
    // Forward, triplanar pixels: the y and z axes' projections' uv' (read_offset's xy is the x
    // axis's), each traced where its weight is not 0 and its uv elsewhere.
    std::vector<float> read_offset_yz() const;
    // The same planes straight into the caller's memory (mapped OpenCL buffers: one copy), the
    // material target's id and uv density as a plane each; with `regions` (rows in GL's order,
    // bottom first), only their pixels.
    void read_into(const PlanePointers& planes,
                   const std::vector<PixelRegion>* regions = nullptr) const;
    // The uv derivatives of the last draw with `derivatives`, 4 per pixel: du/dx, dv/dx, du/dy,
    // dv/dy (rows bottom first); the G-buffer file keeps them, the passes do not read them.
    std::vector<float> read_uv_derivatives() const;
    // The curvature of the last draw with `curvature`, 4 per pixel (rows bottom first): the base
    // surface's k_uu, k_uv, k_vv in the pixel's tangent frame, uv units, and the uv's stretch; 0
    // where nothing was drawn.
    std::vector<float> read_curvature() const;
    // The uv metric's planes for the last draw (draw or draw_behind): drawn again at GL_EQUAL on
    // its depth (uv_metric_frag.glsl), so the G-buffer's eight targets keep their layout. Blocks.
    void draw_metric(const View& view);
    // After draw_metric: 12 floats a pixel as the offset pass's three planes of width * height
    // (rows bottom first), 0 where nothing was drawn; into `out` (with `regions`: only theirs).
    std::vector<float> read_metric() const;
    void read_metric_into(float* out, const std::vector<PixelRegion>* regions = nullptr) const;
    // Forward draws over the curved base after this call with `on` trace with the uv metric too
    // (the fragment's interpolated dP/du, dP/dv and symbols, as draw_metric writes them).
    void set_forward_metric(bool on) { forward_metric_ = on; }
    // The frame's results into GL (rows bottom first): the colour (4 floats a pixel) into the
    // colour texture, the depth after the pixel depth offset into the second depth target, which
    // depth_after() reads. Blocks until GL has them.
    void write_results(const float* color, const float* depth_after);
    std::vector<float> depth_after() const;

  private:
    struct DrawMesh {
        int material = 0;
        VertexArray vao;
        BufferObject vertices, indices;
        GLsizei count = 0;
    };
    int width_, height_;
    std::vector<DrawMesh> meshes_;
    std::optional<PixelRegion> scissor_;
    bool forward_metric_ = false;
    // `curved`: forward traces over the curved base (relief.glsl's curvature). Without `clear`
    // the targets keep what the caller put there.
    void draw_with(const View& view, const std::vector<ForwardMaterial>* forward, bool prepass,
                   const Program& program, bool curved, bool clear = true,
                   const Program* prepass_program = nullptr);
    Program deferred_, forward_, deferred_count_, forward_count_, depth_only_, deferred_peel_,
        peel_mask_, peel_depth_, metric_program_;
    VertexArray mask_vao_;
    BufferObject mask_pixels_;  // draw_behind's pixels, in runs along their rows
    bool peel_closed_ = false;  // the depth is 0 but at the last draw_behind's open_runs_
    GLsizei open_runs_ = 0;
    Texture depth_, normal_, tangent_, uv_, derivatives_, material_, offset_, offset2_, curvature_,
        color_, depth_after_, metric_[3];
    Framebuffer fbo_, depth_fbo_, metric_fbo_;
    BufferObject counter_;
};

}  // namespace offsetmap::renderer
