// `offsetmap frame --truth`: the relief meshes tessellated and displaced for real, drawn from the
// frame's camera, and every run measured against them; coarser tessellations and the per-pixel
// methods costed beside them (frame.json's truth, truth-*.png, coverage-*.png).
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <nlohmann/json.hpp>

#include "pictures.hpp"
#include "runs.hpp"

namespace offsetmap::cli {

nlohmann::json truth_section(const FrameRequest& request, const std::shared_ptr<Runtime>& rt,
                             FrameRuns& runs, Tiles& tiles);

}  // namespace offsetmap::cli
#endif
