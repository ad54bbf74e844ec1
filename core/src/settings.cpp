// A pass's settings: their ranges, and the kernel parameters they give.
#include "offsetmap/settings.hpp"

#include <algorithm>
#include <cfloat>
#include <sstream>

#include "offsetmap/error.hpp"

namespace offsetmap {

std::array<float, 4> kernel_tile_bounds(const PassSettings& s) {
    std::array<float, 4> b = s.tile_bounds;
    // Finite stand-ins for the open sides: a program built for finite math keeps its compares.
    for (float& x : b) x = std::max(-FLT_MAX, std::min(FLT_MAX, x));
    return b;
}

OmOffsetParams offset_params(const PassSettings& s, int hf_w, int hf_h, int gb_w, int gb_h) {
    OmOffsetParams p{};
    p.gb_width = gb_w;
    p.gb_height = gb_h;
    p.hf_width = hf_w;
    p.hf_height = hf_h;
    p.address_mode = static_cast<om_int>(s.address);
    p.scale = s.scale;
    p.ref_plane = s.reference_plane;
    const GrazingRule g = grazing_rule(s, hf_w, hf_h);
    p.min_vz = g.min_vz;
    p.grazing = static_cast<om_int>(s.grazing);
    p.max_cells = g.max_cells;
    p.tile_mask = s.out_of_tile_mask ? 1 : 0;
    const std::array<float, 4> tile = kernel_tile_bounds(s);
    p.tile_u0 = tile[0];
    p.tile_v0 = tile[1];
    p.tile_u1 = tile[2];
    p.tile_v1 = tile[3];
    p.mip_levels = 1;
    p.lod_threshold = s.lod.threshold;
    p.lod_fade = s.lod.fade;
    p.lod_min_detail = s.lod.min_detail;
    p.lod_footprint = s.lod.footprint ? 1 : 0;
    p.lod_fade_lo = s.lod.fade_texels_lo;
    p.lod_fade_hi = s.lod.fade_texels_hi;
    return p;
}

void validate(const PassSettings& s) {
    auto range = [](const char* name, float v, float lo, float hi) {
        if (!(v >= lo && v <= hi)) {
            std::ostringstream m;
            m << name << " must be in [" << lo << ", " << hi << "], got " << v;
            throw Error(m.str());
        }
    };
    range("scale", s.scale, 0.0f, 1.0f);
    range("reference plane", s.reference_plane, 0.0f, 1.0f);
    range("minimum elevation (degrees)", s.min_elevation_deg, 0.1f, 89.0f);
    range("maximum offset (texels)", s.max_offset_texels, 1.0f, 1.0e6f);
    const std::array<float, 4>& t = s.tile_bounds;
    for (int axis = 0; axis < 2; ++axis) {
        if (!(t[axis] < t[axis + 2])) {
            std::ostringstream m;
            m << "tile bounds must have "
              << "uv"[axis] << "_min < "
              << "uv"[axis] << "_max (infinite for an open side), got [" << t[axis] << ", "
              << t[axis + 2] << "]";
            throw Error(m.str());
        }
    }
    if (s.lod.enabled) {
        range("LOD threshold", s.lod.threshold, 0.5f, 16.0f);
        if (!(s.lod.fade > 0.0f && s.lod.fade <= s.lod.threshold))
            throw Error("LOD fade must be in (0, threshold], got " + std::to_string(s.lod.fade));
        if (!(s.lod.fade_texels_lo >= 0.0f && s.lod.fade_texels_hi > s.lod.fade_texels_lo))
            throw Error("LOD fade texel range must satisfy 0 <= low < high, got [" +
                        std::to_string(s.lod.fade_texels_lo) + ", " +
                        std::to_string(s.lod.fade_texels_hi) + "]");
        if (!(s.lod.min_detail > 0.0f && s.lod.min_detail <= 1.0f))
            throw Error("LOD minimum detail must be in (0, 1], got " +
                        std::to_string(s.lod.min_detail));
    }
}

}  // namespace offsetmap
