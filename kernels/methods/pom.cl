// pom (Tatarchuk 05/06): a linear search whose step count is lerp(n_max, n_min, V.z) (more samples
// at grazing views: Tatarchuk's dynamic sampling rate; p[0] = n_min, p[1] = n_max), then the ray
// intersected with the straight segment joining the last two height samples. Tatarchuk's V.N is
// V.z here. Cost: at most n_max + 1 fetches.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    float n_min = P->p[0], n_max = P->p[1];
    int n = om_lod_count(r, mix(n_max, n_min, r->v.z));
    OmLinearHit hit = om_linear_search(r, f, n);
    float lambda = 0.0f;
    if (hit.index > 0) {
        // Along the segment, height minus ray height goes from d0 < 0 (above) to d1 >= 0.
        float l0 = (float)(hit.index - 1) / (float)n;
        float d0 = hit.h_prev - (1.0f - l0);
        float d1 = hit.h_cur - (1.0f - (float)hit.index / (float)n);
        lambda = l0 + (d0 / (d0 - d1)) / (float)n;
    }
    float t = om_ray_t(r, lambda);
    *t_hit = t;
    return om_ray_uv(r, t);
}
