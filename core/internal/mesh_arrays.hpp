// An import's mesh as core's per-vertex helpers read it (derive_curvature, derive_uv_metric):
// arrays at a stride and whole triangles of indices within the vertices.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "offsetmap/error.hpp"

namespace offsetmap {

// Vertex k's floats in an array `stride` bytes a vertex (0: `packed`).
inline const float* strided_row(const float* base, std::size_t stride, std::size_t k,
                                std::size_t packed) {
    return reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) +
                                          k * (stride ? stride : packed));
}

// Throws Error naming `who` for an index count not a multiple of 3, missing indices, or an index
// past the vertices.
inline void check_triangles(const std::string& who, const std::uint32_t* indices,
                            std::size_t index_count, std::size_t vertex_count) {
    if (index_count % 3)
        throw Error(who + ": " + std::to_string(index_count) + " indices are not whole triangles");
    if (index_count && !indices) throw Error(who + ": the indices are missing");
    for (std::size_t i = 0; i < index_count; ++i)
        if (indices[i] >= vertex_count)
            throw Error(who + ": index " + std::to_string(i) + " is " + std::to_string(indices[i]) +
                        ", past the mesh's " + std::to_string(vertex_count) + " vertices");
}

}  // namespace offsetmap
