// `offsetmap frame --sun`: the light's view the shown frame drew, as files and tiles: the
// displaced shadow map and the base's (shadow-map.exr, shadow-map-base.exr), the relief's depth
// along the light's rays, and the frame's points against the map (shadow-mask.png).
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <nlohmann/json.hpp>

#include "pictures.hpp"
#include "runs.hpp"

namespace offsetmap::cli {

// frame.json's shadow_map: the sun, the map, the light's passes, the pixels in shadow.
nlohmann::json sun_section(const FrameRequest& request, const FrameRuns& runs, Tiles& tiles);

}  // namespace offsetmap::cli
#endif
