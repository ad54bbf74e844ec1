// exact: the first hit of the eye ray with the bilinearly interpolated height field, the ground
// truth. A DDA walks the bilinear patches (cells between texel centres) the ray's footprint
// crosses from the top plane to the bottom plane, solving each (om_patch_hit, common/patch.cl).
// Cost: one patch (4 texels, counted as one fetch) per cell crossed, at most ~ (s / V.z)(W + H).
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
    int n = 0;
    for (; n < P->max_cells; ++n) {
        float t_out = fmin(fmin(tx, ty), r->t_exit);
        float hit;
        if (om_patch_hit(r, f, i, j, c0, d, t, t_out, &hit)) {
            *t_hit = hit;
            return om_ray_uv(r, hit);
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
