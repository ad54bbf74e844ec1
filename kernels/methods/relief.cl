// relief (Policarpo et al. 05; Premecz section 2.3): linear search of n = p[0] steps, then binary
// search of m = p[1] steps between the last sample above and the first below the relief. Returns
// the bracket's lower end (a point at or below the surface, as Policarpo's best depth).
// Cost: at most n + 1 + m fetches.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    int n = om_lod_count(r, P->p[0]), m = (int)P->p[1];
    OmLinearHit hit = om_linear_search(r, f, n);
    float hi = (float)hit.index / (float)n;
    float lo = hit.index > 0 ? (float)(hit.index - 1) / (float)n : 0.0f;
    for (int k = 0; k < m && hit.index > 0; ++k) {
        float mid = 0.5f * (lo + hi);
        float h = om_height(f, om_ray_uv(r, om_ray_t(r, mid)));
        if (h >= 1.0f - mid)
            hi = mid;
        else
            lo = mid;
    }
    float t = om_ray_t(r, hi);
    *t_hit = t;
    return om_ray_uv(r, t);
}
