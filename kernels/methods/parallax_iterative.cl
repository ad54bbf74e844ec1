// parallax-iterative (Premecz 06, section 3): the slope step repeated from the previous estimate,
// `iterations` k (one fetch each; k = 1 is parallax-slope) and `safe` (as parallax-slope).
// Like any fixed-point iteration it can settle on a later intersection or oscillate between
// surfaces (Premecz: "not even the convergence is guaranteed"); the slab clamp keeps it bounded.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    int k = (int)OM_PARAM(P, iterations);
    int safe = OM_PARAM(P, safe) != 0.0f;
    OmF t = 0.0f;
    for (int i = 0; i < k; ++i) t = om_slope_step(r, f, t, safe, active, fetches OM_IMG_ARG);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, om_left_through_top(r, t));
    return t;
}
