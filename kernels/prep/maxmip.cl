// Maximum-height pyramid for `maxmip` (Tevs, Ihrke & Seidel 2008), stored from level 1: block
// (I, J) of level k covers the cells [I 2^k, (I+1) 2^k) x [J 2^k, (J+1) 2^k), a cell (i, j) being
// the bilinear patch between texel centres i..i+1, j..j+1, and holds the largest texel of those
// patches, which bounds the bilinear surface over the block. The pyramid covers the map padded to
// a multiple of 2^levels a side (om_maxmip_padded); a padded block reads texels past the edge
// through the address mode (wrapped or clamped), so a tile's partial last block stores the maximum
// of a superset of its cells: still a bound.

__kernel void om_maxmip_first(const OmOffsetParams P, __global const float* heights,
                              __global float* level1, int w1, int h1) {
    int I = get_global_id(0), J = get_global_id(1);
    if (I >= w1 || J >= h1) return;
    OmField f = om_field(heights, &P, 0);
    float m = 0.0f;
    for (int y = 2 * J; y <= 2 * J + 2; ++y)
        for (int x = 2 * I; x <= 2 * I + 2; ++x) m = fmax(m, om_texel(&f, x, y));
    level1[J * w1 + I] = m;
}

__kernel void om_maxmip_next(__global float* pyramid, int parent_offset, int pw, int child_offset,
                             int cw, int ch) {
    int I = get_global_id(0), J = get_global_id(1);
    if (I >= cw || J >= ch) return;
    __global const float* p = pyramid + parent_offset;
    float m = fmax(fmax(p[2 * J * pw + 2 * I], p[2 * J * pw + 2 * I + 1]),
                   fmax(p[(2 * J + 1) * pw + 2 * I], p[(2 * J + 1) * pw + 2 * I + 1]));
    pyramid[child_offset + J * cw + I] = m;
}
