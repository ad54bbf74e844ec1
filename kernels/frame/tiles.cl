// The material frame's offset entry: one method's dispatch over its compacted tile entries
// (classify.cl). A work-item takes one block of one entry's tile (two neighbouring blocks, one per
// group, for a method walking two groups: OM_LANE_PAIRS; blocks as om_tile_block_h shapes them)
// and traces the lanes of the entry's material with that material's parameters and relief
// (om_offset_lanes or om_offset_lane_pair, as om_offset does); lanes of other materials are skipped
// before any fetch and not stored, so each pixel gets the bits its material's pass alone would give
// it. Pasted after offset.cl.

// Block q of a tile: the lanes of the entry's material (the rest skipped) and their G-buffer
// planes. A block past the tile's last one holds no lane of mine.
typedef struct {
    OmBlock b;
    OmI mine;
    OmF u, v, vx, vy, vz;
    OmCurvature k;
} OmTileBlock;

OM_INLINE OmTileBlock om_tile_block(const OmTileParams* T, int tile, int q, float id,
                                    __global const float* material, __global const float* gb_uv,
                                    __global const float* gb_view,
                                    __global const float4* curvature,
                                    __global const float4* uv_metric) {
    OmTileBlock w;
    const int bh = om_tile_block_h(OM_LANES, T->tile_h), bw = OM_LANES / bh;
    const int per_row = OM_TILE_W / bw;
    const int tx = tile % T->tiles_x * OM_TILE_W, ty = tile / T->tiles_x * T->tile_h;
    const int x0 = tx + q % per_row * bw, y0 = ty + q / per_row * bh;
    const int y1 = min(ty + T->tile_h, T->height);
    const int inside = q < om_tile_blocks(OM_LANES, T->tile_h) && x0 < T->width && y0 < y1;
    w.b = om_block_at(inside ? x0 : 0, inside ? y0 : 0, T->width, y1, bw, T->width);
    w.mine = inside ? om_load_block_f(material, w.b) == id : (OmI)0;
    w.k.uu = w.k.uv = w.k.vv = w.k.stretch = 0.0f;
#ifdef OM_UV_METRIC
    w.k.m.j00 = w.k.m.j10 = w.k.m.j01 = w.k.m.j11 = 0.0f;
    w.k.m.guu = w.k.m.guv = w.k.m.gvv = w.k.m.huu = w.k.m.huv = w.k.m.hvv = 0.0f;
#endif
    if (OM_ANY(w.mine)) {
        om_load_block(gb_uv, gb_view, w.b, &w.u, &w.v, &w.vx, &w.vy, &w.vz);
        w.k = om_load_curvature(curvature, uv_metric, T->width * T->height, w.b);
    } else {
        w.u = w.v = w.vx = w.vy = w.vz = 0.0f;
    }
    return w;
}

__kernel void om_offset_tiles(const OmTileParams T, __global const OmMaterialSlot* slots,
                              __global const uint* entries, __global const float* material,
                              __global const float2* gb_uv2, __global const float4* gb_view4,
                              __global const float* heights, __global const float* aux,
                              __global float2* out_uv2, __global float* out_depth,
                              __global uint* out_fetches, __global uint* out_flags,
                              __global const float4* curvature,
                              __global const float4* uv_metric) {
#ifdef OM_LANE_PAIRS
    const int groups = 2;  // a work-item's blocks: two groups for the method's om_trace_pair
#else
    const int groups = 1;
#endif
    const int per_entry = (om_tile_blocks(OM_LANES, T.tile_h) + groups - 1) / groups;
    const int gid = (int)get_global_id(0);
    const int e = gid / per_entry;
    if (e >= T.entry_count) return;
    const int q = (gid - e * per_entry) * groups;
    const int tile = (int)entries[2 * (T.entry_base + e)];
    const int slot = (int)entries[2 * (T.entry_base + e) + 1];
    __global const OmMaterialSlot* S = slots + slot;
    const OmOffsetParams P = S->P;
    __global const float* gb_uv = (__global const float*)gb_uv2;
    __global const float* gb_view = (__global const float*)gb_view4;
    __global float* out_uv = (__global float*)out_uv2;
    __global const float* field = heights + S->heights_offset;
    __global const float* data = aux ? aux + S->aux_offset : aux;
    const float id = (float)S->id;
    const OmTileBlock a = om_tile_block(&T, tile, q, id, material, gb_uv, gb_view, curvature,
                                         uv_metric);
#ifdef OM_LANE_PAIRS
    const OmTileBlock b = om_tile_block(&T, tile, q + 1, id, material, gb_uv, gb_view, curvature,
                                         uv_metric);
    if (!OM_ANY(a.mine) && !OM_ANY(b.mine)) return;
    const OmLaneIn in_a = {a.u, a.v, a.vx, a.vy, a.vz, 0.0f, !a.mine, a.k};
    const OmLaneIn in_b = {b.u, b.v, b.vx, b.vy, b.vz, 0.0f, !b.mine, b.k};
    OmLaneOut out_a, out_b;
    om_offset_lane_pair(&P, &in_a, &in_b, field, data, &out_a, &out_b);
    om_store_block(out_uv, out_depth, out_fetches, out_flags, a.b, a.mine, out_a.ou, out_a.ov,
                   out_a.t, out_a.fetches, out_a.flags);
    om_store_block(out_uv, out_depth, out_fetches, out_flags, b.b, b.mine, out_b.ou, out_b.ov,
                   out_b.t, out_b.fetches, out_b.flags);
#else
    if (!OM_ANY(a.mine)) return;
    OmF ou, ov, t;
    OmI fetches, flags;
    om_offset_lanes(&P, a.u, a.v, a.vx, a.vy, a.vz, &a.k, !a.mine, 0.0f, field, data, &ou, &ov,
                    &t, &fetches, &flags);
    om_store_block(out_uv, out_depth, out_fetches, out_flags, a.b, a.mine, ou, ov, t, fetches,
                   flags);
#endif
}
