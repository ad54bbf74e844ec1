// Search helpers shared by the marching methods (lambda parametrisation, see ray.cl).

typedef struct {
    int index;     // first sample i in 0..n with H(lambda_i) >= 1 - lambda_i (n when none before)
    float h_prev;  // height at sample index - 1 (1 when index is 0: the top plane)
    float h_cur;   // height at sample index
} OmLinearHit;

// n + 1 samples at lambda_i = i / n from the top plane down; stops at the first sample at or below
// the relief. lambda_n = 1 is the bottom plane where every H >= 0, so it always stops by i = n.
inline OmLinearHit om_linear_search(const OmRay* r, OmHeightField* f, int n) {
    OmLinearHit hit = {n, 1.0f, 0.0f};
    float h_prev = 1.0f;
    for (int i = 0; i <= n; ++i) {
        float lambda = (float)i / (float)n;
        float h = om_height(f, om_ray_uv(r, om_ray_t(r, lambda)));
        if (h >= 1.0f - lambda) {
            hit.index = i;
            hit.h_prev = h_prev;
            hit.h_cur = h;
            return hit;
        }
        h_prev = h;
    }
    return hit;
}

// One step of parallax with slope (Premecz 2006, section 3), from the ray point at t: intersect
// the ray with the plane through the relief point above p(t).xy with the relief's normal there.
// Premecz traces (u, v, 0) + V t with h = SCALE H + BIAS <= 0; here t runs the other way
// (p(t) = (u, v, 0) - t V) and h = s (H - r), so his uv + h N.z / (N.V) V.xy is uv - t' V.xy with
//   t' = t - gap N.z / (N.V),   gap = s (H - r) + t V.z  (relief height minus ray height).
// exact form: N.z / (N.V) = 1 / (n.V) for n = (-s dH/du, -s dH/dv, 1). Guard: n.V below 1e-4
//   (plane parallel to or facing away from the ray) is taken as 1e-4, so the step runs to the slab.
// safe form (Premecz's "safer" variant): the division dropped, t' = t - gap N.z with N unit.
// Either way t' is clamped to the slab [t_enter, t_exit].
inline float om_slope_step(const OmRay* r, OmHeightField* f, float t, int safe) {
    float2 g;
    float h = om_height_grad(f, om_ray_uv(r, t), &g);
    float gap = om_surface_z(r, h) + t * r->v.z;
    float2 sg = r->scale * g;
    float dt;
    if (safe)
        dt = gap * rsqrt(1.0f + dot(sg, sg));
    else
        dt = gap / fmax(r->v.z - dot(sg, r->v.xy), 1.0e-4f);
    return clamp(t - dt, r->t_enter, r->t_exit);
}
