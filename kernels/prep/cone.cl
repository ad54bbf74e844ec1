// Cone map for `cone`: per cell (the bilinear patch between texel centres i..i+1, j..j+1; W x H
// cells, the last row and column wrap or are the clamped extrusion) one packed word (methods/cone_map.h)
// bounding the cell's maximum height Hc (the largest of its four corners bounds the patch) and a
// cone ratio c, in texels per unit of H, such that the open region
//     { (p, H) : dist(p, cell) < c (H - Hc) }
// (p in texel space) holds no relief. Cones are per cell, not per texel centre, so they hold at
// every point a bilinear fetch can return, which is what Bán et al. ("Robust cone step mapping",
// EGSR 2024) show per-texel cones fail to do: a ray anywhere in the cell may step by its cone.
//
// c = min over other cells D with Hd > Hc of delta(C, D) / (Hd - Hc), capped at max_ratio, where
// delta is the gap between the cell squares when they do not touch. Touching cells have gap 0, but
// their patch rises from corners the cells share (all <= Hc): at distance x from the shared edge
// the patch is at most Hc + x (Hd - Hc), and at distance x from a shared corner at most Hc +
// sqrt(2) x (Hd - Hc), so delta = 1 (edge) or 1/sqrt(2) (corner) keeps the bound. Acceleration (in
// the spirit of Valasek & Bán's max-mip cone builds): cells are grouped in 8 x 8 blocks whose
// maxima bound every cell inside; a block is opened only when its bound could beat the best cone so
// far, and the search stops at the ring where no cell could.


// Largest texel of block (I, J): cells [8I, 8I + 8) x [8J, 8J + 8), i.e. texels 8I .. 8I + 8.
__kernel void om_cone_blocks(const OmOffsetParams P, __global const float* heights, int bw, int bh,
                             __global float* block_max) {
    int I = get_global_id(0), J = get_global_id(1);
    if (I >= bw || J >= bh) return;
    OmField f = om_field(heights, &P, 0);
    float m = 0.0f;
    for (int y = OM_CONE_BLOCK * J; y <= OM_CONE_BLOCK * (J + 1); ++y)
        for (int x = OM_CONE_BLOCK * I; x <= OM_CONE_BLOCK * (I + 1); ++x)
            m = fmax(m, om_texel(&f, x, y));
    block_max[J * bw + I] = m;
}

OM_INLINE float om_cell_max(const OmField* f, int i, int j) {
    float k00, k10, k01, k11;
    om_corners(f, i, j, &k00, &k10, &k01, &k11);
    return fmax(fmax(k00, k10), fmax(k01, k11));
}

// The cell's word: Hc rounded up and c rounded down, each checked against the decoder the method
// and the host use.
OM_INLINE uint om_cone_pack(float hc, float c) {
    uint qh = (uint)ceil(hc * OM_CONE_HC_SCALE);
    if (om_cone_hc(qh) < hc) ++qh;
    uint qc = (uint)floor(sqrt(c) * OM_CONE_C_SCALE);
    while (qc > 0 && om_cone_ratio(qc << 16) > c) --qc;
    return qh | qc << 16;
}

// Gap between unit cells (or a cell and a block) along one axis: [a, a + na) vs [b, b + nb).
OM_INLINE int om_gap(int a, int na, int b, int nb) {
    return max(max(b - (a + na), a - (b + nb)), 0);
}

// blocks_valid: block maxima bound the cells at any block index (clamp, or wrap with sizes that are
// multiples of 8); otherwise every cell in reach is visited.
__kernel void om_cone_map(const OmOffsetParams P, __global const float* heights,
                          __global const float* block_max, int bw, int bh, int blocks_valid,
                          float global_max, float max_ratio, __global uint* cone) {
    int i = get_global_id(0), j = get_global_id(1);
    if (i >= P.hf_width || j >= P.hf_height) return;
    OmField f = om_field(heights, &P, 0);
    const int B = OM_CONE_BLOCK;
    float hc = om_cell_max(&f, i, j);
    float best = max_ratio;
    int bi = i / B, bj = j / B;
    for (int ring = 0;; ++ring) {
        // Every cell of this ring of blocks is at least 8 (ring - 1) cells away.
        float nearest = (float)max(B * (ring - 1), 0);
        if (nearest >= best * (global_max - hc)) break;
        for (int J = bj - ring; J <= bj + ring; ++J) {
            bool edge_row = J == bj - ring || J == bj + ring;
            for (int I = bi - ring; I <= bi + ring; I += edge_row ? 1 : 2 * max(ring, 1)) {
                int gx = om_gap(i, 1, B * I, B), gy = om_gap(j, 1, B * J, B);
                float gap = fmax(sqrt((float)(gx * gx + gy * gy)), M_SQRT1_2_F);
                if (blocks_valid) {
                    int ci = om_address(I, bw, P.address_mode == OM_ADDRESS_WRAP);
                    int cj = om_address(J, bh, P.address_mode == OM_ADDRESS_WRAP);
                    float m = block_max[cj * bw + ci];
                    if (m <= hc || gap >= best * (m - hc)) continue;
                } else if (gap >= best * (global_max - hc)) {
                    continue;
                }
                for (int y = B * J; y < B * (J + 1); ++y) {
                    for (int x = B * I; x < B * (I + 1); ++x) {
                        float hd = om_cell_max(&f, x, y);
                        if (hd <= hc) continue;
                        int cx = om_gap(i, 1, x, 1), cy = om_gap(j, 1, y, 1);
                        float delta = cx == 0 && cy == 0 ? (x == i || y == j ? 1.0f : M_SQRT1_2_F)
                                                         : sqrt((float)(cx * cx + cy * cy));
                        best = fmin(best, delta / (hd - hc));
                    }
                }
            }
        }
    }
    cone[OM_CONE_INDEX(i, j, om_cone_tiles(P.hf_width))] = om_cone_pack(hc, best);
}
