#include "offsetmap/depth_offset_pass.hpp"

#include <algorithm>

#include "launch.hpp"
#include "pixel_grid.hpp"

namespace offsetmap {

DepthOffsetPass::DepthOffsetPass(std::shared_ptr<Runtime> runtime)
    : runtime_(std::move(runtime)),
      kernel_(runtime_->kernel(runtime_->program({"common/unproject.cl", "frame/depth_offset.cl"}),
                               "om_depth_offset")) {}

cl::Event DepthOffsetPass::enqueue(const DepthOffsetInputs& in, const DepthOffsetTargets& out,
                                   const std::vector<cl::Event>& wait,
                                   const cl::CommandQueue& queue) {
    check_gbuffer_size(in.width, in.height, "the depth offset's frame");
    OmDepthOffsetParams p{};
    p.grid = pixel_grid(in.camera, in.width, in.height, "the depth offset's camera");
    check_inverse(in.view_projection, in.camera, "the depth offset's camera");
    std::copy(in.view_projection.begin(), in.view_projection.end(), p.view_proj);
    std::copy(in.camera.inverse_view_projection.begin(), in.camera.inverse_view_projection.end(),
              p.inv_view_proj);
    std::copy(in.camera.eye.begin(), in.camera.eye.end(), p.eye);
    p.eye_w = in.camera.orthographic ? 0.0f : 1.0f;
    const cl::Context& context = runtime_->context();
    const size_t n = static_cast<size_t>(in.width) * in.height;
    check_buffer(context, in.depth, {"the depth offset's depth buffer", "float", sizeof(float), n});
    check_buffer(context, in.t, {"the depth offset's t buffer", "float", sizeof(float), n});
    check_buffer(context, in.density,
                 {"the depth offset's uv density buffer", "float", sizeof(float), n});
    check_buffer(context, out.depth,
                 {"the depth offset's output depth buffer", "float", sizeof(float), n, true});
    const cl::CommandQueue& q = pass_queue(*runtime_, queue);
    cl::Event done;
    try {
        set_args(kernel_, p, in.depth, in.t, in.density, out.depth);
        enqueue_grid(q, kernel_,
                     cl::NDRange((in.width + OM_DEPTH_RUN - 1) / OM_DEPTH_RUN, in.height),
                     wait.empty() ? nullptr : &wait, &done);
    } catch (const cl::Error& e) {
        throw Error("cannot run the pixel depth offset: " + describe_cl_error(e.err()));
    }
    return done;
}

}  // namespace offsetmap
