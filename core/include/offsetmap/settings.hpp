// A pass's settings (the relief's placement, the grazing rule, LOD) and what they give the kernels.
#pragma once
#include <array>

#include "offsetmap/shared.h"

namespace offsetmap {

// The host's names for the shared header's OM_* constants (the kernels read the constants).
enum class AddressMode : om_int { Wrap = OM_ADDRESS_WRAP, Clamp = OM_ADDRESS_CLAMP };
enum class GrazingPolicy : om_int {
    Clamp = OM_GRAZING_CLAMP,
    Limit = OM_GRAZING_LIMIT,
    Cap = OM_GRAZING_CAP
};
// How upload() keeps a field's heights for the passes (PassSettings::heights).
enum class HeightStorage : om_int { Auto, Float, Unorm16 };
enum class ShadowMode : om_int {
    None = OM_SHADOW_NONE,
    Hard = OM_SHADOW_HARD,
    Soft = OM_SHADOW_SOFT
};

// Tatarchuk's level-of-detail system (off by default). The per-pixel mip level m comes from the
// G-buffer's lod buffer, or from the uv footprint between neighbouring pixels when it has none.
// Heights are read at level floor(m), step counts scale by mix(1, min_detail, m / threshold), and
// the offset fades to plain normal mapping over `fade` levels below `threshold`.
// Footprint mode (footprint = true) keeps the per-pixel level and the height reads but caps each
// method's step count at the texels of that level the ray's footprint crosses (plus one) and fades
// to normal mapping as that count falls from fade_texels_hi to fade_texels_lo.
struct LodSettings {
    bool enabled = false;
    float threshold = 4.0f;    // mip level at and past which uv' = uv, [0.5, 16]
    float fade = 1.0f;         // (0, threshold]
    float min_detail = 0.25f;  // (0, 1]
    bool footprint = false;
    float fade_texels_lo = 0.5f;  // [0, fade_texels_hi)
    float fade_texels_hi = 2.0f;
};

// The relief's placement (docs/design.md, conventions): surface z = scale * (H - reference_plane),
// in uv units.
struct PassSettings {
    float scale = 0.05f;             // depth scale s, in uv units, [0, 1]
    float reference_plane = 1.0f;    // r in [0,1]: the polygon's height
    float min_elevation_deg = 1.0f;  // grazing rule: views lower than this are raised to it
    AddressMode address = AddressMode::Wrap;
    LodSettings lod;
    // What happens at grazing views (GrazingPolicy, OM_GRAZING_*; bounded loops, finite outputs):
    //  Clamp: views below min_elevation_deg are traced at that elevation (the default).
    //  Limit: Welsh's offset limiting for every method: rays along normalize(V.x, V.y, 1), so an
    //         offset never exceeds the depth it crosses (biased at every view but straight down).
    //  Cap:   a march-length cap: the ray's footprint through the whole slab is at most
    //         max_offset_texels, i.e. views are raised to atan(s max(W, H) / max_offset_texels).
    GrazingPolicy grazing = GrazingPolicy::Clamp;
    float max_offset_texels = 32.0f;  // Cap policy: longest footprint of a ray, [1, 1e6]
    // Flag pixels whose uv' leaves the tile (OM_FLAG_OUT_OF_TILE), for silhouettes on non-tiling
    // (clamped) surfaces and at a mesh's open edges; the shade pass draws them as background.
    bool out_of_tile_mask = false;
    // The tile the mask keeps: u_min, v_min, u_max, v_max (a surface's uv range, [0,1]^2 for one
    // uv square); an infinite side is open (a cylinder's u, which runs around it).
    std::array<float, 4> tile_bounds{0.0f, 0.0f, 1.0f, 1.0f};
    // How upload() stores a field's heights, which every pass then reads (docs/design.md,
    // "Height storage"):
    //  Float:   a float per texel.
    //  Unorm16: every level rounded to the nearest multiple of 1/65535 (|change| <= 0.5 / 65535)
    //           and, beside the floats, packed so a bilinear patch is one 64-bit read; the passes
    //           then run on the rounded heights exactly as on a float field holding them.
    //  Auto:    Unorm16 where it loses nothing: level 0 already holds multiples of 1/65535 (8- and
    //           16-bit maps, unorm buffers), else Float.
    HeightStorage heights = HeightStorage::Auto;
};

// Throws Error naming the setting that is out of range.
void validate(const PassSettings& settings);

// The grazing rule and the march cap, derived once (core/src/grazing.cpp) for the offset pass, the
// shade pass (the light obeys the view's rule), the oracle and the tests.
struct GrazingRule {
    // Views with a lower V.z are flagged GRAZING and, but under Limit, raised to it (same
    // azimuth). sin(min_elevation_deg), raised by the Cap policy so that a footprint through the
    // whole slab spans at most max_offset_texels. A float, as the kernels compare it.
    float min_vz = 0.0f;
    // The most cells a ray's footprint crosses between the top and bottom planes (it spans at
    // most s / min_vz in uv), plus the start cell and rounding: every cell walk's hard cap.
    int max_cells = 0;
};
GrazingRule grazing_rule(const PassSettings& settings, int map_w, int map_h);

// The kernel parameters a pass with these settings uses over a hf_w x hf_h height map (grazing
// rule, march cap, LOD) and a gb_w x gb_h G-buffer (0 x 0 for kernels that read none); method
// parameters and mip levels are the caller's to fill in.
OmOffsetParams offset_params(const PassSettings& settings, int hf_w, int hf_h, int gb_w = 0,
                             int gb_h = 0);

// The tile bounds as the kernels and shaders take them: an open side as -+FLT_MAX.
std::array<float, 4> kernel_tile_bounds(const PassSettings& settings);

}  // namespace offsetmap
