// The material frame's offset entry: one method's dispatch over its compacted tile entries
// (classify.cl). A work-item takes OM_LANES pixels of one row of one entry's tile and traces the
// lanes of the entry's material with that material's parameters and relief (om_offset_lanes, as
// om_offset does); lanes of other materials are skipped before any fetch and not stored, so each
// pixel gets the bits its material's pass alone would give it. Pasted after offset.cl.
__kernel void om_offset_tiles(const OmTileParams T, __global const OmMaterialSlot* slots,
                              __global const uint* entries, __global const float* material,
                              __global const float2* gb_uv2, __global const float4* gb_view4,
                              __global const float* heights, __global const float* aux,
                              __global float2* out_uv2, __global float* out_depth,
                              __global uint* out_fetches, __global uint* out_flags) {
    const int segments = OM_TILE_W / OM_LANES;
    const int per_entry = T.tile_h * segments;
    const int gid = (int)get_global_id(0);
    const int e = gid / per_entry;
    if (e >= T.entry_count) return;
    const int r = gid - e * per_entry;
    const int row = r / segments;
    const int tile = (int)entries[2 * (T.entry_base + e)];
    const int slot = (int)entries[2 * (T.entry_base + e) + 1];
    const int y = tile / T.tiles_x * T.tile_h + row;
    const int x0 = tile % T.tiles_x * OM_TILE_W + (r - row * segments) * OM_LANES;
    if (y >= T.height || x0 >= T.width) return;
    const int base = y * T.width + x0;
    const int count = min(OM_LANES, T.width - x0);
    __global const OmMaterialSlot* S = slots + slot;
    const OmOffsetParams P = S->P;
    OmF mat;
#if OM_LANES == 1
    mat = material[base];
#else
    float tm[OM_LANES];
    for (int k = 0; k < OM_LANES; ++k) tm[k] = material[base + min(k, count - 1)];
    mat = OM_VLOAD(tm);
#endif
    const OmI mine = mat == (float)S->id;
    if (!OM_ANY(mine)) return;
    OmF u, v, vx, vy, vz;
    om_load_gbuffer((__global const float*)gb_uv2, (__global const float*)gb_view4, base, count, &u,
                    &v, &vx, &vy, &vz);
    OmF ou, ov, t;
    OmI fetches, flags;
    om_offset_lanes(&P, u, v, vx, vy, vz, !mine, 0.0f, heights + S->heights_offset,
                    aux ? aux + S->aux_offset : aux, &ou, &ov, &t, &fetches, &flags);
    om_store_lanes((__global float*)out_uv2, out_depth, out_fetches, out_flags, base, count, mine,
                   ou, ov, t, fetches, flags);
}
