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
// Over a curved base (OM_CURVED) the entry hands this method the tangent plane's lanes only (the
// walks' bounds hold for the straight ray): the curved lanes walk every cell (common/curved.cl).
#define OM_CURVED_WALK

// Each lane's cell maximum and cone ratio (clamp: cells off the map have no cone, their maximum
// from the patch itself): its word of the packed, tiled cone map, decoded by the same macros as
// om_cone_hc and om_cone_ratio (methods/cone_map.h); tiles_x is the map's tiles per row.
OM_INLINE void om_cone_cell(const OmField* f, int tiles_x, OmI i, OmI j, OmF* hc,
                            OmF* c OM_IMG_PARAM) {
    OmI i0, i1, j0, j1;
    om_patch_address(f, i, j, &i0, &i1, &j0, &j1);  // the cell's own texel, after the address mode
    OmI outside = f->wrap ? (OmI)0 : (OmI)(i != i0 || j != j0);
    OmI q = OM_AS_INT(OM_GATHER(f->aux, OM_CONE_INDEX(i0, j0, tiles_x)));
    *hc = OM_CONE_HC_OF(OM_TO_FLOAT(q & 0xffff));
    OmF root = OM_CONE_ROOT_OF(OM_TO_FLOAT((q >> 16) & 0xffff));
    *c = OM_SEL(root * root, 0.0f, outside);
    if (OM_ANY(outside)) {
        OmF k00, k10, k01, k11;
        om_corners(f, i, j, &k00, &k10, &k01, &k11 OM_IMG_ARG);
        *hc = OM_SEL(*hc, fmax(fmax(k00, k10), fmax(k01, k11)), outside);
    }
}

// One group of lanes' walk, advanced a step at a time so that two groups can share a loop.
typedef struct {
    OmWalk w;
    OmF across, down;  // per unit t: texels crossed, H descended
    OmF t, hit_t;
    OmI i, j;
    OmI cones;  // the cone map is built from level 0: under LOD (a coarser level) walk like `exact`
    OmI done;
} OmConeWalk;

OM_INLINE void om_cone_begin(const OmRay* r, const OmField* f, OmI active, OmConeWalk* s) {
    s->w = om_walk(r, f);
    s->across = sqrt(s->w.dx * s->w.dx + s->w.dy * s->w.dy);
    s->down = r->vz / r->scale;
    s->t = r->t_enter;
    om_walk_cell(&s->w, s->t, &s->i, &s->j);
    s->cones = f->level == 0;
    s->hit_t = r->t_exit;
    s->done = !active;
}

// One cell (or cone jump) for the lanes not done.
OM_INLINE void om_cone_step(const OmRay* r, const OmField* f, int tiles_x, OmConeWalk* s,
                            OmI* fetches OM_IMG_PARAM) {
    OmF t = s->t, down = s->down;
    OmI i = s->i, j = s->j, cones = s->cones;
    OmI live = !s->done;
    OmF tx, ty;
    OmF t_out = om_walk_exit(&s->w, i, j, (OmI)1, r->t_exit, &tx, &ty);
    OmF hc, c;
    om_cone_cell(f, tiles_x, i, j, &hc, &c OM_IMG_ARG);
    *fetches += OM_ONE(live & cones);
    hc = OM_SEL((OmF)1.0f, hc, cones);
    c = OM_SEL((OmF)0.0f, c, cones);
    OmI below = live & (r->ref - t_out * down < hc);
    if (OM_ANY(below)) {
        OmF th;
        OmI hit = om_patch_hit(r, f, &s->w, i, j, t, t_out, below, fetches, &th OM_IMG_ARG);
        s->hit_t = OM_SEL(s->hit_t, th, hit);
        s->done |= hit;
        live &= !hit;
    }
    // Above the cell's maximum through the cell: the larger of the cone step and the exit.
    OmF t_cone = t + c * (r->ref - t * down - hc) / (s->across + c * down);
    OmI jump = live & !below & (c > 0.0f) & (t_cone > t_out);
    OmI past = jump & (t_cone >= r->t_exit);  // leaves the slab above the relief: no hit
    s->done |= past;
    jump &= !past;
    OmI ni, nj;
    om_walk_cell(&s->w, t_cone, &ni, &nj);
    jump &= ni != i || nj != j;  // rounding can leave it in this cell: step normally
    t = OM_SEL(t, t_cone, jump);
    i = OM_SEL(i, ni, jump);
    j = OM_SEL(j, nj, jump);
    // Otherwise on to the next cell through the exit face.
    OmI step = live & !past & !jump;
    OmI end = step & (t_out >= r->t_exit);
    s->done |= end;
    om_walk_step(&s->w, step & !end, tx, ty, t_out, &t, &i, &j);
    s->t = t;
    s->i = i;
    s->j = j;
}

OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    const int tiles_x = om_cone_tiles(P->hf_width);
    OmConeWalk s;
    om_cone_begin(r, f, active, &s);
    // With `beam` on, the lanes first skip together what the beam proves empty (common/beam.cl),
    // over the max pyramid stored after the cone map's tiles.
    if (OM_PARAM(P, beam) != 0.0f) {
        s.t = om_beam_start(r, f, &s.w, om_cone_pyramid(f->aux, P->hf_width, P->hf_height), P,
                            active, fetches);
        om_walk_cell(&s.w, s.t, &s.i, &s.j);
    }
    for (int n = 0; n < P->max_cells && OM_ANY(!s.done); ++n)
        om_cone_step(r, f, tiles_x, &s, fetches OM_IMG_ARG);
    // Lanes still walking ran out of cells.
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !s.done);
    return s.hit_t;
}

// Two groups of lanes walked in one loop (the entry's OM_LANE_PAIRS): a cone jump waits on its
// cone-map read, and with two independent walks in flight the core works on one group while the
// other's read is outstanding (a gain with AVX-512's gathers; none under AVX2, whose reads are
// scalar loads that already overlap: docs/throughput.md). Each group steps exactly
// as om_trace steps it, so the frame is the same bit for bit.
OM_INLINE void om_trace_pair(const OmRay* ra, const OmField* fa, OmI active_a, const OmRay* rb,
                             const OmField* fb, OmI active_b, const OmOffsetParams* P, OmF* ta,
                             OmI* fetches_a, OmI* flags_a, OmF* tb, OmI* fetches_b,
                             OmI* flags_b OM_IMG_PARAM) {
    const int tiles_x = om_cone_tiles(P->hf_width);
    OmConeWalk a, b;
    om_cone_begin(ra, fa, active_a, &a);
    om_cone_begin(rb, fb, active_b, &b);
    if (OM_PARAM(P, beam) != 0.0f) {
        om_beam_start_pair(ra, fa, &a.w, active_a, fetches_a, &a.t, rb, fb, &b.w, active_b,
                           fetches_b, &b.t, om_cone_pyramid(fa->aux, P->hf_width, P->hf_height), P);
        om_walk_cell(&a.w, a.t, &a.i, &a.j);
        om_walk_cell(&b.w, b.t, &b.i, &b.j);
    }
    OM_PAIR_LOOP(P->max_cells,  //
                 OM_ANY(!a.done), om_cone_step(ra, fa, tiles_x, &a, fetches_a OM_IMG_ARG),
                 OM_ANY(!b.done), om_cone_step(rb, fb, tiles_x, &b, fetches_b OM_IMG_ARG));
    *flags_a |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !a.done);
    *flags_b |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !b.done);
    *ta = a.hit_t;
    *tb = b.hit_t;
}
