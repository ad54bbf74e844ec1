// The uv's metric a vertex, for an engine's mesh import: what the G-buffer's uv metric plane
// carries (GBuffer::uv_metric, docs/design.md "The uv metric") once the G-buffer pass
// interpolates it and writes dP/du and dP/dv in the pixel's tangent frame over the uv density.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace offsetmap {

// A triangle mesh as an import holds it: per vertex a position (3 floats) and a uv (2 floats),
// each array `stride` bytes from one vertex to the next (0: packed), 3 indices a triangle.
struct UvMetricMesh {
    const float* positions = nullptr;
    std::size_t position_stride = 0;
    const float* uvs = nullptr;
    std::size_t uv_stride = 0;
    std::size_t vertex_count = 0;
    const std::uint32_t* indices = nullptr;
    std::size_t index_count = 0;
};

struct UvMetricVertex {
    // dP/du and dP/dv, world units per uv unit: each triangle's (the linear map from its uv to
    // its plane), averaged by area over the vertex's triangles (the tangent and bitangent with
    // their lengths, as Lengyel's per-triangle tangents give them).
    std::array<float, 3> dpdu{}, dpdv{};
    // The Christoffel symbols of the uv parametrisation, (uu, uv, vv) for Gamma^u and Gamma^v:
    // Gamma^k_ij = G^-1 (d2P/du_i du_j . dP/du_l), the second derivatives those of the vertices'
    // dP/du and dP/dv interpolated over each triangle, averaged by area over the vertex's
    // triangles. Zero where no triangle gives them (degenerate uv or geometry).
    std::array<float, 3> gamma_u{}, gamma_v{};
};

// Throws Error for a null array with vertices, an index count not a multiple of 3, or an index
// past the vertices. A triangle whose uv or world area is zero gives nothing; a vertex none of
// whose triangles gives anything has zeros, which the pass reads as no metric.
std::vector<UvMetricVertex> derive_uv_metric(const UvMetricMesh& mesh);

}  // namespace offsetmap
