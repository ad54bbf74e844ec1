// maxmip (Tevs, Ihrke & Seidel, "Maximum mipmaps for fast, accurate, and scalable dynamic height
// field rendering", I3D 2008): the exact first hit, like `exact`, found by a hierarchical walk of
// a maximum-height pyramid (kernels/prep/maxmip.cl) instead of every cell: where the ray stays
// above a block's maximum the whole block is skipped; where it dips below, the walk descends, down
// to single cells solved exactly (om_patch_hit, shared with `exact`). Inside a block the ray first
// jumps to where it reaches the block's maximum height. p[0] = the highest level used (0: plain
// DDA, identical to `exact`). Cost: O(log n) block tests plus the cells near the hit. The hierarchy
// needs wrap addressing and level 0 of the height pyramid (no LOD level); otherwise the walk stays
// at level 0 and is `exact`.

// Levels of the max pyramid for this map: while both sizes stay even (blocks tile the map).
inline int om_maxmip_levels(const OmOffsetParams* P) {
    if (P->address_mode != OM_ADDRESS_WRAP) return 0;
    int levels = 0, w = P->hf_width, h = P->hf_height;
    while (levels < 15 && (w & 1) == 0 && (h & 1) == 0) {
        w >>= 1;
        h >>= 1;
        ++levels;
    }
    return levels;
}

// floor(i / 2^k) for any sign (a right shift of a negative int is implementation-defined in C99).
inline int om_block_index(int i, int k) { return i >= 0 ? i >> k : -((-i - 1) >> k) - 1; }

// The cell index along one axis at ray parameter t, kept inside [lo, hi] (rounding at block faces).
inline int om_cell_at(float c0, float d, float t, int lo, int hi) {
    return clamp((int)om_floor(c0 - t * d), lo, hi);
}

float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    int top = f->level == 0 ? min(om_maxmip_levels(P), (int)P->p[0]) : 0;
    int offset[16];  // start of level k in the aux buffer (level 1 at 0)
    offset[1] = 0;
    for (int k = 1; k < top; ++k)
        offset[k + 1] = offset[k] + (P->hf_width >> k) * (P->hf_height >> k);

    float2 c0 = om_cell_coord(f, r->uv);
    float2 d = OM_F2(r->v.x * f->fw, r->v.y * f->fh);
    // Blocks wider than the ray's whole footprint cannot be skipped more cheaply than walked: the
    // walk starts at, and never climbs past, the level of the footprint's length in cells.
    float span = (r->t_exit - r->t_enter) * fmax(fabs(d.x), fabs(d.y));
    top = min(top, span > 1.0f ? (int)ceil(log2(span)) : 0);
    int si = d.x > 0.0f ? -1 : 1, sj = d.y > 0.0f ? -1 : 1;
    float t = r->t_enter;
    int i = (int)om_floor(c0.x - t * d.x), j = (int)om_floor(c0.y - t * d.y);
    int k = top;
    // Each step descends a level or leaves a block: bounded by the cells crossed times the levels.
    int cap = min(P->max_cells, 0x3fffffff / (2 * top + 2)) * (2 * top + 2);
    int n = 0;
    for (; n < cap; ++n) {
        int size = 1 << k;
        int I = om_block_index(i, k), J = om_block_index(j, k);
        int x_lo = I * size, y_lo = J * size;
        int bx = si < 0 ? x_lo : x_lo + size, by = sj < 0 ? y_lo : y_lo + size;
        float tx = d.x != 0.0f ? (c0.x - (float)bx) / d.x : INFINITY;
        float ty = d.y != 0.0f ? (c0.y - (float)by) / d.y : INFINITY;
        float t_out = fmin(fmin(tx, ty), r->t_exit);
        if (k == 0) {
            float hit;
            if (om_patch_hit(r, f, i, j, c0, d, t, t_out, &hit)) {
                *t_hit = hit;
                return om_ray_uv(r, hit);
            }
        } else {
            int wk = P->hf_width >> k, hk = P->hf_height >> k;
            float block_max = f->aux[offset[k] + om_wrap_index(J, hk) * wk + om_wrap_index(I, wk)];
            f->fetches += 1u;
            // The ray (z = -t V.z) is above the block's ceiling until t_ceiling.
            float t_ceiling = -r->scale * (block_max - r->ref) / r->v.z;
            if (t_ceiling < t_out) {
                if (t_ceiling > t) {
                    t = t_ceiling;
                    i = om_cell_at(c0.x, d.x, t, x_lo, x_lo + size - 1);
                    j = om_cell_at(c0.y, d.y, t, y_lo, y_lo + size - 1);
                }
                --k;  // the ray dips below the ceiling in this block: look closer
                continue;
            }
        }
        // Nothing here: leave the block through its exit face and look wider again.
        if (t_out >= r->t_exit) break;
        t = t_out;
        if (tx <= ty) {
            i = si < 0 ? x_lo - 1 : x_lo + size;
            j = om_cell_at(c0.y, d.y, t, y_lo, y_lo + size - 1);
        } else {
            j = sj < 0 ? y_lo - 1 : y_lo + size;
            i = om_cell_at(c0.x, d.x, t, x_lo, x_lo + size - 1);
        }
        // Climb only when the new cell lies in another parent block: the old parent's ceiling
        // was already found above the ray, so testing it again would only cost a fetch.
        if (k < top && (om_block_index(i, k + 1) != om_block_index(I, 1) ||
                        om_block_index(j, k + 1) != om_block_index(J, 1)))
            ++k;
    }
    if (n == cap) *flags |= OM_FLAG_CAPPED;
    *t_hit = r->t_exit;
    return om_ray_uv(r, r->t_exit);
}
