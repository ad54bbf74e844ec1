// The light stage: the scene from its light's view (a directional light's orthographic view,
// light_camera; a spot's perspective one, spot_camera) through the deferred
// passes that make its depth, and nothing else: the G-buffer drawn, its planes moved to the
// device, reconstructed, offset by every pixel's material and moved along the light's rays by the
// depth offset. That depth is the displaced shadow map (or, flat, the base's depth before the
// offset) the receivers' test reads. No shading, nothing read back; drawn once a camera frame, on
// the camera's GL context and OpenCL queue, with the table's fields as the camera's frame holds
// them.
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include "../raster.hpp"
#include "offsetmap/depth_offset_pass.hpp"
#include "offsetmap/material_frame.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/shadow_mask_pass.hpp"
#include "planes.hpp"

namespace offsetmap::renderer {

class LightStage {
  public:
    // `scene`'s light must be directional or a spot (FrameRenderer::set_shadow_map checks it);
    // `materials`
    // the camera's frame's (their fields shared). The camera's GL context must be current.
    LightStage(std::shared_ptr<Runtime> runtime, const Scene& scene,
               const std::vector<FrameMaterial>& materials, int size);

    // Draws the map (blocking); with `curved`, each ray over the base's curvature as the camera's.
    // Bit for bit the whole map's draw: the texels outside the scene's box hold the empty
    // map's values each time.
    // The times of its passes (shade and to_gl 0; total their sum).
    PassTimes draw(ReconstructPass& reconstruct, bool curved);
    // The map the last draw made: displaced (after the offset) or the base's depth.
    ShadowMapView map(bool displaced) const;
    int size() const { return size_; }

  private:
    // `lit`: the scene seen from its light (light_camera); the last argument only tells the two
    // constructors apart.
    LightStage(std::shared_ptr<Runtime> runtime, const Scene& lit,
               const std::vector<FrameMaterial>& materials, int size, int);

    std::shared_ptr<Runtime> rt_;
    int size_;
    View view_;
    // The map's texels the scene's meshes can cover (their vertices' bounding box, a texel
    // around; GL's rows): after a first whole draw (and whenever the curvature plane joins) only
    // they are cleared, drawn, moved and reconstructed; the rest keeps the empty map's values.
    PixelRegion covered_;
    bool whole_drawn_ = false, whole_curved_ = false;
    Raster raster_;
    GBufferPlanes planes_;
    DeviceGBuffer dg_;
    OffsetTargets targets_;
    MaterialFrame frame_;
    std::optional<TriplanarPlanes> triplanar_;
    DepthOffsetPass depth_offset_;
    cl::Buffer depth_after_;
};

}  // namespace offsetmap::renderer
