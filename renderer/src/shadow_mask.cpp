#include "offsetmap/renderer/shadow_mask.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "launch.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

OmShadowMaskParams shadow_mask_params(const std::array<float, 16>& inverse_view_projection,
                                      int width, int height,
                                      const std::array<float, 16>& light_view_projection,
                                      int map_width, int map_height, int pcf_radius,
                                      float slack_texels, float slack_depth) {
    OmShadowMaskParams p{};
    p.width = width;
    p.height = height;
    p.map_width = map_width;
    p.map_height = map_height;
    std::copy(inverse_view_projection.begin(), inverse_view_projection.end(), p.inv_view_proj);
    std::copy(light_view_projection.begin(), light_view_projection.end(), p.light_view_proj);
    p.slack_texels = slack_texels;
    p.slack_depth = slack_depth;
    p.pcf_radius = pcf_radius;
    return p;
}

ShadowMaskPass::ShadowMaskPass(Runtime& rt)
    : kernel_(rt.kernel(rt.program({"frame/shadow_mask.cl"}), "om_shadow_mask")) {}

cl::Event ShadowMaskPass::enqueue(const cl::CommandQueue& queue, const OmShadowMaskParams& p,
                                  const cl::Buffer& depth, const cl::Buffer& map,
                                  const cl::Buffer& out) {
    if (p.width < 1 || p.height < 1 || p.map_width < 1 || p.map_height < 1)
        throw Error("the shadow test needs a frame and a shadow map of at least 1x1 pixels");
    if (p.pcf_radius < 0 || p.pcf_radius > 8)
        throw Error("the shadow test's filter radius must be in [0, 8] texels, got " +
                    std::to_string(p.pcf_radius));
    if (!(p.slack_texels >= 0.0f && p.slack_texels <= 16.0f) ||
        !(p.slack_depth >= 0.0f && p.slack_depth < 1.0f))
        throw Error("the shadow test's slack must be in [0, 16] texels and [0, 1) of depth");
    cl::Event done;
    try {
        set_args(kernel_, p, depth, map, out);
        enqueue_grid(queue, kernel_, cl::NDRange(p.width, p.height), nullptr, &done);
    } catch (const cl::Error& e) {
        throw Error("cannot run the shadow test: " + describe_cl_error(e.err()));
    }
    return done;
}

}  // namespace offsetmap::renderer
