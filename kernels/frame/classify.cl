// The material frame's tile classification: one work-item per tile reads its pixels' material
// ids and appends one entry (tile, slot) per material present to the list of that material's
// method (counts[method] entries from list_base[method]). Pixels of id 0 (no relief) get their
// outputs here: uv' = uv, depth 0, no fetches, flag EMPTY where uv is NaN; no method runs for
// them. An id that is not a non-negative integer with a slot is counted in counts[method_count],
// the smallest such pixel in counts[method_count + 1] (reset to 0xffffffff by the host), so the
// host can name it before any pixel is traced. Without T.pass_through (a triplanar frame's second
// and third projections, whose id-0 pixels nobody reads) id 0 gets nothing, and a row of it is one
// load.
#if OM_TILE_W != 16
#error "a tile row is one float16"
#endif

__kernel void om_classify(const OmTileParams T, __global const float* material,
                          __global const float2* gb_uv, __global const int* slot_of_id,
                          __global const int* method_of_slot, __global const uint* list_base,
                          __global uint* counts, __global uint* entries, __global float2* out_uv,
                          __global float* out_depth, __global uint* out_fetches,
                          __global uint* out_flags) {
    const int tile = (int)get_global_id(0);
    if (tile >= T.tile_count) return;
    const int x0 = tile % T.tiles_x * OM_TILE_W, y0 = tile / T.tiles_x * T.tile_h;
    const int x1 = min(x0 + OM_TILE_W, T.width), y1 = min(y0 + T.tile_h, T.height);
    uint present = 0u;
    for (int y = y0; y < y1; ++y) {
        // Most rows of most tiles hold one material: one vector load, one lookup.
        if (x1 - x0 == OM_TILE_W) {
            const float16 row = vload16(0, material + y * T.width + x0);
            const float m = row.s0;
            if (m == 0.0f && !T.pass_through && all(row == (float16)0.0f)) continue;
            if (m != 0.0f && all(row == (float16)m)) {
                const int slot = om_slot_of(m, T.id_limit, slot_of_id);
                if (slot >= 0) {
                    present |= 1u << slot;  // the whole row's material
                    continue;
                }
            }
        }
        for (int x = x0; x < x1; ++x) {
            const int p = y * T.width + x;
            const float m = material[p];
            if (m == 0.0f) {
                if (!T.pass_through) continue;
                const float2 uv = gb_uv[p];
                out_uv[p] = uv;
                if (out_depth) out_depth[p] = 0.0f;
                if (out_fetches) out_fetches[p] = 0u;
                if (out_flags) out_flags[p] = isnan(uv.x) || isnan(uv.y) ? OM_FLAG_EMPTY : 0u;
                continue;
            }
            const int slot = om_slot_of(m, T.id_limit, slot_of_id);
            if (slot < 0) {
                atomic_inc(&counts[T.method_count]);
                atomic_min(&counts[T.method_count + 1], (uint)p);
                continue;
            }
            present |= 1u << slot;
        }
    }
    for (int s = 0; s < T.slot_count; ++s) {
        if (!(present & (1u << s))) continue;
        const int k = method_of_slot[s];
        const uint at = list_base[k] + atomic_inc(&counts[k]);
        entries[2 * at] = (uint)tile;
        entries[2 * at + 1] = (uint)s;
    }
}
