// The exact ray / bilinear-patch intersection shared by `exact`, `maxmip` and `cone`: within one
// cell the ray height minus the patch height is a quadratic in the ray parameter, solved in closed
// form with selects for its branches (the rare bisection runs only when a lane needs it).

// First tau in [0, tmax] with c0 + c1 tau + c2 tau^2 <= 0, given c0 > 0; -1 when there is none.
inline OmF om_lane_first_root(OmF c0, OmF c1, OmF c2, OmF tmax, OmI active) {
    OmF disc = c1 * c1 - 4.0f * c2 * c0;
    OmF q = -0.5f * (c1 + copysign(sqrt(fmax(disc, 0.0f)), c1));
    OmF r1 = c0 / q, r2 = q / c2;
    OmF lo = fmin(r1, r2), hi = fmax(r1, r2);
    OmI solvable = disc >= 0.0f && q != 0.0f;
    OmF root = OM_SEL(OM_SEL((OmF)-1.0f, hi, solvable && hi >= 0.0f && hi <= tmax), lo,
                      solvable && lo >= 0.0f && lo <= tmax);
    // Rounding hid a sign change the end point shows: bisect it.
    OmI bisect = active & (root < 0.0f) & (c0 + tmax * (c1 + tmax * c2) <= 0.0f);
    if (OM_ANY(bisect)) {
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

// Whether each lane's ray is on or below bilinear patch (i, j) somewhere in [t, t_out], and the
// first such t (t itself may be negative: the ray starts above the polygon when r < 1). c(t) = (cx,
// cy) - t (dx, dy) in cell coordinates. Counts one fetch in the lanes of `active`; other lanes
// return false.
inline OmI om_lane_patch_hit(const OmLaneRay* r, const OmLaneField* f, OmI i, OmI j, OmF cx, OmF cy,
                             OmF dx, OmF dy, OmF t, OmF t_out, OmI active, OmI* fetches,
                             OmF* t_hit OM_IMG_PARAM) {
    OmF k00, k10, k01, k11;
    om_lane_corners(f, i, j, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    *fetches += OM_ONE(active);
    OmF e1 = k10 - k00, e2 = k01 - k00, e3 = k00 - k10 - k01 + k11;
    OmF a = cx - t * dx - OM_TO_FLOAT(i), b = cy - t * dy - OM_TO_FLOAT(j);
    OmF da = -dx, db = -dy, s = r->scale;
    OmF h0 = k00 + e1 * a + e2 * b + e3 * a * b;
    // f(tau) = z(t + tau) - s (H(tau) - r), with z(t) = -t V.z.
    OmF q0 = -t * r->vz - s * (h0 - r->ref);
    OmF q1 = -r->vz - s * (e1 * da + e2 * db + e3 * (a * db + b * da));
    OmF q2 = -s * e3 * da * db;
    OmI at_start = q0 <= 0.0f;
    OmF tau = om_lane_first_root(q0, q1, q2, t_out - t, active & !at_start);
    *t_hit = OM_SEL(t + tau, t, at_start);
    return active & (at_start | (tau >= 0.0f));
}
