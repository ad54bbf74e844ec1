// parallax-slope (Premecz 06; slope notes): one slope step from the polygon point (t = 0):
// intersect the ray with the tangent plane of the relief above uv. `safe` (0: exact form with
// the n.V guard, 1: Premecz's form without the N.V division). See om_slope_step in
// ray.cl.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    const OmF t =
        om_slope_step(r, f, (OmF)0.0f, OM_PARAM(P, safe) != 0.0f, active, fetches OM_IMG_ARG);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, om_left_through_top(r, t));
    return t;
}
