// Height sampling, for OM_LANES pixels at once (lanes.h; the prep kernels and the shade pass use it
// with one). Conventions (DESIGN.md): texel (i, j) has its centre at uv = ((i + 0.5) / W,
// (j + 0.5) / H); bilinear between texel centres; wrap (tiling) or clamp. Each lane may read its
// own mip level (LOD), so the level's offset and size are per lane.

typedef struct {
    __global const float* h;  // level 0 (the pyramid's start)
    OmI level;                // each lane's mip level
    OmI offset;               // start of each lane's level
    OmI w, hgt;               // each lane's level size
    OmF fw, fh;
    int wrap;
    int pot;  // level 0 is a power of two both ways, so every level is: wrap by mask
    __global const float* aux;  // the method's precomputed data (cone map), or NULL
} OmLaneField;

// The field at each lane's mip level, clamped to the levels present. Level k is max(1, W >> k) x
// max(1, H >> k) texels stored after level k - 1; texel centres follow the same convention at every
// level, so a level samples the same uv as level 0.
OM_INLINE OmLaneField om_lane_field(__global const float* h, const OmOffsetParams* P, OmI level) {
    OmLaneField f;
    f.h = h;
    f.wrap = P->address_mode == OM_ADDRESS_WRAP;
    f.pot = (P->hf_width & (P->hf_width - 1)) == 0 && (P->hf_height & (P->hf_height - 1)) == 0;
    level = clamp(level, 0, max(P->mip_levels - 1, 0));
    OmI w = P->hf_width, hgt = P->hf_height, offset = 0;
    for (int k = 0; k < P->mip_levels - 1 && OM_ANY(level > k); ++k) {
        OmI below = k < level;
        offset = OM_SEL(offset, offset + w * hgt, below);
        w = OM_SEL(w, max(w / 2, 1), below);
        hgt = OM_SEL(hgt, max(hgt / 2, 1), below);
    }
    f.aux = 0;
    f.level = level;
    f.offset = offset;
    f.w = w;
    f.hgt = hgt;
    f.fw = OM_TO_FLOAT(w);
    f.fh = OM_TO_FLOAT(hgt);
    return f;
}

// Level 0 of a w x hgt map (the prep kernels and the shade pass).
OM_INLINE OmLaneField om_lane_field_of(__global const float* h, int w, int hgt, int wrap) {
    OmOffsetParams P;
    P.hf_width = w;
    P.hf_height = hgt;
    P.address_mode = wrap ? OM_ADDRESS_WRAP : OM_ADDRESS_CLAMP;
    P.mip_levels = 1;
    return om_lane_field(h, &P, (OmI)0);
}

// Integer % has no SIMD instruction (PoCL splits it into a division per lane): when every lane's
// n is a power of two (the usual map, level and distance-map sizes) a mask gives the same residue,
// negative i included.
OM_INLINE OmI om_lane_wrap(OmI i, OmI n) {
    if (!OM_ANY((n & (n - 1)) != 0)) return i & (n - 1);
    OmI r = i % n;
    return OM_SEL(r, r + n, r < 0);
}

// The texel columns i0, i1 = i + 1 and rows j0, j1 = j + 1 of each lane's patch (i, j) after the
// field's address mode. Resolved once per patch, not per texel: integer % costs tens of cycles on a
// CPU, and power-of-two maps need none (a mask also wraps negative indices).
OM_INLINE void om_lane_address(const OmLaneField* f, OmI i, OmI j, OmI* i0, OmI* i1, OmI* j0,
                               OmI* j1) {
    if (f->wrap && f->pot) {
        *i0 = i & (f->w - 1);
        *i1 = (i + 1) & (f->w - 1);
        *j0 = j & (f->hgt - 1);
        *j1 = (j + 1) & (f->hgt - 1);
    } else if (f->wrap) {
        *i0 = om_lane_wrap(i, f->w);
        *i1 = OM_SEL(*i0 + 1, 0, *i0 + 1 == f->w);
        *j0 = om_lane_wrap(j, f->hgt);
        *j1 = OM_SEL(*j0 + 1, 0, *j0 + 1 == f->hgt);
    } else {
        *i0 = clamp(i, 0, f->w - 1);
        *i1 = clamp(i + 1, 0, f->w - 1);
        *j0 = clamp(j, 0, f->hgt - 1);
        *j1 = clamp(j + 1, 0, f->hgt - 1);
    }
}

// One stored texel (i, j) per lane, after the address mode.
OM_INLINE OmF om_lane_texel(const OmLaneField* f, OmI i, OmI j OM_IMG_PARAM) {
    OmI i0, i1, j0, j1;
    om_lane_address(f, i, j, &i0, &i1, &j0, &j1);
    return OM_HEIGHTS(f->h, f->offset + j0 * f->w + i0);
}

// The four corners of each lane's patch (i, j) (integer texel-centre coordinates): k00 at (i, j),
// k10 at (i + 1, j), k01, k11.
OM_INLINE void om_lane_corners(const OmLaneField* f, OmI i, OmI j, OmF* k00, OmF* k10, OmF* k01,
                               OmF* k11 OM_IMG_PARAM) {
    OmI i0, i1, j0, j1;
    om_lane_address(f, i, j, &i0, &i1, &j0, &j1);
    OmI r0 = f->offset + j0 * f->w, r1 = f->offset + j1 * f->w;
#ifdef OM_PAIR_GATHER
    // Each row's two corners as one pair, unless a lane's row wraps or is clamped at the edge
    // (and p[i + 1] could lie past the buffer). A branch, not a lane mask on the gathers: a
    // predicted branch lets the gathers start before the test is done, a mask delays every
    // dependent fetch by its reduction. Without the hint, the code PoCL made for pom's search
    // was 20 % slower than with the mask; with it every method is as fast or faster (A/B runs).
    if (__builtin_expect(!OM_ANY(i1 != i0 + 1), 1)) {
        om_gather_pairs(f->h, r0 + i0, k00, k10);
        om_gather_pairs(f->h, r1 + i0, k01, k11);
        return;
    }
#endif
    *k00 = OM_HEIGHTS(f->h, r0 + i0);
    *k10 = OM_HEIGHTS(f->h, r0 + i1);
    *k01 = OM_HEIGHTS(f->h, r1 + i0);
    *k11 = OM_HEIGHTS(f->h, r1 + i1);
}

// The four corners of the patch under (u, v) and the position (a, b) inside it.
OM_INLINE void om_lane_patch(const OmLaneField* f, OmF u, OmF v, OmF* a, OmF* b, OmF* k00, OmF* k10,
                             OmF* k01, OmF* k11 OM_IMG_PARAM) {
    OmF cx = clamp(u * f->fw - 0.5f, -1.0e8f, 1.0e8f);
    OmF cy = clamp(v * f->fh - 0.5f, -1.0e8f, 1.0e8f);
    OmF fx = OM_LFLOOR(cx), fy = OM_LFLOOR(cy);
    *a = cx - fx;
    *b = cy - fy;
    om_lane_corners(f, OM_TO_INT(fx), OM_TO_INT(fy), k00, k10, k01, k11 OM_IMG_ARG);
}

// Bilinear height H(u, v) in [0, 1] per lane.
OM_INLINE OmF om_lane_height_at(const OmLaneField* f, OmF u, OmF v OM_IMG_PARAM) {
    OmF a, b, k00, k10, k01, k11;
    om_lane_patch(f, u, v, &a, &b, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    return mix(mix(k00, k10, a), mix(k01, k11, a), b);
}

// The same, counting one fetch in the lanes of `active` (the methods' cost measure).
OM_INLINE OmF om_lane_height(const OmLaneField* f, OmF u, OmF v, OmI active,
                             OmI* fetches OM_IMG_PARAM) {
    *fetches += OM_ONE(active);
    return om_lane_height_at(f, u, v OM_IMG_ARG);
}

// Bilinear height and its exact gradient (dH/du, dH/dv) on the patch: the gradient of the bilinear
// surface itself, so slope methods follow the same relief that `exact` intersects.
OM_INLINE OmF om_lane_height_grad(const OmLaneField* f, OmF u, OmF v, OmI active, OmI* fetches,
                                  OmF* gu, OmF* gv OM_IMG_PARAM) {
    OmF a, b, k00, k10, k01, k11;
    om_lane_patch(f, u, v, &a, &b, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    *fetches += OM_ONE(active);
    *gu = mix(k10 - k00, k11 - k01, b) * f->fw;
    *gv = mix(k01 - k00, k11 - k10, a) * f->fh;
    return mix(mix(k00, k10, a), mix(k01, k11, a), b);
}
