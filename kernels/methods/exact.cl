// exact: the first hit of the eye ray with the bilinearly interpolated height field, the ground
// truth. A DDA walks the bilinear patches (cells between texel centres) the ray's footprint
// crosses from the top plane to the bottom plane, solving each (om_patch_hit,
// common/patch.cl). Cost: one patch (4 texels, counted as one fetch) per cell crossed, at most
// ~ (s / V.z)(W + H). Each lane walks its own cells; the loop ends when every lane has its
// answer.
// Over a curved base (OM_CURVED) the entry hands this method the tangent plane's lanes only (the
// walks' bounds hold for the straight ray): the curved lanes walk every cell (common/curved.cl).
#define OM_CURVED_WALK

// One group of lanes' walk, a cell at a time, so that two groups can share a loop.
typedef struct {
    OmWalk w;
    OmF t, hit_t;
    OmI i, j, done;
} OmExactWalk;

OM_INLINE void om_exact_begin(const OmRay* r, const OmField* f, OmI active, OmExactWalk* s) {
    s->w = om_walk(r, f);
    s->t = r->t_enter;
    om_walk_cell(&s->w, s->t, &s->i, &s->j);
    s->hit_t = r->t_exit;
    s->done = !active;
}

// The next cell for the lanes not done. No hit at the bottom plane: reached through rounding,
// where the gap is exactly 0 when H = 0 (the root at the segment's end can round away); the
// answer is then t_exit.
OM_INLINE void om_exact_step(const OmRay* r, const OmField* f, OmExactWalk* s,
                             OmI* fetches OM_IMG_PARAM) {
    OmI live = !s->done;
    OmF tx, ty, th;
    OmF t_out = om_walk_exit(&s->w, s->i, s->j, (OmI)1, r->t_exit, &tx, &ty);
    OmI hit = om_patch_hit(r, f, &s->w, s->i, s->j, s->t, t_out, live, fetches, &th OM_IMG_ARG);
    s->hit_t = OM_SEL(s->hit_t, th, hit);
    OmI end = live & !hit & (t_out >= r->t_exit);
    s->done |= hit | end;
    om_walk_step(&s->w, live & !hit & !end, tx, ty, t_out, &s->t, &s->i, &s->j);
}

OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmExactWalk s;
    om_exact_begin(r, f, active, &s);
    for (int n = 0; n < P->max_cells && OM_ANY(!s.done); ++n)
        om_exact_step(r, f, &s, fetches OM_IMG_ARG);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !s.done);  // ran out of cells
    return s.hit_t;
}

// Two groups of lanes walked in one loop (the entry's OM_LANE_PAIRS; see cone's om_trace_pair;
// its gain per instruction set: docs/throughput.md).
OM_INLINE void om_trace_pair(const OmRay* ra, const OmField* fa, OmI active_a, const OmRay* rb,
                             const OmField* fb, OmI active_b, const OmOffsetParams* P, OmF* ta,
                             OmI* fetches_a, OmI* flags_a, OmF* tb, OmI* fetches_b,
                             OmI* flags_b OM_IMG_PARAM) {
    OmExactWalk a, b;
    om_exact_begin(ra, fa, active_a, &a);
    om_exact_begin(rb, fb, active_b, &b);
    OM_PAIR_LOOP(P->max_cells, OM_ANY(!a.done), om_exact_step(ra, fa, &a, fetches_a OM_IMG_ARG),
                 OM_ANY(!b.done), om_exact_step(rb, fb, &b, fetches_b OM_IMG_ARG));
    *flags_a |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !a.done);
    *flags_b |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !b.done);
    *ta = a.hit_t;
    *tb = b.hit_t;
}
