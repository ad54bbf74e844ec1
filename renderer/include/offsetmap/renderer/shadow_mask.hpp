// The receivers' shadow test (kernels/frame/shadow_mask.cl): each pixel's point after the depth
// offset against a light's displaced shadow map, percentage-closer filtered with the receiver's
// plane as the bias.
#pragma once
#include <array>

#include "offsetmap/cl.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/shared.h"

namespace offsetmap::renderer {

// The kernel's parameters (GL conventions, rows bottom first): the camera's frame and inverse
// view-projection, the map's size and the light's view-projection (column-major). The slack
// defaults allow a quarter texel of the receiver plane's change and 4e-6 of window depth.
OmShadowMaskParams shadow_mask_params(const std::array<float, 16>& inverse_view_projection,
                                      int width, int height,
                                      const std::array<float, 16>& light_view_projection,
                                      int map_width, int map_height, int pcf_radius = 1,
                                      float slack_texels = 0.25f, float slack_depth = 4e-6f);

class ShadowMaskPass {
  public:
    explicit ShadowMaskPass(Runtime& runtime);
    // depth: the frame's window depth after the offset, one float a pixel; map: the light's,
    // one float a texel; writes the lit fraction of each pixel (1 on sky) into `out`. Throws
    // Error for parameters out of range. Enqueued on `queue`; returns its event.
    cl::Event enqueue(const cl::CommandQueue& queue, const OmShadowMaskParams& params,
                      const cl::Buffer& depth, const cl::Buffer& map, const cl::Buffer& out);

  private:
    cl::Kernel kernel_;
};

}  // namespace offsetmap::renderer
