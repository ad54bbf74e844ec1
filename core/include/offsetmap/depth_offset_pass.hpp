// The pixel depth offset (kernels/frame/depth_offset.cl): each pixel's window depth moved along
// its eye ray by the offset pass's depth t times the uv density, so that the depth buffer holds
// the relief's surface (what a depth test, a shadow map or a soft particle then sees), in the
// engine camera's conventions.
#pragma once
#include <array>
#include <memory>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap {

struct DepthOffsetInputs {
    int width = 0, height = 0;
    // The frame's camera: its inverse view-projection, eye (or, orthographic, the direction toward
    // it), depth convention and row order, as the reconstruct pass reads them.
    EngineCamera camera;
    // world -> clip (column-major): the inverse of camera.inverse_view_projection, to project the
    // moved point back (checked: their product must be the identity).
    std::array<float, 16> view_projection{};
    cl::Buffer depth;    // float a pixel: window depth, as the engine's depth buffer holds it
    cl::Buffer t;        // float a pixel: the offset pass's depth (OffsetTargets::depth)
    cl::Buffer density;  // float a pixel: uv density, world units per uv unit
};

struct DepthOffsetTargets {
    // float a pixel: the depth after; sky (at or past the far plane) and pixels whose t is 0, NaN
    // or infinite keep theirs bit for bit. May be the input's depth buffer only if no other pass
    // reads that concurrently.
    cl::Buffer depth;
};

class DepthOffsetPass {
  public:
    explicit DepthOffsetPass(std::shared_ptr<Runtime> runtime);
    // Enqueues on `queue` (the runtime's when null) after `wait`; returns the kernel's event.
    // Throws Error naming the input that is missing, too small or inconsistent, before anything
    // is enqueued.
    cl::Event enqueue(const DepthOffsetInputs& in, const DepthOffsetTargets& out,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

  private:
    std::shared_ptr<Runtime> runtime_;
    cl::Kernel kernel_;
};

}  // namespace offsetmap
