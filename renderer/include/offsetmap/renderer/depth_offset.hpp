// The rendered frame's pixel depth offset on the OpenCL device (kernels/frame/depth_offset.cl):
// GL's window depth moved along each eye ray by the offset pass's t times the uv density.
#pragma once
#include <array>

#include "offsetmap/cl.hpp"
#include "offsetmap/renderer/scene.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap::renderer {

// The kernel's parameters for a width x height frame (GL conventions): the view-projection and
// its inverse (column-major) and the eye: its position, or with `orthographic` (a directional
// light's view) the direction toward it.
OmDepthOffsetParams depth_offset_params(const std::array<float, 16>& view_projection,
                                        const std::array<float, 16>& inverse_view_projection,
                                        const Vec3& eye, int width, int height,
                                        bool orthographic = false);

class DepthOffsetPass {
  public:
    explicit DepthOffsetPass(Runtime& runtime);
    // depth, t and density: one float a pixel, rows bottom first; writes the depth after into
    // `out`. Enqueued on `queue`; returns its event.
    cl::Event enqueue(const cl::CommandQueue& queue, const OmDepthOffsetParams& params,
                      const cl::Buffer& depth, const cl::Buffer& t, const cl::Buffer& density,
                      const cl::Buffer& out);

  private:
    cl::Kernel kernel_;
};

}  // namespace offsetmap::renderer
