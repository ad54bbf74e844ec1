// The frames `offsetmap frame` renders for a request: `auto` chosen on the frame's own G-buffer,
// then the deferred frame, over the curved base (--curvature), with the layer behind (--layers
// 2), the sun's shadow map and mask of the shown frame (--sun), and the forward peer (--forward),
// all on one renderer.
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "request.hpp"

namespace offsetmap::cli {

struct FrameRuns {
    std::unique_ptr<renderer::FrameRenderer> renderer;
    std::vector<renderer::FrameRun> runs;  // deferred first; the forward runs from forward_at
    // Per run: the material id each pixel shows.
    std::vector<std::vector<float> > shown_ids;
    size_t shown_at = 0;    // final.png's run: the last deferred one
    size_t forward_at = 0;  // runs.size() without --forward
    // The first deferred frame's G-buffer (as the engine wrote it, and reconstructed) and the
    // table traced exactly over it.
    EngineScene engine;
    GBuffer gb;
    OffsetResult exact;
    size_t covered = 0;
    // With --sun: the shown frame's configuration rendered with the sun's map (the shown run
    // itself with --shadows map): its mask; and the light's maps of that frame.
    std::optional<renderer::FrameRun> sun;
    renderer::LightMaps light_maps;
};

// Renders every run the request asks for, printing auto's choices (into request.methods).
FrameRuns render_runs(FrameRequest& request, const std::shared_ptr<Runtime>& rt);

// A run's name in frame.json: `deferred` (the tangent plane), `deferred-curved`,
// `deferred-two-layers`, `forward`, `forward-prepass`.
std::string run_name(const renderer::FrameRun& r);

}  // namespace offsetmap::cli
#endif
