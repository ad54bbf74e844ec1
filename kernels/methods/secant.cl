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
    OmF eta_a, eta_b;
    om_search_etas(r, &hit, la, lb, &eta_a, &eta_b);
    OmF ga = hit.h_prev - eta_a;  // < 0: above the relief
    OmF gb = hit.h_cur - eta_b;   // >= 0: on or below (unless the ray left through the top)
    OmF wa = ga, wb = gb;         // Illinois-weighted gaps that steer the next point
    OmI kept = 0;                 // +1: the a end survived the last step, -1: b
    OmI run = active & (hit.index > 0) & !hit.miss;
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, hit.miss);
    OmI done = !run || gb <= tol;
    OmI found = 0;  // a refinement point within tol: the answer
    OmF lambda = 0.0f;
    for (int k = 0; k < m && OM_ANY(!done); ++k) {
        OmI live = !done;
        OmF x = om_segment_cut(la, lb, wa, wb);
        OmF px, py, eta;
        om_ray_sample(r, x, &px, &py, &eta);
        OmF g = om_height(f, px, py, live, fetches OM_IMG_ARG) - eta;
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
    lambda = OM_SEL(lambda, (OmF)1.0f, hit.miss);
    return om_ray_t(r, lambda);
}
