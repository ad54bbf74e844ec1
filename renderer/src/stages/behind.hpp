// The layer-behind stage: the G-buffer's second layer (depth peeling: each pixel's nearest surface
// behind the first), drawn, moved and reconstructed only where the first layer's trace left its
// pixels to what lies behind (OM_FLAGS_SEE_BEHIND: a ray that left the curved base, a tile mask's
// discard), traced there by the material frame (MaterialFrame::enqueue_behind), and the surface
// shown taken into the first layer's planes: what an engine that draws its second layer on demand
// runs after its first layer's offset pass.
#pragma once
#include <cstdint>
#include <vector>

#include "../raster.hpp"
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/material_frame.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/timing.hpp"
#include "planes.hpp"

namespace offsetmap::renderer {

// The first layer as the stage reads and amends it.
struct FirstLayer {
    const Raster& raster;          // its last draw (the peel's depth)
    const EngineGBuffer& engine;   // the planes its reconstruct read
    const DeviceGBuffer& gbuffer;  // its explicit G-buffer (BEHIND pixels take the second's)
    const OffsetTargets& targets;  // its offset (flags read; BEHIND pixels take the second's)
    const GBufferPlanes& planes;   // its depth and uv density take the second's where BEHIND
};

class BehindStage {
  public:
    // The camera's GL context must be current.
    BehindStage(Runtime& runtime, const Scene& scene, int width, int height, bool lit);

    // After the first layer's trace was enqueued (`clock` started with it): its flags read, the
    // second layer drawn, moved, reconstructed and traced at the pixels that need it (every pixel
    // with `whole`; none drawn where none needs it). Blocking; adds each pass's time to its
    // column of `t`, the first layer's trace to the offset's. `metric`: with its uv metric.
    void trace(const View& view, const FirstLayer& first, ReconstructPass& reconstruct,
               MaterialFrame& frame, bool curved, bool metric, bool whole, Stopwatch& clock,
               PassTimes& t);

  private:
    Runtime& rt_;
    int width_, height_;
    Raster raster_;
    GBufferPlanes planes_;
    DeviceGBuffer dg_;
    OffsetTargets targets_;
    std::vector<std::uint32_t> flags_, needed_;
};

}  // namespace offsetmap::renderer
