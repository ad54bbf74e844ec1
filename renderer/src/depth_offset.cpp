#include "offsetmap/renderer/depth_offset.hpp"

#include <algorithm>

#include "launch.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

OmDepthOffsetParams depth_offset_params(const std::array<float, 16>& view_projection,
                                        const std::array<float, 16>& inverse_view_projection,
                                        const Vec3& eye, int width, int height, bool orthographic) {
    OmDepthOffsetParams p{};
    p.width = width;
    p.height = height;
    std::copy(view_projection.begin(), view_projection.end(), p.view_proj);
    std::copy(inverse_view_projection.begin(), inverse_view_projection.end(), p.inv_view_proj);
    std::copy(eye.begin(), eye.end(), p.eye);
    p.eye_w = orthographic ? 0.0f : 1.0f;
    return p;
}

DepthOffsetPass::DepthOffsetPass(Runtime& rt)
    : kernel_(rt.kernel(rt.program({"frame/depth_offset.cl"}), "om_depth_offset")) {}

cl::Event DepthOffsetPass::enqueue(const cl::CommandQueue& queue, const OmDepthOffsetParams& p,
                                   const cl::Buffer& depth, const cl::Buffer& t,
                                   const cl::Buffer& density, const cl::Buffer& out) {
    cl::Event done;
    try {
        set_args(kernel_, p, depth, t, density, out);
        enqueue_grid(queue, kernel_,
                     cl::NDRange((p.width + OM_DEPTH_RUN - 1) / OM_DEPTH_RUN, p.height), nullptr,
                     &done);
    } catch (const cl::Error& e) {
        throw Error("cannot run the pixel depth offset: " + describe_cl_error(e.err()));
    }
    return done;
}

}  // namespace offsetmap::renderer
