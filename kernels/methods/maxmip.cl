// maxmip (Tevs, Ihrke & Seidel, "Maximum mipmaps for fast, accurate, and scalable dynamic height
// field rendering", I3D 2008): the exact first hit, like `exact`, found by a hierarchical walk of
// a maximum-height pyramid (kernels/prep/maxmip.cl) instead of every cell: where the ray stays
// above a block's maximum the whole block is skipped; where it dips below, the walk descends, down
// to single cells solved exactly (om_patch_hit, shared with `exact`). Inside a block the ray
// first jumps to where it reaches the block's maximum height. `max_level` = the highest level used
// (0: plain DDA, identical to `exact`). Cost: O(log n) block tests plus the cells near the hit. The
// hierarchy needs level 0 of the height pyramid (no LOD level); otherwise the walk stays at level 0
// and is `exact`.
// Any map size, either address mode: blocks are laid out per tile of the map (a tile's last block
// along an axis may be partial, its stored maximum taken over the padded pyramid's wider block, a
// superset), and the walk's unbounded cell grid is cut at tile edges, so a block never straddles
// one. Under clamp addressing the relief outside the tile is the edge texels extruded: a block
// there takes its maximum from the tile's edge block on that side, which covers the edge texels.
// Over a curved base (OM_CURVED) the entry hands this method the tangent plane's lanes only (the
// walks' bounds hold for the straight ray): the curved lanes walk every cell (common/curved.cl).
#define OM_CURVED_WALK

// Each lane walks its own levels and blocks; the loop ends when every lane has its answer.

// The tile of cell i along an axis of n cells, floor(i / n), and the cell's place in it, i - tile n
// (by a float reciprocal, corrected by one either way).
OM_INLINE OmI om_tile_of(OmI i, int n, float inv_n, OmI* place) {
    OmI tile = OM_TO_INT(OM_LFLOOR(OM_TO_FLOAT(i) * inv_n));
    OmI l = i - tile * n;
    OmI over = l >= n, under = l < 0;
    tile = OM_SEL(OM_SEL(tile, tile - 1, under), tile + 1, over);
    *place = OM_SEL(OM_SEL(l, l + n, under), l - n, over);
    return tile;
}

// The cell index along one axis at ray parameter t, kept inside [lo, hi] (rounding at faces).
OM_INLINE OmI om_cell_at(OmF c0, OmF d, OmF t, OmI lo, OmI hi) {
    return clamp(OM_TO_INT(OM_LFLOOR(c0 - t * d)), lo, hi);
}

// Where the ray leaves the cells [x_lo, x_hi) x [y_lo, y_hi) (om_walk_exit for a rectangle).
OM_INLINE OmF om_rect_exit(const OmWalk* w, OmI x_lo, OmI x_hi, OmI y_lo, OmI y_hi, OmF t_exit,
                           OmF* tx, OmF* ty) {
    OmI bx = OM_SEL(x_hi, x_lo, w->si < 0), by = OM_SEL(y_hi, y_lo, w->sj < 0);
    *tx = OM_SEL((OmF)INFINITY, (w->cx - OM_TO_FLOAT(bx)) / w->dx, w->dx != 0.0f);
    *ty = OM_SEL((OmF)INFINITY, (w->cy - OM_TO_FLOAT(by)) / w->dy, w->dy != 0.0f);
    return fmin(fmin(*tx, *ty), t_exit);
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
    // With `beam` on, the lanes first skip together what the beam proves empty (common/beam.cl).
    if (OM_PARAM(P, beam) != 0.0f) t = om_beam_start(r, f, &w, f->aux, P, active, fetches);
    OmI i, j;
    om_walk_cell(&w, t, &i, &j);
    OmI k = top;
    const int levels = om_maxmip_levels(W, H, P->address_mode);
    const int Wp = om_maxmip_padded(W, levels), Hp = om_maxmip_padded(H, levels);
    const float inv_w = 1.0f / (float)W, inv_h = 1.0f / (float)H;
    const OmI clamped = (OmI)(P->address_mode != OM_ADDRESS_WRAP) != 0;
    // Each step descends a level or leaves a block: bounded by the cells crossed times the levels.
    OmI cap = min((OmI)P->max_cells, 0x3fffffff / (2 * top + 2)) * (2 * top + 2);
    OmF hit_t = r->t_exit;
    OmI live = active, capped = 0;
    for (int n = 0; OM_ANY(live); ++n) {
        capped |= live & ((OmI)n >= cap);
        live &= (OmI)n < cap;
        // The block of level k holding cell (i, j), cut at its tile's edges.
        OmI li, lj;
        OmI ti = om_tile_of(i, W, inv_w, &li), tj = om_tile_of(j, H, inv_h, &lj);
        OmI bi = li >> k, bj = lj >> k;
        OmI x_lo = ti * W + (bi << k), y_lo = tj * H + (bj << k);
        OmI x_hi = min(x_lo + ((OmI)1 << k), ti * W + W);
        OmI y_hi = min(y_lo + ((OmI)1 << k), tj * H + H);
        OmF tx, ty;
        OmF t_out = om_rect_exit(&w, x_lo, x_hi, y_lo, y_hi, r->t_exit, &tx, &ty);
        // Level 0: solve the cell.
        OmI cell = live & (k == 0);
        if (OM_ANY(cell)) {
            OmF th;
            OmI hit = om_patch_hit(r, f, &w, i, j, t, t_out, cell, fetches, &th OM_IMG_ARG);
            hit_t = OM_SEL(hit_t, th, hit);
            live &= !hit;
        }
        // Above level 0: the block's ceiling. Level k of the padded pyramid starts at the sum over
        // 1 <= m < k of (Wp H p / 4^m) floats (the padded sizes halve exactly at every level).
        OmI block = live & (k > 0);
        OmI descend = 0;
        if (OM_ANY(block)) {
            OmI km = max(k - 1, (OmI)0), wk = (OmI)Wp >> k;
            OmI offset = ((OmI)Wp >> km) * ((OmI)Hp >> km) * (((OmI)1 << (2 * km)) - 1) / 3;
            // Clamp: outside the tile the edge block on that side bounds the extruded relief.
            OmI si = OM_SEL(bi, OM_SEL(((OmI)(W - 1)) >> k, (OmI)0, ti < 0), clamped & (ti != 0));
            OmI sj = OM_SEL(bj, OM_SEL(((OmI)(H - 1)) >> k, (OmI)0, tj < 0), clamped & (tj != 0));
            OmI idx = offset + sj * wk + si;
            OmF block_max = OM_GATHER(f->aux, OM_SEL((OmI)0, idx, block));
            *fetches += OM_ONE(block);
            // The ray (z = -t V.z) is above the block's ceiling until t_ceiling.
            OmF t_ceiling = -r->scale * (block_max - r->ref) / r->vz;
            descend = block & (t_ceiling < t_out);
            OmI jump = descend & (t_ceiling > t);
            t = OM_SEL(t, t_ceiling, jump);
            i = OM_SEL(i, om_cell_at(w.cx, w.dx, t, x_lo, x_hi - 1), jump);
            j = OM_SEL(j, om_cell_at(w.cy, w.dy, t, y_lo, y_hi - 1), jump);
            k = OM_SEL(k, k - 1, descend);  // the ray dips below the ceiling: look closer
        }
        // Nothing here: leave the block through its exit face and look wider again.
        OmI leave = live & !descend;
        OmI end = leave & (t_out >= r->t_exit);
        live &= !end;
        leave &= !end;
        t = OM_SEL(t, t_out, leave);
        OmI along_x = tx <= ty;
        OmI ni = OM_SEL(om_cell_at(w.cx, w.dx, t, x_lo, x_hi - 1),
                        OM_SEL(x_hi, x_lo - 1, w.si < 0), along_x);
        OmI nj = OM_SEL(OM_SEL(y_hi, y_lo - 1, w.sj < 0),
                        om_cell_at(w.cy, w.dy, t, y_lo, y_hi - 1), along_x);
        i = OM_SEL(i, ni, leave);
        j = OM_SEL(j, nj, leave);
        // Climb only when the new cell lies outside the old block's parent (in the same tile):
        // the parent's ceiling was already found above the ray, so testing it again would only
        // cost a fetch.
        OmI px_lo = ti * W + ((bi >> 1) << (k + 1)), py_lo = tj * H + ((bj >> 1) << (k + 1));
        OmI px_hi = min(px_lo + ((OmI)2 << k), ti * W + W);
        OmI py_hi = min(py_lo + ((OmI)2 << k), tj * H + H);
        OmI climb = leave & (k < top) &
                    (i < px_lo || i >= px_hi || j < py_lo || j >= py_hi);
        k = OM_SEL(k, k + 1, climb);
    }
    // Lanes still live: the loop was ended from outside (llvmpipe stops a kernel's loops after
    // 65535 iterations in all), so their walks are as unfinished as capped ones.
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, capped | live);
    return hit_t;
}
