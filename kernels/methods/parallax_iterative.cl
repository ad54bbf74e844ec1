// parallax-iterative (Premecz 06, section 3): the slope step repeated from the previous estimate,
// p[0] = iterations k (one fetch each; k = 1 is parallax-slope), p[1] = safe (as parallax-slope).
// Like any fixed-point iteration it can settle on a later intersection or oscillate between
// surfaces (Premecz: "not even the convergence is guaranteed"); the slab clamp keeps it bounded.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    int k = (int)P->p[0];
    int safe = P->p[1] != 0.0f;
    float t = 0.0f;
    for (int i = 0; i < k; ++i) t = om_slope_step(r, f, t, safe);
    *t_hit = t;
    return om_ray_uv(r, t);
}
