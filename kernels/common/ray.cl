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
#ifdef OM_CURVED
    // The base's curvature (docs/design.md, "Curved surfaces"): in the ray's vertical plane the
    // circle of normal curvature kn = e.K.e, and the cross term kc = e_perp.K.e, with e = -V.xy /
    // |V.xy| the direction the footprint runs ((1, 0) for a vertical view); in uv units. The
    // trace runs in the surface's lengths (one uv density each way); an offset (x, y) there is
    // (x / a, y a) in uv for the uv's stretch a: su = 1 / a, sv = a.
    OmF kn, kc, ex, ey, lxy, su, sv;
#ifdef OM_UV_METRIC
    // The uv metric's (docs/design.md, "The uv metric"): the footprint at arc length l along e
    // and `side` across it lies at l m + side n + l^2 g in uv (m = A e, n = A e_perp for A the
    // inverse of the uv's Jacobian in the frame, g = -Gamma(m, m) / 2), and the relief there is
    // 1 / clamp(1 - d.offset, 1/4, 4) times as deep (d: the density's log rate, Gamma's trace
    // / 2; the reciprocal linear, so no sample divides).
    OmF mu, mv, nu, nv, gu, gv, du, dv;
#endif
    OmI curved;     // lanes over a curved base; the rest trace the plane, bit for bit
    OmI exits_top;  // curved lanes that leave the slab through its top again (a convex base)
    int any_curved;
#endif
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
#ifdef OM_CURVED
    r->curved = 0;
    r->exits_top = 0;
    r->any_curved = 0;
#endif
    flags =
        OM_SEL(flags, (flags & (int)OM_FLAG_RENORMALIZED) | (int)OM_FLAG_BACKFACING, backfacing);
    flags = OM_SEL(flags, (OmI)OM_FLAG_INVALID, invalid);
    return OM_SEL(flags, (OmI)OM_FLAG_EMPTY, empty);
}

#ifdef OM_CURVED
#ifdef OM_UV_METRIC
// The uv metric at a pixel (docs/design.md, "The uv metric"): dP/du and dP/dv in the pixel's
// tangent frame in the pass's lengths (j00 = dP/du.T, j10 = dP/du.B, j01 = dP/dv.T, j11 =
// dP/dv.B, over the uv density), and the Christoffel symbols of the uv parametrisation,
// Gamma^u_uu, _uv, _vv (g*) and Gamma^v_uu, _uv, _vv (h*).
typedef struct {
    OmF j00, j10, j01, j11, guu, guv, gvv, huu, huv, hvv;
} OmUvMetric;
#define OM_METRIC_PARAM , const OmUvMetric* mt

// A metric the trace can use: every value finite and the Jacobian well inside its orientation
// (det J above 1e-6 of |J|^2: a zero plane, a pole's collapsed row or a frame mirrored against
// its uv is none, and the pixel keeps the curvature plane's stretch).
OM_INLINE OmI om_metric_usable(const OmUvMetric* m) {
    const OmF det = m->j00 * m->j11 - m->j01 * m->j10;
    const OmF norm = m->j00 * m->j00 + m->j10 * m->j10 + m->j01 * m->j01 + m->j11 * m->j11;
    const OmF g = m->guu + m->guv + m->gvv + m->huu + m->huv + m->hvv;
    return isfinite(det) && isfinite(norm) && isfinite(g) && det > 1.0e-6f * norm;
}

// A Jacobian within 2^-12 of the identity (float positions and uv leave an isotropic flat mesh a
// few 1e-6 off: as the stretch's rule, a 10-texel offset moves by under 0.002 texel).
OM_INLINE OmI om_metric_identity(const OmUvMetric* m) {
    const float e = 0x1p-12f;
    return fabs(m->j00 - 1.0f) <= e && fabs(m->j10) <= e && fabs(m->j01) <= e &&
           fabs(m->j11 - 1.0f) <= e;
}

// A pixel on the tangent plane whatever its symbols: no curvature, no stretch (1, or none) and
// an identity Jacobian. Its symbols are not read (their term is second order in a footprint
// whose first order is the plane's), so it traces the plane, bit for bit.
OM_INLINE OmI om_metric_flat(OmF kuu, OmF kuv, OmF kvv, OmF stretch, const OmUvMetric* m) {
    const OmI no_stretch = stretch == 1.0f || !(stretch > 0.0f) || isinf(stretch);
    return kuu == 0.0f && kuv == 0.0f && kvv == 0.0f && no_stretch && om_metric_identity(m);
}

// A metric that moves a pixel with no curvature and no stretch off the plane's trace: a
// Jacobian off the identity (with it, the pixel is om_metric_flat and its symbols are unread).
OM_INLINE OmI om_metric_bends(const OmUvMetric* m) { return !om_metric_identity(m); }

// The ray's footprint terms from the metric (A = J^-1; lanes without a usable one keep the
// stretch's A = diag(1 / a, a) and no rates).
OM_INLINE void om_ray_metric(OmRay* r, const OmUvMetric* m, OmI usable) {
    const OmF inv = 1.0f / (m->j00 * m->j11 - m->j01 * m->j10);
    const OmF a00 = OM_SEL(r->su, m->j11 * inv, usable);
    const OmF a01 = OM_SEL((OmF)0.0f, -m->j01 * inv, usable);
    const OmF a10 = OM_SEL((OmF)0.0f, -m->j10 * inv, usable);
    const OmF a11 = OM_SEL(r->sv, m->j00 * inv, usable);
    const OmF ex = r->ex, ey = r->ey;
    r->mu = a00 * ex + a01 * ey;
    r->mv = a10 * ex + a11 * ey;
    r->nu = a01 * ex - a00 * ey;
    r->nv = a11 * ex - a10 * ey;
    const OmF uu = r->mu * r->mu, uv = 2.0f * r->mu * r->mv, vv = r->mv * r->mv;
    r->gu = OM_SEL((OmF)0.0f, -0.5f * (m->guu * uu + m->guv * uv + m->gvv * vv), usable);
    r->gv = OM_SEL((OmF)0.0f, -0.5f * (m->huu * uu + m->huv * uv + m->hvv * vv), usable);
    r->du = OM_SEL((OmF)0.0f, 0.5f * (m->guu + m->huv), usable);
    r->dv = OM_SEL((OmF)0.0f, 0.5f * (m->guv + m->hvv), usable);
}
#else
#define OM_METRIC_PARAM
#endif

// The ray over a curved base: K = [[kuu, kuv], [kuv, kvv]] in uv units per lane (positive bends
// away from N), and the uv's stretch a (1, or not a finite value above 0: none). Lanes with K = 0
// and no stretch, a non-finite K or no depth scale stay on the plane. On the rest,
// the slab between h = s (1 - r) and h = -s r over the circle of curvature kn is met where
//   kn t^2 - 2 V.z t - H0 (2 + kn H0) = 0    (h(t) = H0, |V| = 1),
// entered at the root through t < 0 and left at the bottom's first root t >= 0, or, where a
// convex base turns the ray away before the bottom (no real root), through the top's second.
// kn is held within 1 / (2 s) in magnitude: a base bent tighter than twice the relief's depth
// leaves the circles of the slab degenerate (the model's stated limit).
OM_INLINE void om_ray_curve(OmRay* r, OmF kuu, OmF kuv, OmF kvv, OmF stretch,
                            OmI lanes OM_METRIC_PARAM) {
    const OmI finite = isfinite(kuu) && isfinite(kuv) && isfinite(kvv);
    // !(a > 0) also takes NaN; an infinite stretch is as unusable.
    const OmF a = OM_SEL(stretch, (OmF)1.0f, !(stretch > 0.0f) || isinf(stretch));
#ifdef OM_UV_METRIC
    const OmI metric = om_metric_usable(mt);
    const OmI curved = lanes & finite &
                       (kuu != 0.0f || kuv != 0.0f || kvv != 0.0f || a != 1.0f ||
                        (metric & om_metric_bends(mt)));
#else
    const OmI curved = lanes & finite & (kuu != 0.0f || kuv != 0.0f || kvv != 0.0f || a != 1.0f);
#endif
    r->curved = r->scale > 0.0f ? curved : (OmI)0;
    r->any_curved = OM_ANY(r->curved);
    if (!r->any_curved) return;
    const OmF lxy = sqrt(r->vx * r->vx + r->vy * r->vy);
    const OmI plumb = !(lxy > 0.0f);
    const OmF ex = OM_SEL(-r->vx / lxy, 1.0f, plumb), ey = OM_SEL(-r->vy / lxy, 0.0f, plumb);
    const OmF kx = OM_SEL((OmF)0.0f, kuu * ex + kuv * ey, curved);
    const OmF ky = OM_SEL((OmF)0.0f, kuv * ex + kvv * ey, curved);
    const float k_max = 0.5f / r->scale;
    r->kn = clamp(ex * kx + ey * ky, -k_max, k_max);
    r->kc = ex * ky - ey * kx;
    r->ex = ex;
    r->ey = ey;
    r->lxy = OM_SEL(lxy, (OmF)0.0f, plumb);
    r->su = 1.0f / a;
    r->sv = a;
#ifdef OM_UV_METRIC
    om_ray_metric(r, mt, metric);
#endif
    const float top = r->scale * (1.0f - r->ref), bottom = -r->scale * r->ref;
    const OmF vz = r->vz, kn = r->kn;
    const OmF c_top = top * (2.0f + kn * top), c_bottom = bottom * (2.0f + kn * bottom);
    const OmF q_top = vz + sqrt(fmax(vz * vz + kn * c_top, 0.0f));
    const OmF d_bottom = vz * vz + kn * c_bottom;
    const OmI away = curved & (d_bottom < 0.0f);  // only where kn > 0
    const OmF t_bottom = -c_bottom / (vz + sqrt(fmax(d_bottom, 0.0f)));
    r->exits_top = away;
    r->t_enter = OM_SEL(r->t_enter, -c_top / q_top, curved);
    r->t_exit = OM_SEL(r->t_exit, OM_SEL(t_bottom, q_top / kn, away), curved);
}

// The curved lanes' ray at t: the footprint's offset (dx, dy) from the pixel in uv and the height h
// above the base along its normal (uv units), from the ray's point (a, z) = (t |V.xy|, -t V.z) in
// its vertical plane (docs/design.md): with c = 1 + kn z and q = sqrt(c^2 + (kn a)^2),
//   h = (2 z + kn t^2) / (q + 1),   arc = atan2(kn a, c) / kn,   sideways -h kc arc.
// Both are exact for kn = 0 (h = z, arc = a). The point keeps what its rates reuse.
// Under the uv metric the point also holds its footprint offset (dx, dy), the relief's depth
// factor's reciprocal g there and he = h g, the height the relief is compared with (h / s + r
// against H).
typedef struct {
    OmF c, ka, q, h, arc;
#ifdef OM_UV_METRIC
    OmF dx, dy, g, he;
#endif
} OmCurvePoint;

OM_INLINE OmCurvePoint om_curve_point(const OmRay* r, OmF t) {
    OmCurvePoint p;
    const OmF a = t * r->lxy, z = -t * r->vz;
    p.c = 1.0f + r->kn * z;
    p.ka = r->kn * a;
    p.q = sqrt(p.c * p.c + p.ka * p.ka);
    p.h = (2.0f * z + r->kn * (t * t)) / (p.q + 1.0f);
    p.arc = OM_SEL(a * (atan2(p.ka, p.c) / p.ka), a, p.ka == 0.0f);
#ifdef OM_UV_METRIC
    const OmF side = -p.h * r->kc * p.arc;
    p.dx = OM_FMA(p.arc, OM_FMA(p.arc, r->gu, r->mu), side * r->nu);
    p.dy = OM_FMA(p.arc, OM_FMA(p.arc, r->gv, r->mv), side * r->nv);
    p.g = clamp(1.0f - (r->du * p.dx + r->dv * p.dy), 0.25f, 4.0f);
    p.he = p.h * p.g;
#endif
    return p;
}

// The point's footprint offset: arc along e, -h kc arc across it, in uv.
OM_INLINE void om_curve_offset(const OmRay* r, const OmCurvePoint* p, OmF* dx, OmF* dy) {
#ifdef OM_UV_METRIC
    *dx = p->dx;
    *dy = p->dy;
#else
    const OmF side = -p->h * r->kc * p->arc;
    *dx = (p->arc * r->ex - side * r->ey) * r->su;
    *dy = (p->arc * r->ey + side * r->ex) * r->sv;
#endif
}

// The height the point's relief is compared with (h / s + r against H): h, or under the uv
// metric h over the relief's depth factor there.
OM_INLINE OmF om_curve_height(const OmCurvePoint* p) {
#ifdef OM_UV_METRIC
    return p->he;
#else
    return p->h;
#endif
}

OM_INLINE void om_curve_at(const OmRay* r, OmF t, OmF* dx, OmF* dy, OmF* h) {
    const OmCurvePoint p = om_curve_point(r, t);
    om_curve_offset(r, &p, dx, dy);
    *h = om_curve_height(&p);
}

// The curve's rates at a point, d/dt of its offset (dx, dy) and h: the ray's direction against
// the circle's normal and tangent at the foot's angle phi (cos phi = c / q, sin phi = kn a / q),
//   h' = |V.xy| sin phi - V.z cos phi,   arc' = (|V.xy| c + V.z kn a) / q^2.
// Under the uv metric, d/dt of l m + side n + l^2 g, and of he = h g: h' g + h g' (g' = 0 where
// g is held at its bounds).
OM_INLINE void om_curve_rate(const OmRay* r, const OmCurvePoint* p, OmF* ddx, OmF* ddy, OmF* dh) {
    *dh = (r->lxy * p->ka - r->vz * p->c) / p->q;
    const OmF darc = (r->lxy * p->c + r->vz * p->ka) / (p->q * p->q);
    const OmF dside = -r->kc * (*dh * p->arc + p->h * darc);
#ifdef OM_UV_METRIC
    const OmF dl2 = 2.0f * p->arc * darc;
    *ddx = darc * r->mu + dside * r->nu + dl2 * r->gu;
    *ddy = darc * r->mv + dside * r->nv + dl2 * r->gv;
    const OmF dg =
        OM_SEL(-(r->du * *ddx + r->dv * *ddy), (OmF)0.0f, p->g <= 0.25f || p->g >= 4.0f);
    *dh = *dh * p->g + p->h * dg;
#else
    *ddx = (darc * r->ex - dside * r->ey) * r->su;
    *ddy = (darc * r->ey + dside * r->ex) * r->sv;
#endif
}

// The curved lanes' footprint at the point, over the plane's (x, y) from the same t.
OM_INLINE void om_curve_select(const OmRay* r, const OmCurvePoint* p, OmF* x, OmF* y) {
    OmF dx, dy;
    om_curve_offset(r, p, &dx, &dy);
    *x = OM_SEL(*x, r->u + dx, r->curved);
    *y = OM_SEL(*y, r->v + dy, r->curved);
}
#endif

// The ray's footprint at t: uv' of a hit there (flat: (u, v) - t V.xy).
OM_INLINE void om_ray_footprint(const OmRay* r, OmF t, OmF* x, OmF* y) {
    *x = r->u - t * r->vx;
    *y = r->v - t * r->vy;
#ifdef OM_CURVED
    if (r->any_curved) {
        const OmCurvePoint p = om_curve_point(r, t);
        om_curve_select(r, &p, x, y);
    }
#endif
}

// The ray's sample at lambda in [0, 1] from entry to exit: its footprint and its height in the
// heights' units (eta = h / s + r: H >= eta is at or below the relief; flat, eta = 1 - lambda).
OM_INLINE void om_ray_sample(const OmRay* r, OmF lambda, OmF* x, OmF* y, OmF* eta) {
    const OmF t = om_ray_t(r, lambda);
    *x = r->u - t * r->vx;
    *y = r->v - t * r->vy;
    *eta = 1.0f - lambda;
#ifdef OM_CURVED
    if (r->any_curved) {
        const OmCurvePoint p = om_curve_point(r, t);
        om_curve_select(r, &p, x, y);
#ifdef OM_UV_METRIC
        // A multiply by the scalar reciprocal: the metric's terms pay for themselves here.
        *eta = OM_SEL(*eta, om_curve_height(&p) * (1.0f / r->scale) + r->ref, r->curved);
#else
        *eta = OM_SEL(*eta, om_curve_height(&p) / r->scale + r->ref, r->curved);
#endif
    }
#endif
}

typedef struct {
    OmI index;   // first sample i in 0..n with H(lambda_i) >= eta_i
    OmF h_prev;  // height at sample index - 1 (1 when index is 0)
    OmF h_cur;   // height at sample index
#ifdef OM_CURVED
    OmF eta_prev, eta_cur;  // the ray's heights there (eta_prev 1 when index is 0)
#endif
    OmI miss;  // curved lanes: no sample met the relief before the ray left through the top
} OmSearchHit;

// n + 1 samples at lambda_i = i / n from the top plane down, each lane with its own n, stopping at
// the first sample at or below the relief (lambda_n = 1 is the bottom plane where every H >= 0, so
// each lane stops by i = n; a curved lane that leaves through the top again stops there too, a
// miss); the loop ends when every lane has. `curved` is a constant: the search is built twice, and
// a block without a curved lane runs the plane's loop with none of the curve's work in it.
OM_INLINE OmSearchHit om_linear_search_as(const OmRay* r, const OmField* f, OmI n, OmI active,
                                          OmI* fetches OM_IMG_PARAM, const int curved) {
    OmSearchHit hit;
    hit.index = n;
    hit.h_prev = 1.0f;
    hit.h_cur = 0.0f;
    hit.miss = 0;
    OmF h_prev = 1.0f, inv_n = 1.0f / OM_TO_FLOAT(n);
#ifdef OM_CURVED
    hit.eta_prev = 1.0f;
    hit.eta_cur = 0.0f;
    OmF eta_prev = 1.0f;
#endif
    // Sample i at cell coordinates c0 + i dc: the top plane's point, then one step of
    // (t_exit - t_enter) / n along -V.xy.
    OmF dt = (r->t_exit - r->t_enter) * inv_n;
    OmF cx0 = OM_CELL(r->u - r->t_enter * r->vx, f->fw);
    OmF cy0 = OM_CELL(r->v - r->t_enter * r->vy, f->fh);
    OmF dcx = -dt * r->vx * f->fw, dcy = -dt * r->vy * f->fh;
    OmI searching = active;
    for (int i = 0; OM_ANY(searching); ++i) {
        OmF fi = (OmF)(float)i, lambda = fi * inv_n;
        OmF cx = OM_FMA(fi, dcx, cx0), cy = OM_FMA(fi, dcy, cy0), eta = 1.0f - lambda;
#ifdef OM_CURVED
        if (curved) {
            OmF x, y, eta_c;
            om_ray_sample(r, lambda, &x, &y, &eta_c);
            cx = OM_SEL(cx, OM_CELL(x, f->fw), r->curved);
            cy = OM_SEL(cy, OM_CELL(y, f->fh), r->curved);
            eta = OM_SEL(eta, eta_c, r->curved);
        }
#endif
        OmF h = om_height_cell(f, cx, cy, searching, fetches OM_IMG_ARG);
        OmI below = h >= eta;
        OmI found = searching & (below || (OmI)i >= n);
        hit.index = OM_SEL(hit.index, (OmI)i, found);
        hit.h_prev = OM_SEL(hit.h_prev, h_prev, found);
        hit.h_cur = OM_SEL(hit.h_cur, h, found);
#ifdef OM_CURVED
        if (curved) {
            hit.miss |= found & !below & r->curved;
            hit.eta_prev = OM_SEL(hit.eta_prev, eta_prev, found);
            hit.eta_cur = OM_SEL(hit.eta_cur, eta, found);
            eta_prev = eta;
        }
#endif
        searching &= !found;
        h_prev = h;
    }
    return hit;
}

OM_INLINE OmSearchHit om_linear_search(const OmRay* r, const OmField* f, OmI n, OmI active,
                                       OmI* fetches OM_IMG_PARAM) {
#ifdef OM_CURVED
    if (r->any_curved) return om_linear_search_as(r, f, n, active, fetches OM_IMG_ARG, 1);
#endif
    return om_linear_search_as(r, f, n, active, fetches OM_IMG_ARG, 0);
}

// The ray's heights at the search's bracket [l0, l1] = [(index - 1) / n, index / n], as the
// methods' gaps take them (flat: 1 - l).
OM_INLINE void om_search_etas(const OmRay* r, const OmSearchHit* hit, OmF l0, OmF l1, OmF* eta0,
                              OmF* eta1) {
    *eta0 = 1.0f - l0;
    *eta1 = 1.0f - l1;
#ifdef OM_CURVED
    *eta0 = OM_SEL(*eta0, hit->eta_prev, r->curved);
    *eta1 = OM_SEL(*eta1, hit->eta_cur, r->curved);
#endif
}

// Curved lanes whose answer t is the slab's exit through the top: the ray left without a hit.
OM_INLINE OmI om_left_through_top(const OmRay* r, OmF t) {
#ifdef OM_CURVED
    return r->exits_top & (t >= r->t_exit);
#else
    return (OmI)0;
#endif
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
// Either way t' is clamped to the slab [t_enter, t_exit]. Over a curved base the same Newton step
// on gap(t) = s (H - r) - h(t), with the curve's rates for -V.
OM_INLINE OmF om_slope_step(const OmRay* r, const OmField* f, OmF t, int safe, OmI active,
                            OmI* fetches OM_IMG_PARAM) {
    OmF gu, gv, x = r->u - t * r->vx, y = r->v - t * r->vy;
#ifdef OM_CURVED
    OmCurvePoint p;
    if (r->any_curved) {
        p = om_curve_point(r, t);
        om_curve_select(r, &p, &x, &y);
    }
#endif
    OmF h = om_height_grad(f, x, y, active, fetches, &gu, &gv OM_IMG_ARG);
    OmF gap = r->scale * (h - r->ref) + t * r->vz;
    OmF su = r->scale * gu, sv = r->scale * gv;
    OmF rate = r->vz - (su * r->vx + sv * r->vy);
#ifdef OM_CURVED
    if (r->any_curved) {
        OmF ddx, ddy, dh;
        om_curve_rate(r, &p, &ddx, &ddy, &dh);
        gap = OM_SEL(gap, r->scale * (h - r->ref) - om_curve_height(&p), r->curved);
        rate = OM_SEL(rate, su * ddx + sv * ddy - dh, r->curved);
    }
#endif
    OmF dt = safe ? gap * rsqrt(1.0f + su * su + sv * sv) : gap / fmax(rate, 1.0e-4f);
    return clamp(t - dt, r->t_enter, r->t_exit);
}
