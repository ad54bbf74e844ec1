// The material frame's triplanar merge. A projection's trace measures t along its ray over the
// surface, normalised in its own frame (kernels/common/triplanar.cl, om_tri_over_surface): times
// that ray's scale, it is t along the one world ray in uv units of 1 / world_scale, which the
// depth offset takes. Where a pixel's second projection weighs, its depth is the weighted depth of
// its projections so scaled and its fetches their sum. A work-item takes 16 pixels: the first
// projection's scales (0 where not triplanar) are one load, and runs of none are skipped.

__kernel void om_triplanar_merge(const int n, __global const float* ids2,
                                 __global const float4* blend, __global float* depth,
                                 __global uint* fetches, __global const float* depth2,
                                 __global const uint* fetches2, __global const float* depth3,
                                 __global const uint* fetches3, __global const float* ray_scale,
                                 __global const float4* view2, __global const float4* view3) {
    const int k0 = (int)get_global_id(0) * 16;
    if (k0 >= n) return;
    if (k0 + 16 <= n && all(vload16(0, ray_scale + k0) == (float16)0.0f)) return;
    for (int k = k0; k < min(k0 + 16, n); ++k) {
        const float s0 = ray_scale[k];
        if (!(s0 > 0.0f)) continue;  // not triplanar (or no usable view: its t is left alone)
        if (ids2[k] == 0.0f) {  // one projection: 1 on an axis-aligned face, bit for bit
            if (depth) depth[k] *= s0;
            continue;
        }
        // The weights as common/triplanar.cl packs them.
        const float4 b = blend[k];
        const float w1 = b.x - 2.0f * floor(0.5f * b.x), w2 = b.y, w0 = 1.0f - w1 - w2;
        const int third = w2 > 0.0f;
        if (depth)
            depth[k] = w0 * depth[k] * s0 + w1 * depth2[k] * view2[k].w +
                       (third ? w2 * depth3[k] * view3[k].w : 0.0f);
        if (fetches) fetches[k] += fetches2[k] + (third ? fetches3[k] : 0u);
    }
}
