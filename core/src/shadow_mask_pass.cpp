#include "offsetmap/shadow_mask_pass.hpp"

#include <algorithm>
#include <string>

#include "launch.hpp"
#include "offsetmap/registry.hpp"
#include "pixel_grid.hpp"

namespace offsetmap {

std::vector<std::string> shadow_mask_program_files() {
    return {"common/unproject.cl", "frame/shadow_mask.cl"};
}

ShadowMaskPass::ShadowMaskPass(std::shared_ptr<Runtime> runtime)
    : runtime_(std::move(runtime)),
      lanes_(runtime_->lanes()),
      kernel_(runtime_->kernel(runtime_->program(shadow_mask_program_files(), lanes_define(lanes_)),
                               "om_shadow_mask")) {}

cl::Event ShadowMaskPass::enqueue(const ShadowMaskInputs& in, const ShadowMaskTargets& out,
                                  const std::vector<cl::Event>& wait,
                                  const cl::CommandQueue& queue) {
    const ShadowMapView& map = in.map;
    if (in.width < 1 || in.height < 1 || map.width < 1 || map.height < 1)
        throw Error("the shadow test needs a frame and a shadow map of at least 1x1 pixels");
    check_gbuffer_size(in.width, in.height, "the shadow test's frame");
    check_gbuffer_size(map.width, map.height, "the shadow map");
    if (in.pcf_radius < 0 || in.pcf_radius > 8)
        throw Error("the shadow test's filter radius must be in [0, 8] texels, got " +
                    std::to_string(in.pcf_radius));
    if (!(in.slack_texels >= 0.0f && in.slack_texels <= 16.0f) ||
        !(in.slack_depth >= 0.0f && in.slack_depth < 1.0f))
        throw Error("the shadow test's slack must be in [0, 16] texels and [0, 1) of depth");
    OmShadowMaskParams p{};
    p.frame = pixel_grid(in.camera, in.width, in.height, "the shadow test's camera");
    p.map = pixel_grid(map.camera, map.width, map.height, "the shadow map's camera");
    if (!finite(map.view_projection.data(), 16))
        throw Error("the shadow map's view-projection must be finite");
    std::copy(in.camera.inverse_view_projection.begin(), in.camera.inverse_view_projection.end(),
              p.inv_view_proj);
    std::copy(map.view_projection.begin(), map.view_projection.end(), p.light_view_proj);
    p.slack_texels = in.slack_texels;
    p.slack_depth = in.slack_depth;
    p.pcf_radius = in.pcf_radius;
    const cl::Context& context = runtime_->context();
    const size_t n = static_cast<size_t>(in.width) * in.height;
    check_buffer(context, in.depth, {"the shadow test's depth buffer", "float", sizeof(float), n});
    check_buffer(context, map.depth,
                 {"the shadow map's depth buffer", "float", sizeof(float),
                  static_cast<size_t>(map.width) * map.height});
    check_buffer(context, out.mask,
                 {"the shadow test's mask buffer", "float", sizeof(float), n, true});
    const cl::CommandQueue& q = pass_queue(*runtime_, queue);
    cl::Event done;
    try {
        set_args(kernel_, p, in.depth, map.depth, out.mask);
        enqueue_grid(q, kernel_, cl::NDRange((in.width + lanes_ - 1) / lanes_, in.height),
                     wait.empty() ? nullptr : &wait, &done);
    } catch (const cl::Error& e) {
        throw Error("cannot run the shadow test: " + describe_cl_error(e.err()));
    }
    return done;
}

}  // namespace offsetmap
