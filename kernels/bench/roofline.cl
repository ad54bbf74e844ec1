// Roofline microkernels for bench/: the floors every offset kernel is measured against.

// G-buffer pass-through: the offset pass's memory traffic (uv 8 B + view 16 B in, uv' 8 B out)
// with no work. Multiplying by 0 keeps the view load without changing the output.
__kernel void om_bench_passthrough(__global const float2* uv, __global const float4* view,
                                   __global float2* out, int n) {
    int i = get_global_id(0);
    if (i >= n) return;
    out[i] = uv[i] + view[i].xy * 0.0f;
}

// Each lane's pixel: a work-item takes a block of OM_LANES pixels of the image, as the offset
// entry's groups are (offsetmap/shared.h), lanes past the edge repeating its last column or row; the
// block's own pixels, so a store per lane stays in it. False past the last block.
OM_INLINE int om_bench_block(const OmOffsetParams* P, OmI* id) {
    const int bw = OM_BLOCK_W(OM_LANES), bh = OM_BLOCK_H(OM_LANES);
    const int g = (int)get_global_id(0), per_row = (P->gb_width + bw - 1) / bw;
    if (g >= om_image_blocks(P->gb_width, P->gb_height, OM_LANES)) return 0;
    OmI x = min(g % per_row * bw + OM_LANE_IDS % bw, (OmI)(P->gb_width - 1));
    OmI y = min(g / per_row * bh + OM_LANE_IDS / bw, (OmI)(P->gb_height - 1));
    *id = y * P->gb_width + x;
    return 1;
}

OM_INLINE void om_bench_store(__global float* out, OmI id, OmF r) {
    for (int k = 0; k < OM_LANES; ++k) out[((int*)&id)[k]] = ((float*)&r)[k];
}

// `chain` dependent bilinear height fetches per pixel through the methods' sampling layer, a block
// of OM_LANES pixels per work-item (lanes.h; 1 unless defined): each fetch's position depends on
// the previous height, as in a march, so none can be skipped or hoisted. Time per fetch = (this -
// pass-through) / chain.
__kernel void om_bench_fetch_chain(const OmOffsetParams P, __global const float* heights,
                                   __global const float* uv, __global float* out, int chain) {
    OmI id;
    if (!om_bench_block(&P, &id)) return;
    OmField f = om_field(heights, &P, (OmI)0);
    OmF u = OM_GATHER(uv, 2 * id), v = OM_GATHER(uv, 2 * id + 1);
    OmI fetches = 0;
    for (int k = 0; k < chain; ++k) {
        OmF h = om_height(&f, u, v, (OmI)1, &fetches OM_IMG_ARG);
        u += 0.37f * h / f.fw;
        v += 0.11f * h / f.fh;
    }
    om_bench_store(out, id, u + v + OM_TO_FLOAT(fetches) * 0.0f);
}

// `count` independent bilinear fetches per pixel along a line, as a linear search makes them: the
// positions do not depend on earlier heights, so fetches can overlap. The fastest fetch rate
// measured is the roof methods are measured against.
__kernel void om_bench_fetch_line(const OmOffsetParams P, __global const float* heights,
                                  __global const float* uv, __global float* out, int count) {
    OmI id;
    if (!om_bench_block(&P, &id)) return;
    OmField f = om_field(heights, &P, (OmI)0);
    OmF u = OM_GATHER(uv, 2 * id), v = OM_GATHER(uv, 2 * id + 1);
    // Stepped in cell coordinates, as the linear search steps (om_height_cell).
    OmF cx = OM_CELL(u, f.fw), cy = OM_CELL(v, f.fh), sum = 0.0f;
    OmI fetches = 0;
    for (int k = 0; k < count; ++k) {
        OmF fk = (OmF)(float)k;
        sum += om_height_cell(&f, OM_FMA(fk, 0.61f, cx), OM_FMA(fk, 0.29f, cy), (OmI)1,
                              &fetches OM_IMG_ARG);
    }
    om_bench_store(out, id, u + v + sum * 0.0f + OM_TO_FLOAT(fetches) * 0.0f);
}
