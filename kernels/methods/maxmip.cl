// maxmip (Tevs, Ihrke & Seidel, "Maximum mipmaps for fast, accurate, and scalable dynamic height
// field rendering", I3D 2008): the exact first hit, like `exact`, found by a hierarchical walk of
// a maximum-height pyramid (kernels/prep/maxmip.cl) instead of every cell: where the ray stays
// above a block's maximum the whole block is skipped; where it dips below, the walk descends, down
// to single cells solved exactly (om_patch_hit, shared with `exact`). Inside a block the ray
// first jumps to where it reaches the block's maximum height. `max_level` = the highest level used
// (0: plain DDA, identical to `exact`). Cost: O(log n) block tests plus the cells near the hit. The
// hierarchy needs wrap addressing and level 0 of the height pyramid (no LOD level); otherwise the
// walk stays at level 0 and is `exact`.

// Each lane walks its own levels and blocks; the loop ends when every lane has its answer.

// floor(i / 2^k) for any sign (a right shift of a negative int is implementation-defined in C99).
OM_INLINE OmI om_block(OmI i, OmI k) { return OM_SEL(-((-i - 1) >> k) - 1, i >> k, i >= 0); }

// The cell index along one axis at ray parameter t, kept inside [lo, hi] (rounding at faces).
OM_INLINE OmI om_cell_at(OmF c0, OmF d, OmF t, OmI lo, OmI hi) {
    return clamp(OM_TO_INT(OM_LFLOOR(c0 - t * d)), lo, hi);
}

OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    const int W = P->hf_width, H = P->hf_height;
    OmI top = OM_SEL((OmI)0,
                     (OmI)min(om_maxmip_levels(P->hf_width, P->hf_height, P->address_mode),
                              (int)OM_PARAM(P, max_level)),
                     f->level == 0);
    OmWalk w = om_walk(r, f);
    // Blocks wider than the ray's whole footprint cannot be skipped more cheaply than walked: the
    // walk starts at, and never climbs past, the level of the footprint's length in cells.
    OmF span = (r->t_exit - r->t_enter) * fmax(fabs(w.dx), fabs(w.dy));
    top = min(top, OM_SEL((OmI)0, OM_TO_INT(ceil(log2(span))), span > 1.0f));
    OmF t = r->t_enter;
    OmI i, j;
    om_walk_cell(&w, t, &i, &j);
    OmI k = top;
    // Each step descends a level or leaves a block: bounded by the cells crossed times the levels.
    OmI cap = min((OmI)P->max_cells, 0x3fffffff / (2 * top + 2)) * (2 * top + 2);
    OmF hit_t = r->t_exit;
    OmI live = active, capped = 0;
    for (int n = 0; OM_ANY(live); ++n) {
        capped |= live & ((OmI)n >= cap);
        live &= (OmI)n < cap;
        OmI size = (OmI)1 << k;
        OmI I = om_block(i, k), J = om_block(j, k);
        OmI x_lo = I * size, y_lo = J * size;
        OmF tx, ty;
        OmF t_out = om_walk_exit(&w, x_lo, y_lo, size, r->t_exit, &tx, &ty);
        // Level 0: solve the cell.
        OmI cell = live & (k == 0);
        if (OM_ANY(cell)) {
            OmF th;
            OmI hit = om_patch_hit(r, f, &w, i, j, t, t_out, cell, fetches, &th OM_IMG_ARG);
            hit_t = OM_SEL(hit_t, th, hit);
            live &= !hit;
        }
        // Above level 0: the block's ceiling. Level k starts at sum over m < k of (W H / 4^m)
        // floats from level 1 (sizes are divisible by 2^k at every level that exists).
        OmI block = live & (k > 0);
        OmI descend = 0;
        if (OM_ANY(block)) {
            OmI km = max(k - 1, 0), wk = (OmI)W >> k, hk = (OmI)H >> k;
            OmI offset = ((OmI)W >> km) * ((OmI)H >> km) * (((OmI)1 << (2 * km)) - 1) / 3;
            OmI idx = offset + om_wrap(J, max(hk, 1)) * wk + om_wrap(I, max(wk, 1));
            OmF block_max = OM_GATHER(f->aux, OM_SEL((OmI)0, idx, block));
            *fetches += OM_ONE(block);
            // The ray (z = -t V.z) is above the block's ceiling until t_ceiling.
            OmF t_ceiling = -r->scale * (block_max - r->ref) / r->vz;
            descend = block & (t_ceiling < t_out);
            OmI jump = descend & (t_ceiling > t);
            t = OM_SEL(t, t_ceiling, jump);
            i = OM_SEL(i, om_cell_at(w.cx, w.dx, t, x_lo, x_lo + size - 1), jump);
            j = OM_SEL(j, om_cell_at(w.cy, w.dy, t, y_lo, y_lo + size - 1), jump);
            k = OM_SEL(k, k - 1, descend);  // the ray dips below the ceiling: look closer
        }
        // Nothing here: leave the block through its exit face and look wider again.
        OmI leave = live & !descend;
        OmI end = leave & (t_out >= r->t_exit);
        live &= !end;
        leave &= !end;
        t = OM_SEL(t, t_out, leave);
        OmI along_x = tx <= ty;
        OmI ni = OM_SEL(om_cell_at(w.cx, w.dx, t, x_lo, x_lo + size - 1),
                        OM_SEL(x_lo + size, x_lo - 1, w.si < 0), along_x);
        OmI nj = OM_SEL(OM_SEL(y_lo + size, y_lo - 1, w.sj < 0),
                        om_cell_at(w.cy, w.dy, t, y_lo, y_lo + size - 1), along_x);
        i = OM_SEL(i, ni, leave);
        j = OM_SEL(j, nj, leave);
        // Climb only when the new cell lies in another parent block: the old parent's ceiling
        // was already found above the ray, so testing it again would only cost a fetch.
        OmI climb = leave & (k < top) &
                    (om_block(i, k + 1) != om_block(I, (OmI)1) ||
                     om_block(j, k + 1) != om_block(J, (OmI)1));
        k = OM_SEL(k, k + 1, climb);
    }
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, capped);
    return hit_t;
}
