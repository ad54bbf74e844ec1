// none: normal mapping (Blinn 78). The surface is taken to lie on the polygon: uv' = uv, t = 0.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    *t_hit = 0.0f;
    return r->uv;
}
