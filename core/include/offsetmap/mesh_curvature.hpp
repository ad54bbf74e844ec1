// The base surface's curvature a vertex, for an engine's mesh import: what the G-buffer's
// curvature plane carries (EngineGBuffer::curvature, docs/design.md "Curved surfaces") once the
// G-buffer pass interpolates it and scales it to uv units.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace offsetmap {

// A triangle mesh as an import holds it: per vertex a position, a normal and a tangent (xyz
// along +u, w the handedness: B = w N x T), each array `stride` bytes from one vertex to the next
// (0: packed floats, 3 or 4 a vertex), so interleaved vertices are read in place; triangles
// counter-clockwise seen from the front, 3 indices each. A uv seam's two sides, separate
// vertices at one place with one normal, are welded for the estimate.
struct CurvatureMesh {
    const float* positions = nullptr;
    std::size_t position_stride = 0;
    const float* normals = nullptr;
    std::size_t normal_stride = 0;
    const float* tangents = nullptr;
    std::size_t tangent_stride = 0;
    std::size_t vertex_count = 0;
    const std::uint32_t* indices = nullptr;
    std::size_t index_count = 0;
};

// Each vertex's second fundamental form in its tangent frame (T, B = w N x T), world units
// (1 / m): k_TT, k_TB, k_BB of dN = K dP, positive where the surface bends away from its normal
// (a sphere seen from outside: 1 / R, 0, 1 / R); zero on a flat mesh and where no face gives an
// estimate. Rusinkiewicz's per-face tensor (the 2 x 2 map of each edge to its normals'
// difference, fitted to the three edges), each face's turned into the vertex's frame and averaged
// by area over the vertices welded with it (at one place within a millionth of the mesh's size,
// normals within 1e-4 radian); a split normal (a hard edge) keeps its sides apart. Exact where the
// normals are a linear function of the position (a sphere's, a cylinder's); first order elsewhere.
// The G-buffer's plane takes it times the uv density (world units per uv unit), with the uv's
// stretch in w. Throws Error for a null array with vertices, an index count not a multiple of 3,
// or an index past the vertices.
std::vector<std::array<float, 3> > derive_curvature(const CurvatureMesh& mesh);

}  // namespace offsetmap
