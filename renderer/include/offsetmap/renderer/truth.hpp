// The surface the relief describes, as geometry: each relief mesh tessellated and displaced along
// its interpolated normal by (uv density) x s x (H - r), H sampled as the passes sample it
// (bilinear between texel centres, the material's address mode; a triplanar material's H the
// blend of its projections' heights), for the G-buffer raster to draw
// as it draws the base meshes. The truth frame every frame is measured against, and tessellation
// as the pixel methods' competitor (docs/design.md, "The displaced mesh").
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/material_table.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/scene.hpp"

namespace offsetmap::renderer {

struct TessellationOptions {
    // The lattice's spacing in texels: vertices on the lines through texel centres every
    // `texels_per_quad` texels (two triangles a lattice cell). Below 1 each bilinear cell is cut
    // into (1 / texels_per_quad)^2 quads; 1 / texels_per_quad must then be a whole number.
    float texels_per_quad = 0.5f;
    // The most triangles kept (after culling) over all meshes: more is an Error naming the mesh.
    size_t max_triangles = 60'000'000;
    // Cull what the camera of a width x height frame cannot see (outside the frustum, facing
    // away): the tessellation of one view. 0 x 0: keep everything.
    int width = 0, height = 0;
    // Keep the triangles facing away from that camera (a light's view: their backs cast shadows).
    bool keep_back_faces = false;
};

struct TessellatedMesh {
    std::string name;
    int material = 0;
    size_t base_triangles = 0;
    size_t triangles = 0;          // kept
    float texels_per_quad = 0.0f;  // its lattice (0: not tessellated)
    // The displaced surface's bound on |tessellated - bilinear| heights, in H units, where every
    // piece lies in one bilinear cell (texels_per_quad <= 1): the map's largest bilinear twist
    // |H00 - H10 - H01 + H11| times texels_per_quad^2 / 4 (truth_bound_texels takes the twists
    // along each ray); NaN for coarser lattices, meshes without relief and triplanar meshes.
    double height_bound = 0.0;
    // A triplanar material's: cut along the world's lattice planes through every projection's
    // texel centres, displaced by the blended height; its vertices' tangents carry their base
    // points (xyz), from which triplanar_truth_uv projects a pixel's uv.
    bool triplanar = false;
};

struct Tessellation {
    Scene scene;  // the relief meshes displaced, the others as they were
    std::vector<TessellatedMesh> meshes;
    size_t triangles = 0;  // every mesh's, relief or not
    size_t bytes = 0;      // vertex and index bytes
    double build_ms = 0;
};

// The scene's relief meshes (a material id the table lists) tessellated and displaced; `table` as
// loaded for the frame. Throws Error naming the mesh and the triangles it would need when they
// pass options.max_triangles, and for a texels_per_quad the lattice cannot take.
Tessellation displace_scene(const Scene& scene, const std::vector<LoadedMaterial>& table,
                            const TessellationOptions& options);

// What a frame shows per pixel, rows top first: the G-buffer's material id, uv' (the offset
// pass's, or the forward shader's), the window depth after the pixel depth offset (GL's
// convention) and the pass's flags (OM_FLAGS_NOT_SHOWN: nothing of the relief shown there).
struct ShownFrame {
    std::string mode;
    const std::vector<float>* material = nullptr;
    const std::vector<cl_float2>* uv = nullptr;
    const std::vector<float>* depth = nullptr;
    const std::vector<std::uint32_t>* flags = nullptr;
    const std::vector<float>* normal = nullptr;  // 3 a pixel where the frame is geometry, or null
};

struct ErrorSummary {
    double mean = 0, p95 = 0, max = 0;
};

// A frame against the truth: per pixel where both show the same relief material, the uv distance
// in that material's texels and the distance between the two surface points in world units;
// pixels that show relief in one and something else (another material, no relief, nothing) in
// the other, within 2 pixels of a base-mesh silhouette or tile-mask edge (the band) or not.
struct TruthComparison {
    std::string mode;
    size_t compared_pixels = 0;
    ErrorSummary uv_err_texels, depth_err;
    size_t mismatch = 0, mismatch_band = 0, mismatch_interior = 0;
    std::vector<float> uv_error;           // texels a pixel, NaN where not compared
    std::vector<std::uint8_t> mismatched;  // 1 where coverage differs
};

// A triplanar material has three uv: the truth's at each pixel is projected into the one the
// frame's G-buffer gives the pixel first (`first`: FrameRun::first_projection, rows top first),
// world_scale (P.T, P.B) of the base point P it shows (GeometryFrame::base_point). Where the frame
// gives none (it shows no triplanar pixel there) the truth keeps its own: the largest projection
// at the point. Without base points, the truth as it is.
GeometryFrame triplanar_truth_uv(GeometryFrame truth, const std::vector<std::int8_t>& first,
                                 const std::vector<LoadedMaterial>& table);

// The pixels within 2 of a base-mesh silhouette (the material changes, sky begins, or the window
// depth steps by 4 times the steps beside it) or of a tile-mask or silhouette edge (`flags`
// changes), rows top first.
std::vector<std::uint8_t> silhouette_band(const std::vector<float>& base_material,
                                          const std::vector<float>& base_depth,
                                          const std::vector<std::uint32_t>& flags, int width,
                                          int height);

// `base`: the frame's explicit G-buffer (uv and tangent-space V of the base meshes, and their
// material ids), window depth and world normals (4 a pixel): a pixel where the truth shows a
// surface within the relief's reach of the base (in uv and along the ray, facing within 45 degrees
// of it) and the frame one beyond it, or the other way (the same material on another face), counts
// as a coverage mismatch too. Where the base shows another material than the one both show (a
// layer behind), the base says nothing of their surface: they are the same surface when their
// points lie within the relief's reach of each other along the ray (at the truth normal's angle).
TruthComparison compare_to_truth(const GeometryFrame& truth, const ShownFrame& frame,
                                 const GBuffer& base, const std::vector<float>& base_depth,
                                 const std::vector<float>& base_normal,
                                 const std::vector<std::uint8_t>& band,
                                 const std::vector<LoadedMaterial>& table,
                                 const std::array<float, 16>& inverse_view_projection, int width,
                                 int height);

// The truth's own bound per pixel, in texels of the pixel's material (NaN where no relief): the
// distance along the pixel's tangent-space ray between its first hits with the height field
// raised and lowered by the tessellation's height bound over the cells the ray crosses (the
// tessellated surface lies between them, so its hit lies between theirs; exact on a flat mesh, to
// first order on a curved one).
std::vector<float> truth_bound_texels(const GBuffer& gbuffer, const std::vector<float>& material,
                                      const std::vector<LoadedMaterial>& table,
                                      const Tessellation& truth);

// The shadows of the surface the relief describes: the displaced meshes tessellated at one lattice
// for both views (culled to the camera's, and to the light's with their backs kept: they cast),
// drawn from the camera (`camera`'s view, width x height, the receivers) and from the scene's
// directional light into their own shadow map of map_size^2 texels (the casters), each receiver
// tested against it as a frame's are (ShadowMaskPass, pcf_radius). One lattice for both, since
// two would disagree by their tessellation errors and shadow each other. Per pixel (rows top
// first) the lit fraction, NaN where the truth shows nothing, and the base normal (3 a pixel).
struct ShadowTruth {
    std::vector<float> lit, normal;
    size_t triangles = 0;  // the light's view's
    double ms = 0;         // tessellation, raster and test, wall clock
};
ShadowTruth shadow_truth(const std::shared_ptr<Runtime>& runtime, FrameRenderer& camera,
                         const Scene& scene, const std::vector<LoadedMaterial>& table,
                         const std::vector<MethodParams>& methods, int width, int height,
                         int map_size, int pcf_radius, float texels_per_quad);

// A frame's light visibility (rows top first) against the truth's: the pixels where one is lit
// (visibility >= 1/2) and the other not, among those both show (the frame's window depth below 1,
// the truth's lit not NaN) whose base normal faces the light (n . toward > 0: a surface facing
// away is dark whatever the shadows say). `mismatched` marks them, if given.
struct ShadowMismatch {
    size_t compared = 0, mismatch = 0;
};
ShadowMismatch shadow_mismatch(const ShadowTruth& truth, const std::vector<float>& visibility,
                               const std::vector<float>& depth,
                               const std::array<float, 3>& toward_light,
                               std::vector<std::uint8_t>* mismatched = nullptr);

}  // namespace offsetmap::renderer
