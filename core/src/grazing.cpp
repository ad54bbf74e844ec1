#include <algorithm>
#include <climits>
#include <cmath>

#include "offsetmap/passes.hpp"

namespace offsetmap {

GrazingRule grazing_rule(const PassSettings& s, int map_w, int map_h) {
    GrazingRule g;
    g.min_vz = static_cast<float>(std::sin(s.min_elevation_deg * M_PI / 180.0));
    if (s.grazing == GrazingPolicy::Cap) {
        // Footprint s |V.xy| / V.z max(W, H) <= cap  <=>  tan(elevation) >= s max(W, H) / cap.
        const double k = s.scale * std::max(map_w, map_h) / s.max_offset_texels;
        g.min_vz = std::max(g.min_vz, static_cast<float>(k / std::sqrt(1.0 + k * k)));
    }
    // A ray spans at most s / min_vz in uv between the top and bottom planes, so it crosses at
    // most that many cell rows plus columns, plus the start cell and rounding.
    const double cells = std::ceil(s.scale / g.min_vz * (map_w + map_h)) + 4.0;
    g.max_cells = static_cast<int>(std::min(cells, static_cast<double>(INT_MAX / 2)));
    return g;
}

}  // namespace offsetmap
