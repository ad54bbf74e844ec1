// none: normal mapping (Blinn 78). The surface is taken to lie on the polygon: uv' = uv, t = 0.
OM_INLINE void om_trace_lanes(const OmLaneRay* r, const OmLaneField* f, const OmOffsetParams* P,
                              OmI active, OmF* t_hit, OmF* u_hit, OmF* v_hit, OmI* fetches,
                              OmI* flags OM_IMG_PARAM) {
    OmF t = 0.0f;
    *t_hit = t;
    *u_hit = r->u - t * r->vx;
    *v_hit = r->v - t * r->vy;
}
