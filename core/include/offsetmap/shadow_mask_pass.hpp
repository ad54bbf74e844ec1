// The receivers' shadow test (kernels/frame/shadow_mask.cl): each pixel's point after the depth
// offset against a light's displaced shadow map, percentage-closer filtered with the receiver's
// own plane as the bias. The map is the light's view of the same passes: its G-buffer, the offset
// and the depth offset (DepthOffsetPass) in the light's camera.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap {

// A light's shadow map: its window depth a texel and the view that drew it.
struct ShadowMapView {
    int width = 0, height = 0;
    // The light's camera (orthographic for a directional light, perspective for a spot): its
    // depth convention and row order; its inverse_view_projection is not read.
    EngineCamera camera;
    std::array<float, 16> view_projection{};  // world -> the light's clip space, column-major
    cl::Buffer depth;                         // float a texel
};

struct ShadowMaskInputs {
    int width = 0, height = 0;
    EngineCamera camera;  // the frame's: inverse view-projection, depth convention, row order
    cl::Buffer depth;     // float a pixel: the frame's window depth after the depth offset
    ShadowMapView map;
    int pcf_radius = 1;  // (2 r + 1)^2 taps, [0, 8]
    // Lit within a quarter texel of the receiver plane's change (what bends between pixels), and
    // 4e-6 of window depth (the points' float rounding); [0, 16] texels, [0, 1) depth.
    float slack_texels = 0.25f;
    float slack_depth = 4e-6f;
};

struct ShadowMaskTargets {
    cl::Buffer mask;  // float a pixel: the lit fraction of the taps (1 on sky)
};

// The test's program (its OM_LANES from the runtime: each work-item tests that many pixels of a
// row).
std::vector<std::string> shadow_mask_program_files();

class ShadowMaskPass {
  public:
    explicit ShadowMaskPass(std::shared_ptr<Runtime> runtime);
    // Enqueues on `queue` (the runtime's when null) after `wait`; returns the kernel's event.
    // Throws Error for a setting out of range or an input missing or too small, before anything
    // is enqueued.
    cl::Event enqueue(const ShadowMaskInputs& in, const ShadowMaskTargets& out,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

  private:
    std::shared_ptr<Runtime> runtime_;
    int lanes_ = 1;  // the kernel's, from the runtime when it was built
    cl::Kernel kernel_;
};

}  // namespace offsetmap
