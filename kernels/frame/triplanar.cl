// The material frame's triplanar merge: where a pixel's second projection weighs, its depth is the
// weighted depth of its projections (each t along the same world ray, in the same uv units per
// world unit) and its fetches their sum. One work-item a pixel, as the layer behind's.

__kernel void om_triplanar_merge(const int n, __global const float4* blend, __global float* depth,
                                 __global uint* fetches, __global const float* depth2,
                                 __global const uint* fetches2, __global const float* depth3,
                                 __global const uint* fetches3) {
    const int k = (int)get_global_id(0);
    if (k >= n) return;
    const float4 b = blend[k];
    if (b.w < 0.0f || !(b.y > 0.0f)) return;
    const int third = b.z > 0.0f;
    if (depth)
        depth[k] = b.x * depth[k] + b.y * depth2[k] + (third ? b.z * depth3[k] : 0.0f);
    if (fetches) fetches[k] += fetches2[k] + (third ? fetches3[k] : 0u);
}
