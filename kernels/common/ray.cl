// The eye ray, per lane: p(t) = (u, v, 0) - t V enters the relief at the top plane z = s (1 - r)
// and leaves it at the bottom z = -s r (docs/design.md, "The ray"). Validation and the grazing
// rule, without branches (a rejected lane gets a harmless ray: uv 0, V = +z, and its result is
// dropped).
// Also the searches the marching methods share: the linear search and the slope step.

typedef struct {
    OmF u, v;        // start point in the local frame
    OmF vx, vy, vz;  // unit view vector, V.z >= min_vz
    float scale;     // s
    float ref;       // r
    OmF t_enter, t_exit;
    OmF detail;    // LOD step-count factor in (0, 1]
    OmI step_cap;  // LOD footprint mode: no more steps than the texels the ray crosses
} OmRay;

OM_INLINE OmI om_step_count(const OmRay* r, OmF n) {
    return max((OmI)1, min(OM_TO_INT(n * r->detail + 0.5f), r->step_cap));
}

OM_INLINE OmF om_ray_t(const OmRay* r, OmF lambda) {
    return r->t_enter + lambda * (r->t_exit - r->t_enter);
}

// Validates each lane's G-buffer pixel and builds its ray. Returns flags; a pixel with EMPTY,
// INVALID or BACKFACING set is passed through unchanged by the entry.
// Grazing rule (clamp and cap policies): V.z is raised to min_vz and V.xy rescaled to keep |V| = 1
// and the azimuth, so every march spans at most s / min_vz in uv and every loop count is bounded;
// the cap policy only raises min_vz (host side). The limit policy replaces V by normalize(V.xy, 1).
// Views below min_vz are flagged GRAZING under every policy. Tracing in a local frame (the
// fractional part of uv under wrap) keeps float precision for any tile index.
OM_INLINE OmI om_ray_setup(OmF u, OmF v, OmF vx, OmF vy, OmF vz, const OmOffsetParams* P, OmRay* r,
                           OmF* base_u, OmF* base_v) {
    OmI empty = isnan(u) || isnan(v);
    OmI finite = isfinite(u) && isfinite(v) && isfinite(vx) && isfinite(vy) && isfinite(vz);
    // Scale by the largest component first so |V| neither overflows nor underflows. Three
    // divisions: a reciprocal and three multiplies measured no faster.
    OmF m = fmax(fabs(vx), fmax(fabs(vy), fabs(vz)));
    OmI invalid = !finite || !(m > 0.0f);
    m = OM_SEL(m, 1.0f, invalid);
    vx = OM_SEL(vx / m, 0.0f, invalid);  // not * (1 / m): 1 / denormal overflows
    vy = OM_SEL(vy / m, 0.0f, invalid);
    vz = OM_SEL(vz / m, 1.0f, invalid);
    u = OM_SEL(u, 0.0f, !finite);
    v = OM_SEL(v, 0.0f, !finite);
    OmF len = sqrt(vx * vx + vy * vy + vz * vz);  // in [1, sqrt 3]
    OmI flags = OM_SEL((OmI)0, (OmI)OM_FLAG_RENORMALIZED, fabs(len * m - 1.0f) > 1.0e-3f);
    OmF inv = 1.0f / len;
    vx *= inv;
    vy *= inv;
    vz *= inv;
    OmI backfacing = !(vz > 0.0f);
    vx = OM_SEL(vx, 0.0f, backfacing);
    vy = OM_SEL(vy, 0.0f, backfacing);
    vz = OM_SEL(vz, 1.0f, backfacing);
    OmI grazing = vz < P->min_vz;
    flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_GRAZING, grazing);
    if (P->grazing == OM_GRAZING_LIMIT) {
        // Welsh's offset limiting as a ray: horizontal travel per unit of depth is |V.xy|, not
        // |V.xy| / V.z, so no offset exceeds the depth it crosses; biased at every angle but 90.
        OmF k = rsqrt(vx * vx + vy * vy + 1.0f);
        vx *= k;
        vy *= k;
        vz = k;
    } else if (OM_ANY(grazing)) {  // rare: most work-items skip the raise
        OmF k = sqrt(1.0f - P->min_vz * P->min_vz) / sqrt(vx * vx + vy * vy);
        vx = OM_SEL(vx, vx * k, grazing);
        vy = OM_SEL(vy, vy * k, grazing);
        vz = OM_SEL(vz, (OmF)P->min_vz, grazing);
    }
    bool wrap = P->address_mode == OM_ADDRESS_WRAP;
    *base_u = wrap ? OM_LFLOOR(u) : (OmF)0.0f;
    *base_v = wrap ? OM_LFLOOR(v) : (OmF)0.0f;
    r->u = u - *base_u;
    r->v = v - *base_v;
    r->vx = vx;
    r->vy = vy;
    r->vz = vz;
    r->scale = P->scale;
    r->ref = P->ref_plane;
    OmF inv_vz = 1.0f / vz;
    r->t_enter = -P->scale * (1.0f - P->ref_plane) * inv_vz;
    r->t_exit = P->scale * P->ref_plane * inv_vz;
    r->detail = 1.0f;
    r->step_cap = 0x7fffffff;
    flags =
        OM_SEL(flags, (flags & (int)OM_FLAG_RENORMALIZED) | (int)OM_FLAG_BACKFACING, backfacing);
    flags = OM_SEL(flags, (OmI)OM_FLAG_INVALID, invalid);
    return OM_SEL(flags, (OmI)OM_FLAG_EMPTY, empty);
}

typedef struct {
    OmI index;   // first sample i in 0..n with H(lambda_i) >= 1 - lambda_i
    OmF h_prev;  // height at sample index - 1 (1 when index is 0)
    OmF h_cur;   // height at sample index
} OmSearchHit;

// n + 1 samples at lambda_i = i / n from the top plane down, each lane with its own n, stopping at
// the first sample at or below the relief (lambda_n = 1 is the bottom plane where every H >= 0, so
// each lane stops by i = n); the loop ends when every lane has.
OM_INLINE OmSearchHit om_linear_search(const OmRay* r, const OmField* f, OmI n, OmI active,
                                       OmI* fetches OM_IMG_PARAM) {
    OmSearchHit hit;
    hit.index = n;
    hit.h_prev = 1.0f;
    hit.h_cur = 0.0f;
    OmF h_prev = 1.0f, inv_n = 1.0f / OM_TO_FLOAT(n);
    // Sample i at cell coordinates c0 + i dc: the top plane's point, then one step of
    // (t_exit - t_enter) / n along -V.xy.
    OmF dt = (r->t_exit - r->t_enter) * inv_n;
    OmF cx0 = OM_CELL(r->u - r->t_enter * r->vx, f->fw);
    OmF cy0 = OM_CELL(r->v - r->t_enter * r->vy, f->fh);
    OmF dcx = -dt * r->vx * f->fw, dcy = -dt * r->vy * f->fh;
    OmI searching = active;
    for (int i = 0; OM_ANY(searching); ++i) {
        OmF fi = (OmF)(float)i, lambda = fi * inv_n;
        OmF h = om_height_cell(f, fma(fi, dcx, cx0), fma(fi, dcy, cy0), searching,
                               fetches OM_IMG_ARG);
        OmI found = searching & (h >= 1.0f - lambda || (OmI)i >= n);
        hit.index = OM_SEL(hit.index, (OmI)i, found);
        hit.h_prev = OM_SEL(hit.h_prev, h_prev, found);
        hit.h_cur = OM_SEL(hit.h_cur, h, found);
        searching &= !found;
        h_prev = h;
    }
    return hit;
}

// The ray cut with the straight segment between two samples lambda_a < lambda_b whose gaps
// (height minus ray height) are g_a < 0 <= g_b: Tatarchuk's segment intersection, and one secant
// step. pom and secant share it, so secant without refinement is pom bit for bit.
OM_INLINE OmF om_segment_cut(OmF la, OmF lb, OmF ga, OmF gb) {
    return la + (lb - la) * (ga / (ga - gb));
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
OM_INLINE OmF om_slope_step(const OmRay* r, const OmField* f, OmF t, int safe, OmI active,
                            OmI* fetches OM_IMG_PARAM) {
    OmF gu, gv;
    OmF h =
        om_height_grad(f, r->u - t * r->vx, r->v - t * r->vy, active, fetches, &gu, &gv OM_IMG_ARG);
    OmF gap = r->scale * (h - r->ref) + t * r->vz;
    OmF su = r->scale * gu, sv = r->scale * gv;
    OmF dt = safe ? gap * rsqrt(1.0f + su * su + sv * sv)
                  : gap / fmax(r->vz - (su * r->vx + sv * r->vy), 1.0e-4f);
    return clamp(t - dt, r->t_enter, r->t_exit);
}
