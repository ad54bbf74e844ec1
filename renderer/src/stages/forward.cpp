// The forward peer's stage of the deferred order: the fragment shader traced each triplanar
// pixel's three axis projections (uv' of the x axis in the offset plane, y and z in the second);
// the shading takes them in the order the reconstruct pass gave the pixel's projections.
#include <cmath>

#include "../frame_impl.hpp"

namespace offsetmap::renderer {

void FrameRenderer::Impl::order_forward_projections(FrameScratch& s) {
    const cl::CommandQueue& q = rt->queue();
    const size_t n = pixels();
    std::vector<cl_float4> blend(n);
    q.enqueueReadBuffer(triplanar->blend, CL_TRUE, 0, n * sizeof(cl_float4), blend.data());
    const std::vector<float> yz = raster->read_offset_yz();
    std::vector<cl_float2> second(n), third(n);
    for (size_t k = 0; k < n; ++k) {
        if (!(blend[k].s[0] >= 0.0f)) continue;
        const cl_float2 axis_uv[3] = {
            s.forward_uv[k], {{yz[4 * k], yz[4 * k + 1]}}, {{yz[4 * k + 2], yz[4 * k + 3]}}};
        // x = 2 c + w1, c = p0 + 6 where the second is on the axis of p0's B
        // (kernels/common/triplanar.cl).
        const int c = static_cast<int>(std::floor(0.5f * blend[k].s[0]));
        const int a0 = (c % 6) >> 1, at = a0 == 0 ? 2 : 0, ab = a0 == 1 ? 2 : 1;
        const bool b_first = c >= 6;
        s.forward_uv[k] = axis_uv[a0];
        second[k] = axis_uv[b_first ? ab : at];
        third[k] = axis_uv[b_first ? at : ab];
    }
    q.enqueueWriteBuffer(targets.uv, CL_FALSE, 0, n * sizeof(cl_float2), s.forward_uv.data());
    q.enqueueWriteBuffer(triplanar->second_targets.uv, CL_FALSE, 0, n * sizeof(cl_float2),
                         second.data());
    q.enqueueWriteBuffer(triplanar->third_targets.uv, CL_TRUE, 0, n * sizeof(cl_float2),
                         third.data());
}

}  // namespace offsetmap::renderer
