// parallax (Kaneko 01): assume the relief is flat at the height H(uv) read at the entry point and
// intersect the ray with that plane: t = s (r - H) / V.z, uv' = uv - (r - H) P with P = s V.xy / V.z.
// Premecz writes uv + h V.xy / V.z with h = SCALE H + BIAS; in this convention h = s (H - r), which
// is the same expression. DESIGN.md's "uv - (1 - H) P" is the r = 1 case.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    float h = om_height(f, r->uv);
    float t = -om_surface_z(r, h) / r->v.z;
    *t_hit = t;
    return om_ray_uv(r, t);
}
