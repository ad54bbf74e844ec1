// parallax-iterative (Premecz 06, section 3): the slope step repeated from the previous estimate,
// p[0] = iterations k (one fetch each; k = 1 is parallax-slope), p[1] = safe (as parallax-slope).
// Like any fixed-point iteration it can settle on a later intersection or oscillate between
// surfaces (Premecz: "not even the convergence is guaranteed"); the slab clamp keeps it bounded.
OM_INLINE void om_trace_lanes(const OmLaneRay* r, const OmLaneField* f, const OmOffsetParams* P,
                              OmI active, OmF* t_hit, OmF* u_hit, OmF* v_hit, OmI* fetches,
                              OmI* flags OM_IMG_PARAM) {
    int k = (int)P->p[0];
    int safe = P->p[1] != 0.0f;
    OmF t = 0.0f;
    for (int i = 0; i < k; ++i) t = om_lane_slope_step(r, f, t, safe, active, fetches OM_IMG_ARG);
    *t_hit = t;
    *u_hit = r->u - t * r->vx;
    *v_hit = r->v - t * r->vy;
}
