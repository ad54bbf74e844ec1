// parallax (Kaneko 01): assume the relief is flat at the height H(uv) read at the entry point and
// intersect the ray with that plane: t = s (r - H) / V.z, uv' = uv - (r - H) P with P = s V.xy /
// V.z. Premecz writes uv + h V.xy / V.z with h = SCALE H + BIAS; in this convention h = s (H - r),
// which is the same expression. DESIGN.md's "uv - (1 - H) P" is the r = 1 case.
OM_INLINE void om_trace_lanes(const OmLaneRay* r, const OmLaneField* f, const OmOffsetParams* P,
                              OmI active, OmF* t_hit, OmF* u_hit, OmF* v_hit, OmI* fetches,
                              OmI* flags OM_IMG_PARAM) {
    OmF h = om_lane_height(f, r->u, r->v, active, fetches OM_IMG_ARG);
    OmF t = -r->scale * (h - r->ref) / r->vz;
    *t_hit = t;
    *u_hit = r->u - t * r->vx;
    *v_hit = r->v - t * r->vy;
}
