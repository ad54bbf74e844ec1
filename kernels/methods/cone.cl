// cone: cone step mapping (Dummer 2006; Policarpo & Oliveira, GPU Gems 3 ch. 18) made robust and
// exact. The cone map (kernels/prep/cone.cl) gives every cell its maximum height Hc and a cone
// ratio c (texels per unit of H) whose cone over the whole cell is free of relief, so a step by the
// cone is safe from any point of the cell, whatever bilinear filtering does between texel centres
// (the failure Bán et al., "Robust cone step mapping", EGSR 2024, point out in per-texel cones).
// Per cell the ray is in:
//  - if the ray stays above Hc until it leaves the cell, the cell is empty: step by the larger of
//    the cone step and the cell exit (both safe). This minimum step is what keeps conservative
//    cones from crawling near the surface (Bán et al.'s minimum step size; Policarpo's relaxed
//    cones get their speed by allowing an overshoot, which then needs a binary search and can cross
//    thin features twice).
//  - otherwise solve the cell exactly (om_patch_hit, shared with `exact`): the first root is the
//    answer, else go on from the cell exit.
// So the result is `exact`'s, to float precision, and each step leaves at least one cell.
// Cone step from height Hr (H units) with the ray moving |d| texels across and V.z / s in H per
// unit t: it stays in the cone while |d| dt < c (Hr - V.z/s dt - Hc), i.e. dt = c (Hr - Hc) / (|d|
// + c V.z/s). Clamp addressing: cells off the map have no cone (c = 0: walked cell by cell). Cost:
// one cone fetch per step plus one patch per cell the ray dips below its cell maximum.
inline float2 om_cone_cell(OmHeightField* f, const OmOffsetParams* P, int i, int j) {
    f->fetches += 1u;
    if (P->address_mode == OM_ADDRESS_WRAP) {
        if (f->pot) {
            i &= f->w - 1;
            j &= f->hgt - 1;
        } else {
            i = om_wrap_index(i, f->w);
            j = om_wrap_index(j, f->hgt);
        }
    } else if (i < 0 || j < 0 || i >= f->w || j >= f->hgt) {
        float4 k = om_patch(f, i, j);
        return OM_F2(fmax(fmax(k.x, k.y), fmax(k.z, k.w)), 0.0f);
    }
    __global const float* c = f->aux + 2 * (j * f->w + i);
    return OM_F2(c[0], c[1]);
}

float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    float2 c0 = om_cell_coord(f, r->uv);
    float2 d = OM_F2(r->v.x * f->fw, r->v.y * f->fh);
    float across = length(d), down = r->v.z / r->scale;  // texels and H per unit t
    float t = r->t_enter;
    int i = (int)om_floor(c0.x - t * d.x), j = (int)om_floor(c0.y - t * d.y);
    int si = d.x > 0.0f ? -1 : 1, sj = d.y > 0.0f ? -1 : 1;
    // The cone map is built from level 0: under LOD (a coarser level) walk cells like `exact`.
    bool cones = f->level == 0;
    int n = 0;
    for (; n < P->max_cells; ++n) {
        int bi = si < 0 ? i : i + 1, bj = sj < 0 ? j : j + 1;
        float tx = d.x != 0.0f ? (c0.x - (float)bi) / d.x : INFINITY;
        float ty = d.y != 0.0f ? (c0.y - (float)bj) / d.y : INFINITY;
        float t_out = fmin(fmin(tx, ty), r->t_exit);
        float2 cell = cones ? om_cone_cell(f, P, i, j) : OM_F2(1.0f, 0.0f);
        if (r->ref - t_out * down < cell.x) {
            float hit;
            if (om_patch_hit(r, f, i, j, c0, d, t, t_out, &hit)) {
                *t_hit = hit;
                return om_ray_uv(r, hit);
            }
        } else if (cell.y > 0.0f) {
            float t_cone = t + cell.y * (r->ref - t * down - cell.x) / (across + cell.y * down);
            if (t_cone > t_out) {
                if (t_cone >= r->t_exit) break;
                int ni = (int)om_floor(c0.x - t_cone * d.x),
                    nj = (int)om_floor(c0.y - t_cone * d.y);
                if (ni != i || nj != j) {  // rounding can leave it in this cell: step normally
                    t = t_cone;
                    i = ni;
                    j = nj;
                    continue;
                }
            }
        }
        if (t_out >= r->t_exit) break;
        t = t_out;
        if (tx <= ty)
            i += si;
        else
            j += sj;
    }
    if (n == P->max_cells) *flags |= OM_FLAG_CAPPED;
    *t_hit = r->t_exit;
    return om_ray_uv(r, r->t_exit);
}
