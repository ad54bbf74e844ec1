// The material frame's offset entry: one method's dispatch over its compacted tile entries
// (classify.cl). A work-item takes OM_LANES pixels of one row of one entry's tile (two rows, one
// per group, for a method walking two groups: OM_LANE_PAIRS) and traces the lanes of the entry's
// material with that material's parameters and relief (om_offset_lanes or om_offset_lane_pair, as
// om_offset does); lanes of other materials are skipped before any fetch and not stored, so each
// pixel gets the bits its material's pass alone would give it. Pasted after offset.cl.

// One row of an entry's tile segment: the lanes of the entry's material (the rest skipped), their
// G-buffer planes, and where they are stored. `row` past the tile or the frame: no lane is mine.
typedef struct {
    int base, count;
    OmI mine;
    OmF u, v, vx, vy, vz;
} OmTileRow;

OM_INLINE OmTileRow om_tile_row(const OmTileParams* T, int tile, int row, int segment, float id,
                                __global const float* material, __global const float* gb_uv,
                                __global const float* gb_view) {
    OmTileRow w;
    const int y = tile / T->tiles_x * T->tile_h + row;
    const int x0 = tile % T->tiles_x * OM_TILE_W + segment * OM_LANES;
    const int inside = row < T->tile_h && y < T->height && x0 < T->width;
    w.base = inside ? y * T->width + x0 : 0;
    w.count = inside ? min(OM_LANES, T->width - x0) : 1;
#if OM_LANES == 1
    w.mine = inside && material[w.base] == id;
#else
    float tm[OM_LANES];
    for (int k = 0; k < OM_LANES; ++k) tm[k] = material[w.base + min(k, w.count - 1)];
    w.mine = OM_VLOAD(tm) == id && inside;
#endif
    if (OM_ANY(w.mine))
        om_load_gbuffer(gb_uv, gb_view, w.base, w.count, &w.u, &w.v, &w.vx, &w.vy, &w.vz);
    else
        w.u = w.v = w.vx = w.vy = w.vz = 0.0f;
    return w;
}

__kernel void om_offset_tiles(const OmTileParams T, __global const OmMaterialSlot* slots,
                              __global const uint* entries, __global const float* material,
                              __global const float2* gb_uv2, __global const float4* gb_view4,
                              __global const float* heights, __global const float* aux,
                              __global float2* out_uv2, __global float* out_depth,
                              __global uint* out_fetches, __global uint* out_flags) {
    const int segments = OM_TILE_W / OM_LANES;
#ifdef OM_LANE_PAIRS
    const int rows = 2;  // a work-item's rows: two groups for the method's om_trace_pair
#else
    const int rows = 1;
#endif
    const int per_entry = (T.tile_h + rows - 1) / rows * segments;
    const int gid = (int)get_global_id(0);
    const int e = gid / per_entry;
    if (e >= T.entry_count) return;
    const int r = gid - e * per_entry;
    const int row = r / segments * rows, segment = r % segments;
    const int tile = (int)entries[2 * (T.entry_base + e)];
    const int slot = (int)entries[2 * (T.entry_base + e) + 1];
    __global const OmMaterialSlot* S = slots + slot;
    const OmOffsetParams P = S->P;
    __global const float* gb_uv = (__global const float*)gb_uv2;
    __global const float* gb_view = (__global const float*)gb_view4;
    __global const float* field = heights + S->heights_offset;
    __global const float* data = aux ? aux + S->aux_offset : aux;
    const OmTileRow a =
        om_tile_row(&T, tile, row, segment, (float)S->id, material, gb_uv, gb_view);
#ifdef OM_LANE_PAIRS
    const OmTileRow b =
        om_tile_row(&T, tile, row + 1, segment, (float)S->id, material, gb_uv, gb_view);
    if (!OM_ANY(a.mine) && !OM_ANY(b.mine)) return;
    const OmLaneIn in_a = {a.u, a.v, a.vx, a.vy, a.vz, 0.0f, !a.mine};
    const OmLaneIn in_b = {b.u, b.v, b.vx, b.vy, b.vz, 0.0f, !b.mine};
    OmLaneOut out_a, out_b;
    om_offset_lane_pair(&P, &in_a, &in_b, field, data, &out_a, &out_b);
    om_store_lanes((__global float*)out_uv2, out_depth, out_fetches, out_flags, a.base, a.count,
                   a.mine, out_a.ou, out_a.ov, out_a.t, out_a.fetches, out_a.flags);
    om_store_lanes((__global float*)out_uv2, out_depth, out_fetches, out_flags, b.base, b.count,
                   b.mine, out_b.ou, out_b.ov, out_b.t, out_b.fetches, out_b.flags);
#else
    if (!OM_ANY(a.mine)) return;
    OmF ou, ov, t;
    OmI fetches, flags;
    om_offset_lanes(&P, a.u, a.v, a.vx, a.vy, a.vz, !a.mine, 0.0f, field, data, &ou, &ov, &t,
                    &fetches, &flags);
    om_store_lanes((__global float*)out_uv2, out_depth, out_fetches, out_flags, a.base, a.count,
                   a.mine, ou, ov, t, fetches, flags);
#endif
}
