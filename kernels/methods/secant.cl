// secant (Risser, Shah & Pattanaik, "Faster relief mapping using the secant method", JGT 2007):
// a linear search, then the bracket [last sample above, first sample below] refined by the secant
// rule on the height gap g(lambda) = H - (1 - lambda), up to m = p[2] iterations or until
// |g| <= tol = p[3] (height units). The linear search takes pom's dynamic step count
// lerp(n_max = p[1], n_min = p[0], V.z): the fixed-step search Risser uses steps over thin walls
// at grazing views, and that, not the refinement, dominates the error there. Risser's plain secant can
// leave the bracket; this is regula falsi (the new point replaces the end of the same sign) with
// the Illinois modification (halve the stale end's gap), so it stays bracketed and converges
// superlinearly. With m = 0 this is exactly pom.
// The answer is the first evaluated point within tol of the relief, else the secant point of the
// final bracket (free: no fetch). Cost: at most n + 1 + m fetches.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    int n = om_lod_count(r, mix(P->p[1], P->p[0], r->v.z)), m = (int)P->p[2];
    float tol = P->p[3];
    OmLinearHit hit = om_linear_search(r, f, n);
    float lambda = 0.0f;
    if (hit.index > 0) {
        float la = (float)(hit.index - 1) / (float)n, lb = (float)hit.index / (float)n;
        float ga = hit.h_prev - (1.0f - la);  // < 0: above the relief
        float gb = hit.h_cur - (1.0f - lb);   // >= 0: on or below
        float wa = ga, wb = gb;               // Illinois-weighted gaps that steer the next point
        int kept = 0;                         // +1: the a end survived the last step, -1: b
        bool done = gb <= tol;
        lambda = lb;
        for (int k = 0; k < m && !done; ++k) {
            float x = la + (lb - la) * wa / (wa - wb);
            float g = om_height(f, om_ray_uv(r, om_ray_t(r, x))) - (1.0f - x);
            if (fabs(g) <= tol) {
                lambda = x;
                done = true;
            } else if (g > 0.0f) {
                lb = x;
                gb = wb = g;
                if (kept == 1) wa *= 0.5f;  // a is stale twice running
                kept = 1;
            } else {
                la = x;
                ga = wa = g;
                if (kept == -1) wb *= 0.5f;
                kept = -1;
            }
        }
        // Otherwise the secant of the final bracket with its true gaps (refine = 0: pom's step).
        if (!done) lambda = la + (lb - la) * ga / (ga - gb);
    }
    float t = om_ray_t(r, lambda);
    *t_hit = t;
    return om_ray_uv(r, t);
}
