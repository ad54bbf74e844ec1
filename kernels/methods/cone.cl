// cone: cone step mapping (Dummer 2006; Policarpo & Oliveira, GPU Gems 3 ch. 18) made robust and
// exact. The cone map (kernels/prep/cone.cl) gives every cell its maximum height Hc and a cone
// ratio c (texels per unit of H) whose cone over the whole cell is free of relief, so a step by the
// cone is safe from any point of the cell, whatever bilinear filtering does between texel centres
// (the failure Bán et al., "Robust cone step mapping", EGSR 2024, point out in per-texel cones).
// Per cell the ray is in:
//  - if the ray stays above Hc until it leaves the cell, the cell is empty: step by the larger of
//    the cone step and the cell exit (both safe). This minimum step is what keeps conservative
//    cones from crawling near the surface (Bán et al.'s minimum step size; Policarpo's relaxed
//    cones get their speed by allowing an overshoot, which then needs a binary search and can cross
//    thin features twice).
//  - otherwise solve the cell exactly (om_patch_hit, shared with `exact`): the first root is
//  the
//    answer, else go on from the cell exit.
// So the result is `exact`'s, to float precision, and each step leaves at least one cell.
// Cone step from height Hr (H units) with the ray moving |d| texels across and V.z / s in H per
// unit t: it stays in the cone while |d| dt < c (Hr - V.z/s dt - Hc), i.e. dt = c (Hr - Hc) / (|d|
// + c V.z/s). Clamp addressing: cells off the map have no cone (c = 0: walked cell by cell). Cost:
// one cone fetch per step plus one patch per cell the ray dips below its cell maximum.

// Each lane's cell maximum and cone ratio (clamp: cells off the map have no cone, their maximum
// from the patch itself): its word of the packed, tiled cone map, decoded as om_cone_hc and
// om_cone_ratio do (om_shared.h); tiles_x is the map's tiles per row.
OM_INLINE void om_cone_cell(const OmField* f, int tiles_x, OmI i, OmI j, OmF* hc,
                            OmF* c OM_IMG_PARAM) {
    OmI i0, i1, j0, j1;
    om_patch_address(f, i, j, &i0, &i1, &j0, &j1);  // the cell's own texel, after the address mode
    OmI outside = f->wrap ? (OmI)0 : (OmI)(i != i0 || j != j0);
    OmI q = OM_AS_INT(OM_GATHER(f->aux, OM_CONE_INDEX(i0, j0, tiles_x)));
    *hc = OM_TO_FLOAT(q & 0xffff) * (1.0f / OM_CONE_HC_SCALE);
    OmF root = OM_TO_FLOAT((q >> 16) & 0xffff) * (1.0f / OM_CONE_C_SCALE);
    *c = OM_SEL(root * root, 0.0f, outside);
    if (OM_ANY(outside)) {
        OmF k00, k10, k01, k11;
        om_corners(f, i, j, &k00, &k10, &k01, &k11 OM_IMG_ARG);
        *hc = OM_SEL(*hc, fmax(fmax(k00, k10), fmax(k01, k11)), outside);
    }
}

OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmWalk w = om_walk(r, f);
    OmF across = sqrt(w.dx * w.dx + w.dy * w.dy), down = r->vz / r->scale;  // per unit t: texels, H
    OmF t = r->t_enter;
    OmI i, j;
    om_walk_cell(&w, t, &i, &j);
    // The cone map is built from level 0: under LOD (a coarser level) walk cells like `exact`.
    OmI cones = f->level == 0;
    const int tiles_x = om_cone_tiles(P->hf_width);
    OmF hit_t = r->t_exit;
    OmI done = !active;
    for (int n = 0; n < P->max_cells && OM_ANY(!done); ++n) {
        OmI live = !done;
        OmF tx, ty;
        OmF t_out = om_walk_exit(&w, i, j, (OmI)1, r->t_exit, &tx, &ty);
        OmF hc, c;
        om_cone_cell(f, tiles_x, i, j, &hc, &c OM_IMG_ARG);
        *fetches += OM_ONE(live & cones);
        hc = OM_SEL((OmF)1.0f, hc, cones);
        c = OM_SEL((OmF)0.0f, c, cones);
        OmI below = live & (r->ref - t_out * down < hc);
        if (OM_ANY(below)) {
            OmF th;
            OmI hit = om_patch_hit(r, f, &w, i, j, t, t_out, below, fetches, &th OM_IMG_ARG);
            hit_t = OM_SEL(hit_t, th, hit);
            done |= hit;
            live &= !hit;
        }
        // Above the cell's maximum through the cell: the larger of the cone step and the exit.
        OmF t_cone = t + c * (r->ref - t * down - hc) / (across + c * down);
        OmI jump = live & !below & (c > 0.0f) & (t_cone > t_out);
        OmI past = jump & (t_cone >= r->t_exit);  // leaves the slab above the relief: no hit
        done |= past;
        jump &= !past;
        OmI ni, nj;
        om_walk_cell(&w, t_cone, &ni, &nj);
        jump &= ni != i || nj != j;  // rounding can leave it in this cell: step normally
        t = OM_SEL(t, t_cone, jump);
        i = OM_SEL(i, ni, jump);
        j = OM_SEL(j, nj, jump);
        // Otherwise on to the next cell through the exit face.
        OmI step = live & !past & !jump;
        OmI end = step & (t_out >= r->t_exit);
        done |= end;
        om_walk_step(&w, step & !end, tx, ty, t_out, &t, &i, &j);
    }
    // Lanes still walking ran out of cells.
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !done);
    return hit_t;
}
