// HeightStorage::Unorm16 (offsetmap/settings.hpp): the pyramid's floats rounded to multiples of
// 1/65535 in place, then each level packed after the pyramid (DeviceHeightField::packed), so a
// bilinear patch is the two words (i, j) and (i + 1, j): one 64-bit read (sampling.cl).

// Heights are in [0, 1] (the readers and the device import clamp them).
#define OM_TO_UNORM16(h) ((uint)((h)*65535.0f + 0.5f))

__kernel void om_round_heights(__global float* pyramid, int n) {
    int i = get_global_id(0);
    if (i < n) pyramid[i] = (float)OM_TO_UNORM16(pyramid[i]) * OM_UNORM16_STEP;
}

// Level (w x h at `offset`) after rounding: a rounded height converts back to its own code.
__kernel void om_pack_heights(__global float* pyramid, int words, int offset, int w, int h) {
    int i = get_global_id(0), j = get_global_id(1);
    if (i >= w || j >= h) return;
    __global const float* level = pyramid + offset;
    uint top = OM_TO_UNORM16(level[j * w + i]);
    uint below = OM_TO_UNORM16(level[min(j + 1, h - 1) * w + i]);
    ((__global uint*)(pyramid + words))[offset + j * w + i] = top | below << 16;
}
