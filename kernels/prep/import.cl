// Level 0 of the height pyramid from heights in the caller's memory: a buffer of values stored as
// OM_STORAGE_* or, where the host defines OM_IMAGE_HEIGHTS, an image (its first channel). Values
// outside [0,1] are clamped and NaN becomes 0, as the file readers clamp, counted in `clamped`;
// depth maps (1 = deepest) become heights.
#ifdef OM_IMAGE_HEIGHTS
#define OM_HEIGHTS_ARG __read_only image2d_t src
#define OM_HEIGHT_AT(i, j, k) read_imagef(src, om_texel_sampler, (int2)(i, j)).x
#else
#define OM_HEIGHTS_ARG __global const uchar* src
#define OM_HEIGHT_AT(i, j, k) om_stored(src, storage, k)
#endif

__kernel void om_import_heights(OM_HEIGHTS_ARG, int storage, int width, int height, int depth_map,
                                __global float* pyramid, __global uint* clamped) {
    const int i = get_global_id(0), j = get_global_id(1);
    if (i >= width || j >= height) return;
    const size_t k = (size_t)j * width + i;
    float h = OM_HEIGHT_AT(i, j, k);
    if (!(h >= 0.0f && h <= 1.0f)) {
        atomic_inc(clamped);
        h = isnan(h) ? 0.0f : clamp(h, 0.0f, 1.0f);
    }
    pyramid[k] = depth_map ? 1.0f - h : h;
}
