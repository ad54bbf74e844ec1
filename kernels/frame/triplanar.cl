// The material frame's triplanar merge: where a pixel's second projection weighs, its depth is the
// weighted depth of its projections (each t along the same world ray, in the same uv units per
// world unit) and its fetches their sum. A work-item takes 16 pixels: the second projection's ids
// (0 where it does not weigh) are one load, and most runs of 16 have none.

__kernel void om_triplanar_merge(const int n, __global const float* ids2,
                                 __global const float4* blend, __global float* depth,
                                 __global uint* fetches, __global const float* depth2,
                                 __global const uint* fetches2, __global const float* depth3,
                                 __global const uint* fetches3) {
    const int k0 = (int)get_global_id(0) * 16;
    if (k0 >= n) return;
    if (k0 + 16 <= n && all(vload16(0, ids2 + k0) == (float16)0.0f)) return;
    for (int k = k0; k < min(k0 + 16, n); ++k) {
        if (ids2[k] == 0.0f) continue;
        // The weights as common/triplanar.cl packs them.
        const float4 b = blend[k];
        const float w1 = b.x - 2.0f * floor(0.5f * b.x), w2 = b.y, w0 = 1.0f - w1 - w2;
        const int third = w2 > 0.0f;
        if (depth) depth[k] = w0 * depth[k] + w1 * depth2[k] + (third ? w2 * depth3[k] : 0.0f);
        if (fetches) fetches[k] += fetches2[k] + (third ? fetches3[k] : 0u);
    }
}
