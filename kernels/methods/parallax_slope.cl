// parallax-slope (Premecz 06; slope notes): one slope step from the polygon point (t = 0):
// intersect the ray with the tangent plane of the relief above uv. p[0] = safe (0: exact form with
// the n.V guard, 1: Premecz's form without the N.V division). See om_slope_step in march.cl.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    float t = om_slope_step(r, f, 0.0f, P->p[0] != 0.0f);
    *t_hit = t;
    return om_ray_uv(r, t);
}
