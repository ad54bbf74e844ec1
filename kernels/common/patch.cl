// The exact ray / bilinear-patch intersection shared by `exact`, `maxmip` and `cone`: within one
// cell the ray height minus the patch height is a quadratic in the ray parameter, solved in closed
// form with selects for its branches (the rare bisection runs only when a lane needs it).

// First tau in [0, tmax] with c0 + c1 tau + c2 tau^2 <= 0, given c0 > 0; -1 when there is none.
OM_INLINE OmF om_first_root(OmF c0, OmF c1, OmF c2, OmF tmax, OmI active) {
    OmF disc = c1 * c1 - 4.0f * c2 * c0;
    OmF q = -0.5f * (c1 + copysign(sqrt(fmax(disc, 0.0f)), c1));
    OmF r1 = c0 / q, r2 = q / c2;
    OmF lo = fmin(r1, r2), hi = fmax(r1, r2);
    OmI solvable = disc >= 0.0f && q != 0.0f;
    OmF root = OM_SEL(OM_SEL((OmF)-1.0f, hi, solvable && hi >= 0.0f && hi <= tmax), lo,
                      solvable && lo >= 0.0f && lo <= tmax);
    // Rounding hid a sign change the end point shows: bisect it.
    OmI bisect = active & (root < 0.0f) & (c0 + tmax * (c1 + tmax * c2) <= 0.0f);
    if (OM_ANY_RARE(bisect)) {
        OmF a = 0.0f, b = tmax;
        for (int k = 0; k < 32; ++k) {
            OmF mid = 0.5f * (a + b);
            OmI below = c0 + mid * (c1 + mid * c2) <= 0.0f;
            b = OM_SEL(b, mid, below);
            a = OM_SEL(mid, a, below);
        }
        root = OM_SEL(root, b, bisect);
    }
    return root;
}

// A ray's walk over cells (the bilinear patches between texel centres), shared by `exact`, `cone`
// and `maxmip`: c(t) = (cx, cy) - t (dx, dy) in cell coordinates (integer c is a texel centre);
// si, sj the directions cell indices step in.
typedef struct {
    OmF cx, cy, dx, dy;
    OmI si, sj;
} OmWalk;

OM_INLINE OmWalk om_walk(const OmRay* r, const OmField* f) {
    OmWalk w;
    w.cx = clamp(OM_CELL(r->u, f->fw), -1.0e8f, 1.0e8f);
    w.cy = clamp(OM_CELL(r->v, f->fh), -1.0e8f, 1.0e8f);
    w.dx = r->vx * f->fw;
    w.dy = r->vy * f->fh;
    w.si = OM_SEL((OmI)1, (OmI)-1, w.dx > 0.0f);
    w.sj = OM_SEL((OmI)1, (OmI)-1, w.dy > 0.0f);
    return w;
}

// The cell holding the ray at t.
OM_INLINE void om_walk_cell(const OmWalk* w, OmF t, OmI* i, OmI* j) {
    *i = OM_TO_INT(OM_LFLOOR(w->cx - t * w->dx));
    *j = OM_TO_INT(OM_LFLOOR(w->cy - t * w->dy));
}

// Where the ray leaves the square of cells [x_lo, x_lo + size) x [y_lo, y_lo + size): through an
// x face at tx, a y face at ty; returns the first of those and t_exit.
OM_INLINE OmF om_walk_exit(const OmWalk* w, OmI x_lo, OmI y_lo, OmI size, OmF t_exit, OmF* tx,
                           OmF* ty) {
    OmI bx = OM_SEL(x_lo + size, x_lo, w->si < 0), by = OM_SEL(y_lo + size, y_lo, w->sj < 0);
    *tx = OM_SEL((OmF)INFINITY, (w->cx - OM_TO_FLOAT(bx)) / w->dx, w->dx != 0.0f);
    *ty = OM_SEL((OmF)INFINITY, (w->cy - OM_TO_FLOAT(by)) / w->dy, w->dy != 0.0f);
    return fmin(fmin(*tx, *ty), t_exit);
}

// Lanes in `step` move on to the neighbouring cell through the exit face found above.
OM_INLINE void om_walk_step(const OmWalk* w, OmI step, OmF tx, OmF ty, OmF t_out, OmF* t, OmI* i,
                            OmI* j) {
    *t = OM_SEL(*t, t_out, step);
    *i = OM_SEL(*i, *i + w->si, step & (tx <= ty));
    *j = OM_SEL(*j, *j + w->sj, step & !(tx <= ty));
}

// Whether each lane's ray is on or below bilinear patch (i, j) somewhere in [t, t_out], and the
// first such t (t itself may be negative: the ray starts above the polygon when r < 1). Counts one
// fetch in the lanes of `active`; other lanes return false.
OM_INLINE OmI om_patch_hit(const OmRay* r, const OmField* f, const OmWalk* w, OmI i, OmI j, OmF t,
                           OmF t_out, OmI active, OmI* fetches, OmF* t_hit OM_IMG_PARAM) {
    OmF k00, k10, k01, k11;
    om_corners(f, i, j, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    *fetches += OM_ONE(active);
    OmF e1 = k10 - k00, e2 = k01 - k00, e3 = k00 - k10 - k01 + k11;
    // The ray's place in the cell, the cell's corner taken off first: cx - i is exact (Sterbenz),
    // so the one rounding left is of t dx, a few ulp of the distance walked. (cx - t dx) - i
    // rounded at the size of cx itself: 0.002 of a cell at v = 16384 texels, where a ray that
    // grazes the relief by that much found a root the double oracle does not.
    OmF a = (w->cx - OM_TO_FLOAT(i)) - t * w->dx, b = (w->cy - OM_TO_FLOAT(j)) - t * w->dy;
    OmF da = -w->dx, db = -w->dy, s = r->scale;
    OmF h0 = k00 + e1 * a + e2 * b + e3 * a * b;
    // f(tau) = z(t + tau) - s (H(tau) - r), with z(t) = -t V.z.
    OmF q0 = -t * r->vz - s * (h0 - r->ref);
    OmF q1 = -r->vz - s * (e1 * da + e2 * db + e3 * (a * db + b * da));
    OmF q2 = -s * e3 * da * db;
    OmI at_start = q0 <= 0.0f;
    OmF tau = om_first_root(q0, q1, q2, t_out - t, active & !at_start);
    *t_hit = OM_SEL(t + tau, t, at_start);
    return active & (at_start | (tau >= 0.0f));
}
