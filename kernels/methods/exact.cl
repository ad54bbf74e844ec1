// exact: the first hit of the eye ray with the bilinearly interpolated height field, the ground
// truth. A DDA walks the bilinear patches (cells between texel centres) the ray's footprint
// crosses from the top plane to the bottom plane; in each cell the ray height minus the patch
// height is a quadratic in the ray parameter, solved in closed form for its first root.
// Cost: one patch (4 texels, counted as one fetch) per cell crossed, at most ~ (s / V.z)(W + H).

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

float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    // Ray in cell coordinates: c(t) = c0 - t * d, where integer c is a texel centre.
    float2 c0 = om_cell_coord(f, r->uv);
    float2 d = OM_F2(r->v.x * f->fw, r->v.y * f->fh);
    float t = r->t_enter;
    float2 c = c0 - t * d;
    int i = (int)om_floor(c.x), j = (int)om_floor(c.y);
    int si = d.x > 0.0f ? -1 : 1, sj = d.y > 0.0f ? -1 : 1;
    // Next cell boundary along each axis and the ray parameter at which it is crossed.
    int bi = si < 0 ? i : i + 1, bj = sj < 0 ? j : j + 1;
    float tx = d.x != 0.0f ? (c0.x - (float)bi) / d.x : INFINITY;
    float ty = d.y != 0.0f ? (c0.y - (float)bj) / d.y : INFINITY;
    float s = r->scale;
    int n = 0;
    for (; n < P->max_cells; ++n) {
        float t_out = fmin(fmin(tx, ty), r->t_exit);
        float4 k = om_patch(f, i, j);
        f->fetches += 1u;
        float e1 = k.y - k.x, e2 = k.z - k.x, e3 = k.x - k.y - k.z + k.w;
        float2 ab = c0 - t * d - OM_F2((float)i, (float)j);
        float da = -d.x, db = -d.y;
        float h0 = k.x + e1 * ab.x + e2 * ab.y + e3 * ab.x * ab.y;
        // f(tau) = z(t + tau) - s (H(tau) - r), with z(t) = -t V.z.
        float q0 = -t * r->v.z - s * (h0 - r->ref);
        float q1 = -r->v.z - s * (e1 * da + e2 * db + e3 * (ab.x * db + ab.y * da));
        float q2 = -s * e3 * da * db;
        if (q0 <= 0.0f) {
            *t_hit = t;
            return om_ray_uv(r, t);
        }
        float tau = om_first_root(q0, q1, q2, t_out - t);
        if (tau >= 0.0f) {
            *t_hit = t + tau;
            return om_ray_uv(r, t + tau);
        }
        if (t_out >= r->t_exit) break;
        t = t_out;
        if (tx <= ty) {
            i += si;
            bi += si;
            tx = (c0.x - (float)bi) / d.x;
        } else {
            j += sj;
            bj += sj;
            ty = (c0.y - (float)bj) / d.y;
        }
    }
    // Reached through rounding at the bottom plane, where the gap is exactly 0 when H = 0 (the
    // root at the segment's end can round away), or through the cap.
    if (n == P->max_cells) *flags |= OM_FLAG_CAPPED;
    *t_hit = r->t_exit;
    return om_ray_uv(r, r->t_exit);
}
