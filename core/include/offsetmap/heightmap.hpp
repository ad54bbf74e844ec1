#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
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

// Which heights a field's buffers hold, shared by every copy of the field. Its generation is a
// number no other field, update or change in this process has had: the passes key what they derive
// from a field (precomputed data, gathered copies) by it, so that neither a released field's
// recycled handle nor heights rewritten in place meet stale data.
class FieldVersion {
  public:
    FieldVersion();  // a new generation
    struct State {
        std::uint64_t generation = 0;
        cl::Event written;  // the last change's completion (null: none since the field was made)
    };
    State state() const;
    // The heights were rewritten, complete with `written`: a new generation.
    void advance(const cl::Event& written);

  private:
    mutable std::mutex mutex_;
    State state_;
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
    // Shared by the field's copies: update() and mark_changed() advance it, and the passes wait
    // for its last change as well as for `ready` (a copy made before an update has the old one).
    std::shared_ptr<FieldVersion> version = std::make_shared<FieldVersion>();
};

// After rewriting a field's buffers itself (heights, mips or normals), the caller marks the field
// changed, with the event the rewrite completes with (null: complete already): `ready` becomes it
// and the version advances, so every pass and material frame holding the field (or a copy of it)
// rebuilds what it derived from the heights on its next enqueue. update() does this itself.
void mark_changed(DeviceHeightField& field, const cl::Event& written = cl::Event());

// What to wait for before reading a field: its `ready` event and its version's last change.
std::vector<cl::Event> field_ready(const DeviceHeightField& field);

// What data derived from a field was made from, for a cache of it: the field's generation, its
// heights buffer (held, so that its handle cannot be given to another buffer while the key lives,
// and a field the caller re-points at another buffer without mark_changed is caught too) and what
// else the data depends on (`detail`: size, settings, parameters).
struct FieldKey {
    std::uint64_t generation = 0;
    cl::Buffer heights;
    std::string detail;
    bool operator==(const FieldKey& o) const {
        return generation == o.generation && heights() == o.heights() && detail == o.detail;
    }
};
FieldKey field_key(const DeviceHeightField& field, const std::string& detail = "");

// Number of levels down to 1 x 1 (at most OM_MAX_MIP_LEVELS) and the floats they take in all.
int mip_level_count(int width, int height);
size_t mip_pyramid_floats(int width, int height, int levels);

// What a field's `heights` buffer holds: its pyramid's floats, and then its words when packed
// (where they start, in words from the buffer's start, is OmOffsetParams::packed_heights: 0
// unless packed).
size_t height_buffer_bytes(const DeviceHeightField& f);
int packed_heights_offset(const DeviceHeightField& f);

}  // namespace offsetmap
