// parallax-limited (Welsh 04, offset limiting): parallax without the division by V.z, so the
// offset never exceeds the depth s (r - H) however grazing the view: uv' = uv - s (r - H) V.xy.
// t is the ray parameter whose footprint is that uv'; the point p(t) is generally not on the relief.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    float h = om_height(f, r->uv);
    float t = -om_surface_z(r, h);
    *t_hit = t;
    return om_ray_uv(r, t);
}
