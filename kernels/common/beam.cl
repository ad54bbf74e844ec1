// The beam: a work-item's rays skip the empty space above the relief together (docs/design.md,
// "Rays that share their empty-space skipping"). Parametrised by height H, lane k's footprint in
// cell coordinates is linear, c_k(H) = c_k(1) + (H - 1) g_k with g_k = s (dx, dy) / V.z, so over a
// height interval [H1, H0] (H <= 1) every lane's x lies in
//   [min_k x_k(1) + (H - 1) max_k gx_k, max_k x_k(1) + (H - 1) min_k gx_k],
// whose ends are linear in H (y alike); where the largest cell maximum of the max pyramid's blocks
// covering that box is at most H1, no lane's relief reaches its ray above H1: every lane may start
// at H1. Each step is scalar work and at most OM_BEAM_SIDE^2 scalar reads shared by all of the
// work-item's lanes; the lanes then walk on alone. Without lanes (OM_LANES 1, a GPU's work-item)
// the beam is the one ray's: a coarse max-mip descent.

// The lanes' footprints as a box in H: x in [x_lo + (H - 1) gx_hi, x_hi + (H - 1) gx_lo] for the
// part of a descent below the top, and the same in y.
typedef struct {
    float x_lo, x_hi, gx_lo, gx_hi;
    float y_lo, y_hi, gy_lo, gy_hi;
} OmBeam;

// Blocks read a side per beam step: the finest level at which the box's cells lie in so many.
#define OM_BEAM_SIDE 3

// The blocks of level L that hold cells [c0, c1] along an axis of n cells (n a multiple of 2^L),
// cut at tile edges as maxmip's walk cuts them (wrap: the tile-local cell's block; clamp: cells
// off the map read the edge block, which bounds the extruded edge texels): the first, p, in the
// unbounded grid and their count. The stored index of block p + k is om_beam_block(p + k, ...).
OM_INLINE int om_beam_blocks(int c0, int c1, int n, int L, int wrap, int* p) {
    if (!wrap) {
        c0 = clamp(c0, 0, n - 1);
        c1 = clamp(c1, 0, n - 1);
    }
    *p = c0 >> L;  // arithmetic: floor for the cells left of the tile too
    return (c1 >> L) - *p + 1;
}
// (om_wrap's rule, sampling.cl, for one scalar: lanes here are the beam's, not the pixels'.)
OM_INLINE int om_beam_block(int b, int blocks) {
    if ((blocks & (blocks - 1)) == 0) return b & (blocks - 1);
    const int r = b - (int)floor((float)b / (float)blocks) * blocks;  // by float, corrected
    return r < 0 ? r + blocks : r >= blocks ? r - blocks : r;
}

// The largest cell maximum over the cells of [x0, x1] x [y0, y1] (cell coordinates, a margin
// already added), from the pyramid's finest level (>= 1, at most top and unit) at which they lie
// in OM_BEAM_SIDE^2 blocks; INFINITY where none holds them so (the box is too wide to tell).
// `unit`: the finest level whose blocks tile the map (2^unit divides both sides).
OM_INLINE float om_beam_ceiling(__global const float* pyramid, const OmOffsetParams* P, int top,
                                int unit, int Wp, int Hp, float x0, float x1, float y0, float y1) {
    if (!(x1 - x0 < 1.0e6f && y1 - y0 < 1.0e6f)) return INFINITY;  // NaN too
    const int i0 = (int)floor(x0), i1 = (int)floor(x1), j0 = (int)floor(y0), j1 = (int)floor(y1);
    const int wrap = P->address_mode == OM_ADDRESS_WRAP;
    // OM_BEAM_SIDE blocks of 2^L cells hold any span below 2^(L+1) (for a side of 3 or more).
    int L = max(1, 31 - (int)clz(max(i1 - i0, j1 - j0)));
    for (; L <= min(top, unit); ++L) {
        int pi, pj;
        const int ni = om_beam_blocks(i0, i1, P->hf_width, L, wrap, &pi);
        const int nj = om_beam_blocks(j0, j1, P->hf_height, L, wrap, &pj);
        if (ni > OM_BEAM_SIDE || nj > OM_BEAM_SIDE) continue;
        const int wk = Wp >> L;
        __global const float* level = pyramid + om_maxmip_level_start(Wp, Hp, L);
        float m = -INFINITY;
        for (int b = 0; b < nj; ++b) {
            __global const float* row = level + om_beam_block(pj + b, P->hf_height >> L) * wk;
            for (int a = 0; a < ni; ++a) m = fmax(m, row[om_beam_block(pi + a, P->hf_width >> L)]);
        }
        return m;
    }
    return INFINITY;
}

// One work-item group's beam, a step at a time, so that two groups' beams can share a loop (their
// reads wait on each other's steps, not their own).
typedef struct {
    OmBeam b;
    float margin, spread, reach;
    float h0, dh;  // free above h0; the next interval tried is [h0 - dh, h0]
    int top, unit, Wp, Hp;
    int n, done;
} OmBeamWalk;

// The box's coefficients over the lanes of `active`. A beam is done at once without such lanes, at
// a coarser level than 0 (the pyramid is level 0's), without a pyramid, or where 2 does not
// divide both of the map's sides (no level's blocks would tile it).
OM_INLINE void om_beam_begin(const OmRay* r, const OmField* f, const OmWalk* w,
                             const OmOffsetParams* P, OmI active, OmBeamWalk* s) {
    s->h0 = 1.0f;
    s->dh = 1.0f;
    s->n = 0;
    s->top = om_maxmip_levels(P->hf_width, P->hf_height, P->address_mode);
    s->unit = 0;
    while (s->unit < s->top && (((P->hf_width | P->hf_height) >> s->unit) & 1) == 0) ++s->unit;
    s->done = s->unit < 1 || !OM_ANY(active) || OM_ANY(f->level != 0);
    if (s->done) return;
    s->Wp = om_maxmip_padded(P->hf_width, s->top);
    s->Hp = om_maxmip_padded(P->hf_height, s->top);
    // Per unit H the footprint moves g = s d / V.z cells (t = s (r - H) / V.z); c(1) = c(t_enter).
    const OmF inv = r->scale / r->vz;
    const OmF gx = w->dx * inv, gy = w->dy * inv;
    const OmF x1 = w->cx - r->t_enter * w->dx, y1 = w->cy - r->t_enter * w->dy;
    OmBeam* b = &s->b;
    b->x_lo = OM_LANE_FMIN(OM_SEL((OmF)INFINITY, x1, active));
    b->x_hi = OM_LANE_FMAX(OM_SEL((OmF)-INFINITY, x1, active));
    b->gx_lo = OM_LANE_FMIN(OM_SEL((OmF)INFINITY, gx, active));
    b->gx_hi = OM_LANE_FMAX(OM_SEL((OmF)-INFINITY, gx, active));
    b->y_lo = OM_LANE_FMIN(OM_SEL((OmF)INFINITY, y1, active));
    b->y_hi = OM_LANE_FMAX(OM_SEL((OmF)-INFINITY, y1, active));
    b->gy_lo = OM_LANE_FMIN(OM_SEL((OmF)INFINITY, gy, active));
    b->gy_hi = OM_LANE_FMAX(OM_SEL((OmF)-INFINITY, gy, active));
    // Float footprints against the walks' own: a hundredth of a cell and a few ulp of the place.
    s->margin = 0.01f + 4.0e-7f * fmax(fmax(fabs(b->x_lo), fabs(b->x_hi)),
                                       fmax(fabs(b->y_lo), fabs(b->y_hi)));
    // Shorter intervals stop paying once the lanes' own spread is most of the box.
    s->spread = fmax(b->x_hi - b->x_lo, b->y_hi - b->y_lo) + 1.0f;
    s->reach = fmax(fmax(fabs(b->gx_lo), fabs(b->gx_hi)), fmax(fabs(b->gy_lo), fabs(b->gy_hi)));
}

// One interval: free down to its end (then try one twice as long), or down to the ceiling found
// (then one half as long, unless the lanes' spread is already most of its box: done).
OM_INLINE void om_beam_step(__global const float* pyramid, const OmOffsetParams* P, OmBeamWalk* s) {
    const OmBeam* b = &s->b;
    const float h0 = s->h0, h1 = fmax(h0 - s->dh, 0.0f), e0 = h0 - 1.0f, e1 = h1 - 1.0f;  // e <= 0
    const float cx0 = fmin(b->x_lo + e0 * b->gx_hi, b->x_lo + e1 * b->gx_hi) - s->margin;
    const float cx1 = fmax(b->x_hi + e0 * b->gx_lo, b->x_hi + e1 * b->gx_lo) + s->margin;
    const float cy0 = fmin(b->y_lo + e0 * b->gy_hi, b->y_lo + e1 * b->gy_hi) - s->margin;
    const float cy1 = fmax(b->y_hi + e0 * b->gy_lo, b->y_hi + e1 * b->gy_lo) + s->margin;
    const float m = om_beam_ceiling(pyramid, P, s->top, s->unit, s->Wp, s->Hp, cx0, cx1, cy0, cy1);
    if (m <= h1) {
        s->h0 = h1;
        s->dh *= 2.0f;
    } else {
        s->h0 = fmin(h0, m);
        s->done = s->dh * s->reach < s->spread;
        s->dh = 0.5f * fmin(s->dh, s->h0);
    }
    ++s->n;
    s->done |= s->n >= OM_BEAM_STEPS || !(s->h0 > 0.0f);
}

// Each lane's safe start: the ray parameter at which it reaches the lowest height the beam proved
// free above, backed off by 2^-20 of the height range (t_enter where the beam did not descend).
// `steps` counts the beam's steps on every lane of `active` (the lanes wait on them together).
OM_INLINE OmF om_beam_t(const OmRay* r, const OmBeamWalk* s, OmI active, OmI* steps) {
    *steps += OM_ONE(active) * (OmI)s->n;
    const OmF t = r->scale * (r->ref - (s->h0 + 1.0f / 1048576.0f)) / r->vz;
    return fmax(r->t_enter, fmin(t, r->t_exit));
}

OM_INLINE OmF om_beam_start(const OmRay* r, const OmField* f, const OmWalk* w,
                            __global const float* pyramid, const OmOffsetParams* P, OmI active,
                            OmI* steps) {
    OmBeamWalk s;
    om_beam_begin(r, f, w, P, active, &s);
    while (!s.done) om_beam_step(pyramid, P, &s);
    return om_beam_t(r, &s, active, steps);
}

// Two groups' beams in one loop (a method's om_trace_pair): each takes the steps it takes alone.
OM_INLINE void om_beam_start_pair(const OmRay* ra, const OmField* fa, const OmWalk* wa,
                                  OmI active_a, OmI* steps_a, OmF* ta, const OmRay* rb,
                                  const OmField* fb, const OmWalk* wb, OmI active_b, OmI* steps_b,
                                  OmF* tb, __global const float* pyramid, const OmOffsetParams* P) {
    OmBeamWalk a, b;
    om_beam_begin(ra, fa, wa, P, active_a, &a);
    om_beam_begin(rb, fb, wb, P, active_b, &b);
    while (!a.done || !b.done) {
        if (!a.done) om_beam_step(pyramid, P, &a);
        if (!b.done) om_beam_step(pyramid, P, &b);
    }
    *ta = om_beam_t(ra, &a, active_a, steps_a);
    *tb = om_beam_t(rb, &b, active_b, steps_b);
}
