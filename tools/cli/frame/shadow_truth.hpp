// `offsetmap frame --sun --truth`: the frame's shadows against the truth's (frame.json's
// truth.shadow_mismatch).
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <nlohmann/json.hpp>

#include "pictures.hpp"
#include "runs.hpp"

namespace offsetmap::cli {

// The truth's own shadows (renderer::shadow_truth) against three frames rendered for them,
// `flat` (the base meshes' map and depth), `displaced` (the relief in both) and
// `displaced-march` (and the self-shadow march, soft unless --shadows says hard): pixels whose
// lit or shadowed state differs. Leaves the renderer's shading and shadow map as the request
// has them. Adds a mismatch picture per variant to `tiles`.
nlohmann::json shadow_truth_section(const FrameRequest& request, const std::shared_ptr<Runtime>& rt,
                                    FrameRuns& runs, Tiles& tiles);

}  // namespace offsetmap::cli
#endif
