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
// surface and the second does; elsewhere they stay (a pixel seen on neither keeps SILHOUETTE or
// OUT_OF_TILE: the background's).
__kernel void om_behind_choose(const int n, __global uint* flags,
                               __global const uint* behind_flags) {
    const int k = (int)get_global_id(0);
    if (k >= n) return;
    const uint f = flags[k], b = behind_flags[k];
    if ((f & OM_FLAGS_SEE_BEHIND) && !(b & OM_FLAGS_NOT_SHOWN)) flags[k] = b | OM_FLAG_BEHIND;
}

__kernel void om_behind_take(const int n, const int words, __global const uint* flags,
                             __global const uint* from, __global uint* to) {
    const int k = (int)get_global_id(0);
    if (k >= n || !(flags[k] & OM_FLAG_BEHIND)) return;
    for (int w = 0; w < words; ++w) to[(size_t)k * words + w] = from[(size_t)k * words + w];
}
