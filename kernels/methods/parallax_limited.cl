// parallax-limited (Welsh 04, offset limiting): parallax without the division by V.z, so the
// offset never exceeds the depth s (r - H) however grazing the view: uv' = uv - s (r - H) V.xy.
// t is the ray parameter whose footprint is that uv'; the point p(t) is generally not on the
// relief.
OM_INLINE void om_trace_lanes(const OmLaneRay* r, const OmLaneField* f, const OmOffsetParams* P,
                              OmI active, OmF* t_hit, OmF* u_hit, OmF* v_hit, OmI* fetches,
                              OmI* flags OM_IMG_PARAM) {
    OmF h = om_lane_height(f, r->u, r->v, active, fetches OM_IMG_ARG);
    OmF t = -r->scale * (h - r->ref);
    *t_hit = t;
    *u_hit = r->u - t * r->vx;
    *v_hit = r->v - t * r->vy;
}
