// secant (Risser, Shah & Pattanaik, "Faster relief mapping using the secant method", JGT 2007):
// a linear search, then the bracket [last sample above, first sample below] refined by the secant
// rule on the height gap g(lambda) = H - (1 - lambda), up to m = `refine` iterations or until
// |g| <= `tol` (height units). The linear search takes pom's dynamic step count
// lerp(`max_samples`, `min_samples`, V.z): the fixed-step search Risser uses steps over thin walls
// at grazing views, and that, not the refinement, dominates the error there. Risser's plain secant
// can leave the bracket; this is regula falsi (the new point replaces the end of the same sign)
// with the Illinois modification (halve the stale end's gap), so it stays bracketed and converges
// superlinearly. With m = 0 this is exactly pom.
// The answer is the first refinement point within tol of the relief, else the secant point of the
// final bracket (free: no fetch); a linear-search sample already within tol ends the refinement
// at once. So with m = 0 the answer is pom's segment cut, bit for bit. Cost: at most n + 1 + m
// fetches.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmI n =
        om_step_count(r, mix((OmF)OM_PARAM(P, max_samples), (OmF)OM_PARAM(P, min_samples), r->vz));
    int m = (int)OM_PARAM(P, refine);
    float tol = OM_PARAM(P, tol);
    OmSearchHit hit = om_linear_search(r, f, n, active, fetches OM_IMG_ARG);
    OmF fn = OM_TO_FLOAT(n);
    OmF la = OM_TO_FLOAT(hit.index - 1) / fn, lb = OM_TO_FLOAT(hit.index) / fn;
    OmF ga = hit.h_prev - (1.0f - la);  // < 0: above the relief
    OmF gb = hit.h_cur - (1.0f - lb);   // >= 0: on or below
    OmF wa = ga, wb = gb;               // Illinois-weighted gaps that steer the next point
    OmI kept = 0;                       // +1: the a end survived the last step, -1: b
    OmI run = active & (hit.index > 0);
    OmI done = !run || gb <= tol;
    OmI found = 0;  // a refinement point within tol: the answer
    OmF lambda = 0.0f;
    for (int k = 0; k < m && OM_ANY(!done); ++k) {
        OmI live = !done;
        OmF x = om_segment_cut(la, lb, wa, wb);
        OmF tx = om_ray_t(r, x);
        OmF g = om_height(f, r->u - tx * r->vx, r->v - tx * r->vy, live, fetches OM_IMG_ARG) -
                (1.0f - x);
        OmI conv = live & (fabs(g) <= tol);
        OmI pos = live & !conv & (g > 0.0f);
        OmI neg = live & !conv & !(g > 0.0f);
        lambda = OM_SEL(lambda, x, conv);
        lb = OM_SEL(lb, x, pos);
        gb = OM_SEL(gb, g, pos);
        wb = OM_SEL(wb, g, pos);
        wa = OM_SEL(wa, 0.5f * wa, pos & (kept == 1));  // a is stale twice running
        la = OM_SEL(la, x, neg);
        ga = OM_SEL(ga, g, neg);
        wa = OM_SEL(wa, g, neg);
        wb = OM_SEL(wb, 0.5f * wb, neg & (kept == -1));
        kept = OM_SEL(OM_SEL(kept, (OmI)-1, neg), (OmI)1, pos);
        done |= conv;
        found |= conv;
    }
    // Otherwise the secant of the final bracket with its true gaps (refine = 0: pom's step).
    lambda = OM_SEL(OM_SEL((OmF)0.0f, om_segment_cut(la, lb, ga, gb), run), lambda, found);
    return om_ray_t(r, lambda);
}
