// The walk over cells for a ray over a curved base, shared by the methods that walk cells (exact,
// cone, maxmip, sphere: their files define OM_CURVED_WALK, and the entry hands them only the lanes
// on the plane). Their precomputed bounds hold for the tangent plane's straight ray, not for the
// bent one, so the curved lanes walk every cell the footprint crosses: from the curve's point at t,
// its tangent finds the face it leaves the cell through, the curve is evaluated there, and the ray
// between the two points is taken as the chord, cut with the cell's bilinear patch in closed form
// (the flat walk's quadratic). A chord spans at most one cell, so it departs from the curve by at
// most |curve''| L^2 / 8 over a step of length L (docs/design.md bounds it). The next cell is the
// face's neighbour; the curve's true point starts the next chord, so the walk does not drift.
#ifdef OM_CURVED

typedef struct {
    OmF t, hit_t;
    OmF cx, cy, h;  // the curve's point at t: cell coordinates and height above the base (uv)
    OmI i, j, done, miss;
} OmCurvedWalk;

OM_INLINE void om_curved_point(const OmRay* r, const OmField* f, OmF t, OmF* cx, OmF* cy, OmF* h) {
    OmF dx, dy;
    om_curve_at(r, t, &dx, &dy, h);
    *cx = clamp(OM_CELL(r->u + dx, f->fw), -1.0e8f, 1.0e8f);
    *cy = clamp(OM_CELL(r->v + dy, f->fh), -1.0e8f, 1.0e8f);
}

// The curve's gap at t (its height minus the relief's, uv units) with cell (i, j)'s patch.
OM_INLINE OmF om_curved_gap(const OmRay* r, const OmField* f, OmF t, OmI i, OmI j, OmF k00, OmF e1,
                            OmF e2, OmF e3) {
    OmF cx, cy, h;
    om_curved_point(r, f, t, &cx, &cy, &h);
    const OmF a = cx - OM_TO_FLOAT(i), b = cy - OM_TO_FLOAT(j);
    return h - r->scale * (k00 + e1 * a + e2 * b + e3 * a * b - r->ref);
}

OM_INLINE void om_curved_begin(const OmRay* r, const OmField* f, OmI active, OmCurvedWalk* s) {
    s->t = r->t_enter;
    om_curved_point(r, f, s->t, &s->cx, &s->cy, &s->h);
    s->i = OM_TO_INT(OM_LFLOOR(s->cx));
    s->j = OM_TO_INT(OM_LFLOOR(s->cy));
    s->hit_t = r->t_exit;
    s->done = !active;
    s->miss = 0;
}

OM_INLINE void om_curved_step(const OmRay* r, const OmField* f, OmCurvedWalk* s,
                              OmI* fetches OM_IMG_PARAM) {
    const OmI live = !s->done;
    OmF ddx, ddy, dh;
    const OmCurvePoint here = om_curve_point(r, s->t);
    om_curve_rate(r, &here, &ddx, &ddy, &dh);
    const OmF dcx = ddx * f->fw, dcy = ddy * f->fh;
    const OmI si = OM_SEL((OmI)-1, (OmI)1, dcx > 0.0f), sj = OM_SEL((OmI)-1, (OmI)1, dcy > 0.0f);
    const OmF bx = OM_TO_FLOAT(OM_SEL(s->i, s->i + 1, si > 0));
    const OmF by = OM_TO_FLOAT(OM_SEL(s->j, s->j + 1, sj > 0));
    const OmF tx = OM_SEL((OmF)INFINITY, (bx - s->cx) / dcx, dcx != 0.0f);
    const OmF ty = OM_SEL((OmF)INFINITY, (by - s->cy) / dcy, dcy != 0.0f);
    // The tangent's exit is the curve's to first order: the curve's point there, joined to the
    // start, crosses the cell's faces at fractions wx, wy of the way (beyond 1 where it falls
    // short); the first face it crosses, and the curve's point at that fraction, end the chord, so
    // the patch is never read far outside its cell. A point the chords have carried a hair past a
    // face leaves through it at once.
    const OmF t_tan = fmin(s->t + fmax(fmin(tx, ty), 0.0f), r->t_exit);
    OmF cx, cy, h;
    om_curved_point(r, f, t_tan, &cx, &cy, &h);
    const OmF ddcx = cx - s->cx, ddcy = cy - s->cy;
    const OmF wx = OM_SEL((OmF)INFINITY, fmax((bx - s->cx) / ddcx, 0.0f), ddcx * dcx > 0.0f);
    const OmF wy = OM_SEL((OmF)INFINITY, fmax((by - s->cy) / ddcy, 0.0f), ddcy * dcy > 0.0f);
    const OmI face_x = wx <= wy;
    const OmF w = fmin(fmin(wx, wy), 2.0f);
    OmF t_out = t_tan;
    const OmI fix = live & (t_tan < r->t_exit) & (w != 1.0f);
    if (OM_ANY(fix)) {
        OmF cx2, cy2, h2;
        const OmF t2 = fmin(s->t + w * (t_tan - s->t), r->t_exit);
        om_curved_point(r, f, t2, &cx2, &cy2, &h2);
        t_out = OM_SEL(t_out, t2, fix);
        cx = OM_SEL(cx, cx2, fix);
        cy = OM_SEL(cy, cy2, fix);
        h = OM_SEL(h, h2, fix);
    }
    // The chord against patch (i, j): gap(tau) = ray height - s (H - r), tau in [0, 1].
    OmF k00, k10, k01, k11;
    om_corners(f, s->i, s->j, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    *fetches += OM_ONE(live);
    const OmF e1 = k10 - k00, e2 = k01 - k00, e3 = k00 - k10 - k01 + k11;
    const OmF a = s->cx - OM_TO_FLOAT(s->i), b = s->cy - OM_TO_FLOAT(s->j);
    const OmF da = cx - s->cx, db = cy - s->cy, sc = r->scale;
    const OmF q0 = s->h - sc * (k00 + e1 * a + e2 * b + e3 * a * b - r->ref);
    const OmF q1 = (h - s->h) - sc * (e1 * da + e2 * db + e3 * (a * db + b * da));
    const OmF q2 = -sc * e3 * da * db;
    const OmI at_start = q0 <= 0.0f;
    const OmF tau = om_first_root(q0, q1, q2, 1.0f, live & !at_start);
    const OmI cut = live & !at_start & (tau >= 0.0f);
    OmI hit = live & at_start;
    OmF th = s->t;
    if (OM_ANY(cut)) {
        // The chord's root brackets the curve's: the curve's own gap there (the patch in hand, no
        // fetch) at or below zero closes [t, root]; above it, the curve's gap where the chord
        // turns back up (its lowest point, or its end, which lies on the curve) at or below zero
        // closes [root, there]; neither, and the chord dipped where the curve grazes by less than
        // the chord's departure: no hit in this cell. Illinois steps on the curve then take the
        // bracket's root to float precision.
        const OmF dt = t_out - s->t;
        const OmF tc = s->t + tau * dt;
        const OmF gc = om_curved_gap(r, f, tc, s->i, s->j, k00, e1, e2, e3);
        const OmF tau_low = -q1 / (2.0f * q2);
        const OmI turns = cut & (q2 > 0.0f) & (tau_low > tau) & (tau_low < 1.0f);
        const OmF t_low = OM_SEL(t_out, s->t + tau_low * dt, turns);
        OmF g_low = q0 + q1 + q2;
        if (OM_ANY(turns & !(gc <= 0.0f)))
            g_low = OM_SEL(g_low, om_curved_gap(r, f, t_low, s->i, s->j, k00, e1, e2, e3), turns);
        const OmI lower = cut & (gc <= 0.0f), upper = cut & !(gc <= 0.0f) & (g_low <= 0.0f);
        const OmI found = lower | upper;
        OmF lo = OM_SEL(tc, s->t, lower), g_lo = OM_SEL(gc, q0, lower);
        OmF hi = OM_SEL(t_low, tc, lower), g_hi = OM_SEL(g_low, gc, lower);
        OmF w_lo = g_lo, w_hi = g_hi;  // Illinois-weighted gaps that steer the next point
        OmI kept = 0;                  // +1: lo survived the last step, -1: hi
        for (int k = 0; k < 4 && OM_ANY(found); ++k) {
            const OmF x = lo + (hi - lo) * (w_lo / (w_lo - w_hi));
            const OmF g = om_curved_gap(r, f, x, s->i, s->j, k00, e1, e2, e3);
            const OmI below = found & (g <= 0.0f), above = found & !(g <= 0.0f);
            hi = OM_SEL(hi, x, below);
            g_hi = OM_SEL(g_hi, g, below);
            w_hi = OM_SEL(w_hi, g, below);
            w_lo = OM_SEL(w_lo, 0.5f * w_lo, below & (kept == 1));
            lo = OM_SEL(lo, x, above);
            g_lo = OM_SEL(g_lo, g, above);
            w_lo = OM_SEL(w_lo, g, above);
            w_hi = OM_SEL(w_hi, 0.5f * w_hi, above & (kept == -1));
            kept = OM_SEL(OM_SEL(kept, (OmI)-1, above), (OmI)1, below);
        }
        // The final bracket's secant with its true gaps.
        th = OM_SEL(th, lo + (hi - lo) * (g_lo / (g_lo - g_hi)), found);
        hit |= found;
    }
    s->hit_t = OM_SEL(s->hit_t, th, hit);
    const OmI end = live & !hit & (t_out >= r->t_exit);
    s->done |= hit | end;
    s->miss |= end & r->exits_top;
    const OmI step = live & !hit & !end;
    s->t = OM_SEL(s->t, t_out, step);
    s->cx = OM_SEL(s->cx, cx, step);
    s->cy = OM_SEL(s->cy, cy, step);
    s->h = OM_SEL(s->h, h, step);
    s->i = OM_SEL(s->i, s->i + si, step & face_x);
    s->j = OM_SEL(s->j, s->j + sj, step & !face_x);
}

// The curved lanes' first hit (t_exit for a bottom reached through rounding, as the flat walk);
// a ray that leaves through the top is flagged SILHOUETTE, one that runs out of cells CAPPED.
OM_INLINE OmF om_curved_walk(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                             OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmCurvedWalk s;
    om_curved_begin(r, f, active, &s);
    for (int n = 0; n < P->max_cells && OM_ANY(!s.done); ++n)
        om_curved_step(r, f, &s, fetches OM_IMG_ARG);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, active & !s.done);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, s.miss);
    return s.hit_t;
}

#endif
