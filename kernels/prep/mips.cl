// One level of the height pyramid (all levels in one buffer) from the level above: each texel is
// the box average of the parent texels it covers (exactly 2 x 2 for even sizes; odd sizes spread
// the extra row or column).
__kernel void om_mip_level(__global float* pyramid, int parent_offset, int pw, int ph,
                           int child_offset, int cw, int ch) {
    int i = get_global_id(0), j = get_global_id(1);
    if (i >= cw || j >= ch) return;
    __global const float* parent = pyramid + parent_offset;
    int x0 = i * pw / cw, x1 = max(x0 + 1, (i + 1) * pw / cw);
    int y0 = j * ph / ch, y1 = max(y0 + 1, (j + 1) * ph / ch);
    float sum = 0.0f;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += parent[y * pw + x];
    pyramid[child_offset + j * cw + i] = sum / (float)((x1 - x0) * (y1 - y0));
}
