#pragma once
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"

namespace offsetmap {

class Runtime;

// The most texels a height map may have: the kernels index a field's texels with 32-bit ints, its
// mip pyramid (4/3 of level 0) included.
inline constexpr long long kMaxHeightTexels = 1ll << 28;

// Heights H in [0,1], 1 = highest, row 0 first: texel (i, j) is h[j * width + i] and has its
// centre at uv = ((i + 0.5) / width, (j + 0.5) / height).
struct HeightMap {
    int width = 0;
    int height = 0;
    std::vector<float> h;
    int clamped = 0;  // texels that were outside [0,1] in the file and were clamped

    float at(int i, int j) const { return h[static_cast<size_t>(j) * width + i]; }
};

// Checks the map (non-empty, sizes agree, finite, in [0,1]); throws Error naming `what`.
void validate_height_map(const HeightMap& map, const std::string& what);

// An RGB(A) image as linear float4 texels (for albedo and normal maps).
struct Image4 {
    int width = 0;
    int height = 0;
    std::vector<cl_float4> texels;
};

// A height map and its derived data on one device.
struct DeviceHeightField {
    int width = 0;
    int height = 0;
    int mip_levels = 1;  // levels in `heights`: level k is max(1, W >> k) x max(1, H >> k)
    cl::Buffer heights;  // float per texel, level 0 first, then each coarser level
    // The heights are multiples of 1/65535 (HeightStorage::Unorm16) and `heights` holds after the
    // floats one word per texel of every level, in the same order: the texel's unorm16 value in
    // the low half, the one below it, (i, j + 1) or the last row again, in the high half.
    bool packed = false;
    cl::Buffer normals;  // float4 per texel of level 0 (derived on the device, or from a file)
    // Complete once heights, mips and normals are on the device; the passes wait for it (a null
    // event: ready already). A caller filling the buffers itself sets it, or leaves it null.
    cl::Event ready;
};

// Number of levels down to 1 x 1 (at most OM_MAX_MIP_LEVELS) and the floats they take in all.
int mip_level_count(int width, int height);
size_t mip_pyramid_floats(int width, int height, int levels);

// What a field's `heights` buffer holds: its pyramid's floats, and then its words when packed
// (where they start, in words from the buffer's start, is OmOffsetParams::packed_heights: 0
// unless packed).
size_t height_buffer_bytes(const DeviceHeightField& f);
int packed_heights_offset(const DeviceHeightField& f);

}  // namespace offsetmap
