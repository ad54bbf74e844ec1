// sphere (Donnelly 05; Premecz section 2.4): sphere tracing through a 3D distance map of the
// relief, precomputed by kernels/prep/distance.cl (`res` voxels per side over the tile,
// `layers` through the slab; `steps` at most). From the top plane the ray advances by the
// distance to the relief, so it can never pass through it.
// Conservative sampling: each voxel stores the distance from its whole box to a proxy that
// contains the relief, so the value of the voxel holding p is a safe step from anywhere inside it
// (Donnelly samples distances at voxel centres trilinearly, which can overestimate and overshoot).
// The step is 0 where p's voxel touches the proxy. Donnelly stops there (`cells` = 0): the error
// is then up to a voxel (1/res across, s/layers in height) plus the proxy's excess over the
// surface, which is the column's maximum: beside a peak, a groove is never reached, and on a map
// finer than the grid (1025 texels under 256 voxels) that is several texels.
// With `cells` = 1 the ray instead walks the bilinear cells inside that voxel, solving each
// exactly as `exact` does (om_patch_hit), and resumes sphere steps where it leaves the voxel
// above the relief: the empty space is skipped by the distance map, the surface is found by the
// patch solve, so the answer is `exact`'s.
// Cost: one fetch per sphere step, at most `steps` (a lane out of them walks the rest of its ray
// in cells; without cells it keeps its last point, above the relief), and one per cell solved (at
// most exact's cap on cells). Lanes that stop early wait for the others.
// Over a curved base (OM_CURVED) the entry hands this method the tangent plane's lanes only (the
// walks' bounds hold for the straight ray): the curved lanes walk every cell (common/curved.cl).
#define OM_CURVED_WALK
OM_INLINE OmF om_sphere_distance(const OmField* f, const OmOffsetParams* P, int res, int layers,
                                 OmF u, OmF v, OmF z) {
    OmF x = clamp(u * (float)res, -1.0e7f, 1.0e7f), y = clamp(v * (float)res, -1.0e7f, 1.0e7f);
    OmI i = OM_TO_INT(OM_LFLOOR(x)), j = OM_TO_INT(OM_LFLOOR(y));
    OmI k = clamp(OM_TO_INT(z), (OmI)0, (OmI)(layers - 1));
    const int wrap = P->address_mode == OM_ADDRESS_WRAP;
    i = om_address(i, (OmI)res, wrap);
    j = om_address(j, (OmI)res, wrap);
    return OM_GATHER(f->aux, (k * res + j) * res + i);
}

// Where the ray at t leaves the voxel it is moving into (on a face, the one past it, so the exit
// is always ahead): through a uv face of the res^2 grid or the layer's floor (x, y and z fall at
// res V.x, res V.y and z_per_t).
OM_INLINE OmF om_face_ahead(OmF x, OmF rate) {  // distance to the next face as x falls at rate
    return OM_SEL((OmF)INFINITY,
                  OM_SEL(OM_LFLOOR(x) + 1.0f - x, x - (ceil(x) - 1.0f), rate > 0.0f) / fabs(rate),
                  rate != 0.0f);
}

OM_INLINE OmF om_voxel_exit(const OmRay* r, int res, OmF t, OmF z, OmF z_per_t) {
    OmF x = (r->u - t * r->vx) * (float)res, y = (r->v - t * r->vy) * (float)res;
    OmF tx = om_face_ahead(x, r->vx * (float)res), ty = om_face_ahead(y, r->vy * (float)res);
    return t + fmin(fmin(tx, ty), om_face_ahead(z, z_per_t));
}

// One group of lanes' march, a step at a time, so that two groups can share a loop.
typedef struct {
    OmWalk w;
    OmF z_per_t;  // the layer coordinate z = w layers / s falls by this per unit t
    float near;   // cells are walked from this far off the proxy
    OmI steps;    // sphere steps a lane may take
    OmF t, t_voxel, hit_t;  // cells are walked while t < t_voxel
    OmI i, j;
    OmI done, hit, traced, walked;
    OmI entered;  // at least one cell per entry: t on a voxel face can round onto its exit
    OmI placed;   // (i, j) is the cell the walk goes on in from t (no sphere step since)
    OmI flags;
} OmSphereMarch;

OM_INLINE void om_sphere_begin(const OmRay* r, const OmField* f, const OmOffsetParams* P,
                               OmI active, OmSphereMarch* s) {
    const int layers = (int)OM_PARAM(P, layers), res = (int)OM_PARAM(P, res);
    s->steps = om_step_count(r, (OmF)OM_PARAM(P, steps));
    // The layer coordinate z = w layers / s of the ray at t, w = s (t_exit - t) / (t_exit -
    // t_enter): one multiply per step, where two divisions lay on the step's dependent chain
    // (a point on a voxel face may fall in either voxel: both boxes hold it, so both are safe).
    s->z_per_t = (float)layers / (r->t_exit - r->t_enter);
    // Cells are walked from half a voxel off the proxy: sphere steps shrink geometrically near it
    // at grazing views, and stall once t + d rounds to t (a floor of 2 texels of travel, where a
    // cell each would be cheaper, measured no faster). Without cells, only 0 stops.
    const int cells = (int)OM_PARAM(P, cells);
    s->near = cells ? 0.5f * fmin(1.0f / (float)res, r->scale / (float)layers) : 0.0f;
    s->w = om_walk(r, f);
    s->t = r->t_enter;
    s->t_voxel = r->t_enter;
    s->hit_t = r->t_exit;
    s->i = 0;
    s->j = 0;
    s->done = !active;
    s->hit = 0;
    s->traced = 0;
    s->walked = 0;
    s->entered = 0;
    s->placed = 0;
    s->flags = 0;
}

OM_INLINE void om_sphere_step(const OmRay* r, const OmField* f, const OmOffsetParams* P,
                              OmSphereMarch* s, OmI* fetches OM_IMG_PARAM) {
    const int res = (int)OM_PARAM(P, res), layers = (int)OM_PARAM(P, layers);
    const int cells = (int)OM_PARAM(P, cells);
    OmF t = s->t;
    OmI i = s->i, j = s->j, done = s->done, placed = s->placed;
    OmI walking = (!done) & ((t < s->t_voxel) | s->entered);
    OmI tracing = (!done) & (!walking);
    OmI spent = tracing & (s->traced >= s->steps);
    tracing &= !spent;
    // Out of sphere steps: with cells the rest of the ray is walked (the answer stays exact's);
    // without, the lane keeps t, above the relief.
    OmI start = cells ? spent : (OmI)0;
    done |= spent & !start;
    s->t_voxel = OM_SEL(s->t_voxel, r->t_exit, start);
    if (OM_ANY(tracing)) {
        OmF z = (r->t_exit - t) * s->z_per_t;
        OmF d = om_sphere_distance(f, P, res, layers, r->u - t * r->vx, r->v - t * r->vy, z);
        *fetches += OM_ONE(tracing);
        s->traced += OM_ONE(tracing);
        OmI touch = tracing & !(d > s->near);
        t = OM_SEL(t, fmin(t + d, r->t_exit), tracing & !touch);
        placed &= !(tracing & !touch);
        OmI enter = cells ? touch & (t < r->t_exit) : (OmI)0;
        done |= touch & !enter;
        if (OM_ANY(enter)) {
            OmF t_leave = fmin(om_voxel_exit(r, res, t, z, s->z_per_t), r->t_exit);
            s->t_voxel = OM_SEL(s->t_voxel, t_leave, enter);
        }
        start |= enter;
    }
    if (OM_ANY(start)) {
        // Back where the last walk left off, its next cell; after a step, the cell at t (at a
        // face, either: a cell the ray has left costs one empty solve).
        OmI ci, cj;
        om_walk_cell(&s->w, t, &ci, &cj);
        i = OM_SEL(i, ci, start & !placed);
        j = OM_SEL(j, cj, start & !placed);
    }
    s->entered = start;
    if (OM_ANY(walking)) {
        OmF tx, ty, th;
        OmF t_out = om_walk_exit(&s->w, i, j, (OmI)1, r->t_exit, &tx, &ty);
        OmI h = om_patch_hit(r, f, &s->w, i, j, t, t_out, walking, fetches, &th OM_IMG_ARG);
        s->hit_t = OM_SEL(s->hit_t, th, h);
        s->hit |= h;
        OmI end = walking & !h & (t_out >= r->t_exit);  // as exact: the bottom plane
        s->walked += OM_ONE(walking);
        OmI capped = walking & !h & !end & (s->walked >= P->max_cells);
        s->flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, capped);
        done |= h | end | capped;
        om_walk_step(&s->w, walking & !h & !end, tx, ty, t_out, &t, &i, &j);
        t = OM_SEL(t, r->t_exit, end);
        placed |= walking;
    }
    s->t = t;
    s->i = i;
    s->j = j;
    s->done = done;
    s->placed = placed;
}

OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmSphereMarch s;
    om_sphere_begin(r, f, P, active, &s);
    while (OM_ANY(!s.done)) om_sphere_step(r, f, P, &s, fetches OM_IMG_ARG);
    // Not done: the loop was ended from outside (llvmpipe's limit on a kernel's loop iterations).
    *flags |= s.flags | OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !s.done);
    return OM_SEL(s.t, s.hit_t, s.hit);
}

// Two groups of lanes marched in one loop (the entry's OM_LANE_PAIRS; see cone's om_trace_pair;
// its gain per instruction set: docs/throughput.md).
OM_INLINE void om_trace_pair(const OmRay* ra, const OmField* fa, OmI active_a, const OmRay* rb,
                             const OmField* fb, OmI active_b, const OmOffsetParams* P, OmF* ta,
                             OmI* fetches_a, OmI* flags_a, OmF* tb, OmI* fetches_b,
                             OmI* flags_b OM_IMG_PARAM) {
    OmSphereMarch a, b;
    om_sphere_begin(ra, fa, P, active_a, &a);
    om_sphere_begin(rb, fb, P, active_b, &b);
    OM_PAIR_LOOP(INT_MAX, OM_ANY(!a.done), om_sphere_step(ra, fa, P, &a, fetches_a OM_IMG_ARG),
                 OM_ANY(!b.done), om_sphere_step(rb, fb, P, &b, fetches_b OM_IMG_ARG));
    *flags_a |= a.flags | OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !a.done);
    *flags_b |= b.flags | OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !b.done);
    *ta = OM_SEL(a.t, a.hit_t, a.hit);
    *tb = OM_SEL(b.t, b.hit_t, b.hit);
}
