// The material frame's layer behind (MaterialFrame::enqueue with a LayerBehind): the second
// layer's ids kept only where the first layer does not show its surface (so the second frame's
// classification traces just those pixels' tiles), the choice of the second layer's result where
// it shows a surface, and the copy of any per-pixel plane (words of 4 bytes) where it was chosen.
// One work-item a pixel: each is a few loads and stores, and the launch is padded to 64.

__kernel void om_behind_mask(const int n, __global const uint* flags, __global const float* ids,
                             __global float* kept) {
    const int k = (int)get_global_id(0);
    if (k >= n) return;
    kept[k] = (flags[k] & OM_FLAGS_SEE_BEHIND) ? ids[k] : 0.0f;
}

// The first layer's flags become the second's, with BEHIND, where the first does not show its
// surface and the second does, and the pixel takes the second layer's result and planes (a null
// plane: one the G-buffers do not carry); elsewhere nothing changes (a pixel seen on neither keeps
// SILHOUETTE or OUT_OF_TILE: the background's). One pass for every plane: most pixels read a flag
// and leave.
__kernel void om_behind_choose(const int n, __global uint* flags, __global const uint* behind_flags,
                               __global const float2* b_uv_out, __global const float* b_depth_out,
                               __global const uint* b_fetches_out, __global float2* uv_out,
                               __global float* depth_out, __global uint* fetches_out,
                               __global const float2* b_uv, __global const float4* b_view,
                               __global const float4* b_light, __global const float* b_lod,
                               __global const float* b_material, __global const float4* b_curvature,
                               __global float2* uv, __global float4* view, __global float4* light,
                               __global float* lod, __global float* material,
                               __global float4* curvature, __global const float4* b_uv_metric,
                               __global float4* uv_metric) {
    const int k = (int)get_global_id(0);
    if (k >= n) return;
    const uint f = flags[k];
    if (!(f & OM_FLAGS_SEE_BEHIND)) return;
    const uint b = behind_flags[k];
    if (b & OM_FLAGS_NOT_SHOWN) return;
    flags[k] = b | OM_FLAG_BEHIND;
    uv_out[k] = b_uv_out[k];
    if (depth_out) depth_out[k] = b_depth_out[k];
    if (fetches_out) fetches_out[k] = b_fetches_out[k];
    uv[k] = b_uv[k];
    view[k] = b_view[k];
    material[k] = b_material[k];
    if (light) light[k] = b_light[k];
    if (lod) lod[k] = b_lod[k];
    if (curvature) curvature[k] = b_curvature[k];
    if (uv_metric)  // three planes of n
        for (int p = 0; p < 3; ++p) uv_metric[p * n + k] = b_uv_metric[p * n + k];
}

__kernel void om_behind_take(const int n, const int words, __global const uint* flags,
                             __global const uint* from, __global uint* to) {
    const int k = (int)get_global_id(0);
    if (k >= n || !(flags[k] & OM_FLAG_BEHIND)) return;
    for (int w = 0; w < words; ++w) to[(size_t)k * words + w] = from[(size_t)k * words + w];
}
