// parallax-slope (Premecz 06; slope notes): one slope step from the polygon point (t = 0):
// intersect the ray with the tangent plane of the relief above uv. p[0] = safe (0: exact form with
// the n.V guard, 1: Premecz's form without the N.V division). See om_lane_slope_step in
// lane_ray.cl.
OM_INLINE void om_trace_lanes(const OmLaneRay* r, const OmLaneField* f, const OmOffsetParams* P,
                              OmI active, OmF* t_hit, OmF* u_hit, OmF* v_hit, OmI* fetches,
                              OmI* flags OM_IMG_PARAM) {
    OmF t = om_lane_slope_step(r, f, (OmF)0.0f, P->p[0] != 0.0f, active, fetches OM_IMG_ARG);
    *t_hit = t;
    *u_hit = r->u - t * r->vx;
    *v_hit = r->v - t * r->vy;
}
