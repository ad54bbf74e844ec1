// The exact ray / bilinear-patch intersection shared by `exact` and `maxmip`: within one cell the
// ray height minus the patch height is a quadratic in the ray parameter, solved in closed form.

// First tau in [0, tmax] with c0 + c1 tau + c2 tau^2 <= 0, given c0 > 0; -1 when there is none.
inline float om_first_root(float c0, float c1, float c2, float tmax) {
    float disc = c1 * c1 - 4.0f * c2 * c0;
    float root = -1.0f;
    if (disc >= 0.0f) {
        // Stable pair of roots; c2 -> 0 degrades gracefully to the linear root c0 / q.
        float q = -0.5f * (c1 + copysign(sqrt(disc), c1));
        if (q != 0.0f) {
            float r1 = c0 / q, r2 = q / c2;
            float lo = fmin(r1, r2), hi = fmax(r1, r2);
            if (lo >= 0.0f && lo <= tmax)
                root = lo;
            else if (hi >= 0.0f && hi <= tmax)
                root = hi;
        }
    }
    if (root < 0.0f && c0 + tmax * (c1 + tmax * c2) <= 0.0f) {
        // Rounding hid a sign change the end point shows: bisect it.
        float lo = 0.0f, hi = tmax;
        for (int k = 0; k < 32; ++k) {
            float mid = 0.5f * (lo + hi);
            if (c0 + mid * (c1 + mid * c2) <= 0.0f)
                hi = mid;
            else
                lo = mid;
        }
        root = hi;
    }
    return root;
}

// Whether the ray is on or below bilinear patch (i, j) somewhere in [t, t_out], and the first such
// t (t itself may be negative: the ray starts above the polygon when r < 1). c0, d: the ray in cell
// coordinates, c(t) = c0 - t d (integer c is a texel centre). Counts one fetch.
inline bool om_patch_hit(const OmRay* r, OmHeightField* f, int i, int j, float2 c0, float2 d,
                         float t, float t_out, float* t_hit) {
    float4 k = om_patch(f, i, j);
    f->fetches += 1u;
    float e1 = k.y - k.x, e2 = k.z - k.x, e3 = k.x - k.y - k.z + k.w;
    float2 ab = c0 - t * d - OM_F2((float)i, (float)j);
    float da = -d.x, db = -d.y, s = r->scale;
    float h0 = k.x + e1 * ab.x + e2 * ab.y + e3 * ab.x * ab.y;
    // f(tau) = z(t + tau) - s (H(tau) - r), with z(t) = -t V.z.
    float q0 = -t * r->v.z - s * (h0 - r->ref);
    float q1 = -r->v.z - s * (e1 * da + e2 * db + e3 * (ab.x * db + ab.y * da));
    float q2 = -s * e3 * da * db;
    if (q0 <= 0.0f) {
        *t_hit = t;
        return true;
    }
    float tau = om_first_root(q0, q1, q2, t_out - t);
    *t_hit = t + tau;
    return tau >= 0.0f;
}
