// Triplanar projection (docs/design.md, "Triplanar relief"): a surface without uv takes its relief
// from up to three axis-aligned projections of the world, each a tangent frame of its own.
// Projection p = 2 axis + (1 where the normal's component along the axis is negative) names the
// frame (T, B, N) with N the signed axis and B = N x T (right-handed, handedness +1):
//   +X: T = -Z, B = +Y   -X: T = +Z, B = +Y
//   +Y: T = +X, B = -Z   -Y: T = +X, B = +Z
//   +Z: T = +X, B = +Y   -Z: T = -X, B = +Y
// so that a face seen head-on with +Y (or, for the floor, -Z) up shows its texture unmirrored, u to
// the right. uv = world_scale (P.T, P.B). Components are 0 or +-1 exactly, so a vector's
// components in a projection's frame (its dot products with T, B, N) are its world components
// moved and negated, without rounding.

// The first lane's value.
#if OM_LANES == 1
#define OM_FIRST(v) (v)
#else
#define OM_FIRST(v) ((v).s0)
#endif

// |x|^k: by squaring where every lane has one whole exponent up to 64 (a few multiplies, and
// closer than exp2(k log2 |x|), which the other cases take).
OM_INLINE OmF om_tri_pow(OmF x, OmF k, int whole) {
    x = fabs(x);
    if (!whole) return exp2(k * log2(x));  // a zero component: exp2(-inf) = 0
    int e = (int)OM_FIRST(k);
    OmF r = 1.0f;
    while (e) {
        if (e & 1) r *= x;
        x *= x;
        e >>= 1;
    }
    return r;
}

// Weights of the three axes from the normal n: |n_a|^sharpness, normalised, then each lowered by
// the cutoff, clamped at 0 and normalised again, so that a weight falls to zero continuously as it
// reaches the cutoff and the three always sum to one (the largest is at least 1/3, above any
// cutoff the host allows).
OM_INLINE void om_tri_weights(OmF nx, OmF ny, OmF nz, OmF sharpness, OmF cutoff, OmF* wx,
                              OmF* wy, OmF* wz) {
    const float k0 = OM_FIRST(sharpness);
    const int whole = !OM_ANY(sharpness != k0) && k0 == floor(k0) && k0 <= 64.0f;
    OmF ax = om_tri_pow(nx, sharpness, whole);
    OmF ay = om_tri_pow(ny, sharpness, whole);
    OmF az = om_tri_pow(nz, sharpness, whole);
    const OmF s = 1.0f / (ax + ay + az);
    ax = fmax(ax * s - cutoff, 0.0f);
    ay = fmax(ay * s - cutoff, 0.0f);
    az = fmax(az * s - cutoff, 0.0f);
    const OmF t = 1.0f / (ax + ay + az);
    *wx = ax * t;
    *wy = ay * t;
    *wz = az * t;
}

// Projection p's frame, per lane.
OM_INLINE void om_tri_frame(OmI p, OmF* tx, OmF* tz, OmF* by, OmF* bz, OmF* nx, OmF* ny,
                            OmF* nz) {
    const OmF one = 1.0f, zero = 0.0f, neg = -1.0f;
    const OmF s = OM_SEL(one, neg, (p & 1) != 0);
    // T.y = 0 and B.x = 0 in every frame.
    *tx = OM_SEL(OM_SEL(zero, one, p >= 2), neg, p == 5);
    *tz = OM_SEL(OM_SEL(zero, neg, p == 0), one, p == 1);
    *by = OM_SEL(one, zero, (p == 2) | (p == 3));
    *bz = OM_SEL(OM_SEL(zero, neg, p == 2), one, p == 3);
    *nx = OM_SEL(zero, s, (p >> 1) == 0);
    *ny = OM_SEL(zero, s, (p >> 1) == 1);
    *nz = OM_SEL(zero, s, (p >> 1) == 2);
}

// (x, y, z) in projection p's frame: (v.T, v.B, v.N).
OM_INLINE void om_tri_into(OmI p, OmF x, OmF y, OmF z, OmF* a, OmF* b, OmF* c) {
    OmF tx, tz, by, bz, nx, ny, nz;
    om_tri_frame(p, &tx, &tz, &by, &bz, &nx, &ny, &nz);
    *a = x * tx + z * tz;
    *b = y * by + z * bz;
    *c = x * nx + y * ny + z * nz;
}

// Projection p's (a, b, c) back in the world: a T + b B + c N.
OM_INLINE void om_tri_out(OmI p, OmF a, OmF b, OmF c, OmF* x, OmF* y, OmF* z) {
    OmF tx, tz, by, bz, nx, ny, nz;
    om_tri_frame(p, &tx, &tz, &by, &bz, &nx, &ny, &nz);
    *x = a * tx + c * nx;
    *y = b * by + c * ny;
    *z = a * tz + b * bz + c * nz;
}

// A direction's components (a, b, c) in a projection's frame turned into the ray of the relief over
// the surface: the relief lies over the surface's tangent plane (normal n), lifted along n, and
// each projection's uv is the world point's, so a step x along the ray moves uv by world_scale
// times x's T and B components less its normal share, (x.T - (x.n)(n.T), x.B - (x.n)(n.B)), and
// the depth, in the same uv units, by world_scale x.n (docs/design.md, "The ray in a projection").
// d = x.n, (nt, nb) = n's T and B components. Unit length; left as it was where n is the axis
// (nt = nb = 0), bit for bit. *scale: 1 / the sheared length, which turns a trace's t along the
// unit ray into t along x (in uv units of 1 / world_scale): 1 where n is the axis.
OM_INLINE void om_tri_over_surface(OmF* a, OmF* b, OmF* c, OmF d, OmF nt, OmF nb, OmF* scale) {
    const OmF ra = *a - d * nt, rb = *b - d * nb;
    const OmF k = 1.0f / sqrt(ra * ra + rb * rb + d * d);
    const OmI axis = (nt == 0.0f) & (nb == 0.0f);
    *a = OM_SEL(ra * k, *a, axis);
    *b = OM_SEL(rb * k, *b, axis);
    *c = OM_SEL(d * k, *c, axis);
    *scale = OM_SEL(k, (OmF)1.0f, axis);
}

// The projections of a pixel, largest weight first (ties: z before y before x), each with the sign
// of the normal's component on its axis (+ for 0), and their weights.
OM_INLINE void om_tri_order(OmF nx, OmF ny, OmF nz, OmF wx, OmF wy, OmF wz, OmI* p0, OmI* p1,
                            OmI* p2, OmF* w0, OmF* w1, OmF* w2) {
    const OmI px = OM_SEL((OmI)0, (OmI)1, nx < 0.0f);
    const OmI py = OM_SEL((OmI)2, (OmI)3, ny < 0.0f);
    const OmI pz = OM_SEL((OmI)4, (OmI)5, nz < 0.0f);
    const OmI z_first = (wz >= wy) & (wz >= wx);
    const OmI y_first = !z_first & (wy >= wx);
    // The first, then the other two in axis order z, y, x, swapped where the later one weighs more.
    *p0 = OM_SEL(OM_SEL(px, py, y_first), pz, z_first);
    *w0 = OM_SEL(OM_SEL(wx, wy, y_first), wz, z_first);
    const OmI x_later = z_first | y_first;
    const OmI a = OM_SEL(pz, py, z_first), b = OM_SEL(py, px, x_later);
    const OmF wa = OM_SEL(wz, wy, z_first), wb = OM_SEL(wy, wx, x_later);
    const OmI swap = wb > wa;
    *p1 = OM_SEL(a, b, swap);
    *p2 = OM_SEL(b, a, swap);
    *w1 = OM_SEL(wa, wb, swap);
    *w2 = OM_SEL(wb, wa, swap);
}

// A triplanar pixel in one float4 (the material frame's `blend` plane): x = 2 c + w1, with
// c = p0 + 6 (1 where the second projection is on the axis of the first's B, 0 on its T's), -1
// where the pixel is not triplanar; y = w2; z, w = the normal's x and y in the first projection's
// frame (its z, at least 1/sqrt(3), from them); w0 = 1 - w1 - w2. The second and third projections'
// signs are the normal's on their axes. w1 <= 1/2, so 2 c + w1 (at most 23.5) keeps w1 to 2^-20,
// and a pixel of one projection stores 2 c and 0 exactly: w0 = 1 and the axis-aligned normal
// (0, 0, 1) come back bit for bit.

// The axes of the first projection's T and B.
OM_INLINE OmI om_tri_t_axis(OmI p0) { return OM_SEL((OmI)0, (OmI)2, (p0 >> 1) == 0); }
OM_INLINE OmI om_tri_b_axis(OmI p0) { return OM_SEL((OmI)1, (OmI)2, (p0 >> 1) == 1); }

OM_INLINE OmF om_tri_pack_x(OmI p0, OmI p1, OmF w1) {
    const OmI c = p0 + 6 * OM_SEL((OmI)0, (OmI)1, (p1 >> 1) == om_tri_b_axis(p0));
    return 2.0f * OM_TO_FLOAT(c) + w1;
}

// A projection on axis a, signed as the world normal (nx, ny, nz) on it.
OM_INLINE OmI om_tri_on_axis(OmI a, OmF nx, OmF ny, OmF nz) {
    const OmF na = OM_SEL(OM_SEL(nx, ny, a == 1), nz, a == 2);
    return 2 * a + OM_SEL((OmI)0, (OmI)1, na < 0.0f);
}

// The blend plane's lanes back: which are triplanar, their projections and weights, and the world
// normal.
OM_INLINE OmI om_tri_unpack(OmF bx, OmF by, OmF bz, OmF bw, OmI* p, OmF* w, OmF* nx, OmF* ny,
                            OmF* nz) {
    const OmI on = bx >= 0.0f;
    const OmF cf = OM_LFLOOR(0.5f * fmax(bx, 0.0f));
    const OmI c = OM_TO_INT(cf);
    w[1] = OM_SEL((OmF)0.0f, bx - 2.0f * cf, on);
    w[2] = OM_SEL((OmF)0.0f, by, on);
    w[0] = 1.0f - w[1] - w[2];
    p[0] = c % 6;
    const OmF dz = sqrt(fmax(1.0f - bz * bz - bw * bw, 0.0f));
    om_tri_out(p[0], bz, bw, dz, nx, ny, nz);
    const OmI pt = om_tri_on_axis(om_tri_t_axis(p[0]), *nx, *ny, *nz);
    const OmI pb = om_tri_on_axis(om_tri_b_axis(p[0]), *nx, *ny, *nz);
    const OmI b_first = c >= 6;
    p[1] = OM_SEL(pt, pb, b_first);
    p[2] = OM_SEL(pb, pt, b_first);
    return on;
}
