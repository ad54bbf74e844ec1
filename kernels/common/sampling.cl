// Height sampling, for OM_LANES pixels at once (lanes.h; the prep kernels and the shade pass use it
// with one). Conventions (docs/design.md): texel (i, j) has its centre at uv = ((i + 0.5) / W,
// (j + 0.5) / H); bilinear between texel centres; wrap (tiling) or clamp. Each lane may read its
// own mip level (LOD), so the level's offset and size are per lane.

typedef struct {
    __global const float* heights;  // the pyramid, level 0 first
    OmI level;                      // each lane's mip level
    OmI offset;                     // start of each lane's level
    OmI width, height;              // each lane's level size
    OmF fw, fh;                     // the same, as floats
    int wrap;
    int pot;  // level 0 is a power of two both ways, so every level is: wrap by mask
    // The method's precomputed data, or NULL: sphere's distance map, maxmip's pyramid of maxima
    // or cone's cone map (the registry row names it).
    __global const float* aux;
    // The heights' unorm16 words (DeviceHeightField::packed), or NULL: a patch's two words (i, j)
    // and (i + 1, j) hold its four corners.
    __global const uint* packed;
} OmField;

// Cell coordinate of u (or v) on an axis of n texels: texel i's centre, (i + 1/2) / n, is c = i,
// and cell i (the bilinear patch between centres i and i + 1) holds c in [i, i + 1). Every kernel
// that turns uv into texels goes through it.
#define OM_CELL(u, n) ((u) * (n)-0.5f)

// The field at each lane's mip level, clamped to the levels present. Level k is max(1, W >> k) x
// max(1, H >> k) texels stored after level k - 1; texel centres follow the same convention at every
// level, so a level samples the same uv as level 0.
OM_INLINE OmField om_field(__global const float* heights, const OmOffsetParams* P, OmI level) {
    OmField f;
    f.heights = heights;
    f.wrap = P->address_mode == OM_ADDRESS_WRAP;
    f.pot = (P->hf_width & (P->hf_width - 1)) == 0 && (P->hf_height & (P->hf_height - 1)) == 0;
    level = clamp(level, (OmI)0, (OmI)max(P->mip_levels - 1, 0));
    OmI w = P->hf_width, h = P->hf_height, offset = 0;
    for (int k = 0; k < P->mip_levels - 1 && OM_ANY(level > k); ++k) {
        OmI below = k < level;
        offset = OM_SEL(offset, offset + w * h, below);
        w = OM_SEL(w, max(w / 2, (OmI)1), below);
        h = OM_SEL(h, max(h / 2, (OmI)1), below);
    }
    f.aux = 0;
    f.packed = P->packed_heights ? (__global const uint*)(heights + P->packed_heights) : 0;
    f.level = level;
    f.offset = offset;
    f.width = w;
    f.height = h;
    f.fw = OM_TO_FLOAT(w);
    f.fh = OM_TO_FLOAT(h);
    return f;
}

// Level 0 of a width x height map (the prep kernels and the shade pass).
OM_INLINE OmField om_field_of(__global const float* heights, int width, int height, int wrap) {
    OmOffsetParams P;
    P.hf_width = width;
    P.hf_height = height;
    P.address_mode = wrap ? OM_ADDRESS_WRAP : OM_ADDRESS_CLAMP;
    P.mip_levels = 1;
    P.packed_heights = 0;  // float heights: om_field reads it (left unset, rusticl read garbage)
    return om_field(heights, &P, (OmI)0);
}

// Integer % has no SIMD instruction (PoCL splits it into a division per lane): when every lane's
// n is a power of two (the usual map, level and distance-map sizes) a mask gives the same residue,
// negative i included.
OM_INLINE OmI om_wrap(OmI i, OmI n) {
    if (!OM_ANY((n & (n - 1)) != 0)) return i & (n - 1);
    // The quotient in float, corrected by one either way: CPUs have no vector integer divide, so %
    // is a scalar division per lane (a quarter of exact's time on a 1025^2 map). Exact while
    // |i| < 2^24; past that, % for the lanes it missed.
    OmI q = OM_TO_INT(OM_LFLOOR(OM_TO_FLOAT(i) / OM_TO_FLOAT(n)));
    OmI r = i - q * n;
    r = OM_SEL(r, r + n, r < 0);
    r = OM_SEL(r, r - n, r >= n);
    OmI missed = (r < 0) | (r >= n);
    if (OM_ANY(missed)) {
        OmI m = i % n;
        r = OM_SEL(r, OM_SEL(m, m + n, m < 0), missed);
    }
    return r;
}

// Cell or texel i of n after an address mode: wrapped (tiling) or clamped to the edge. Every
// kernel resolves its indices here (the bilinear patch through om_patch_address below, which
// resolves a patch's two columns and rows at once).
OM_INLINE OmI om_address(OmI i, OmI n, int wrap) {
    return wrap ? om_wrap(i, n) : clamp(i, (OmI)0, n - 1);
}

// The texel columns i0, i1 = i + 1 and rows j0, j1 = j + 1 of each lane's patch (i, j) after the
// field's address mode. Resolved once per patch, not per texel: integer % costs tens of cycles on a
// CPU, and power-of-two maps need none (a mask also wraps negative indices).
OM_INLINE void om_patch_address(const OmField* f, OmI i, OmI j, OmI* i0, OmI* i1, OmI* j0,
                                OmI* j1) {
    if (f->wrap && f->pot) {
        *i0 = i & (f->width - 1);
        *i1 = (i + 1) & (f->width - 1);
        *j0 = j & (f->height - 1);
        *j1 = (j + 1) & (f->height - 1);
    } else if (f->wrap) {
        *i0 = om_wrap(i, f->width);
        *i1 = OM_SEL(*i0 + 1, 0, *i0 + 1 == f->width);
        *j0 = om_wrap(j, f->height);
        *j1 = OM_SEL(*j0 + 1, 0, *j0 + 1 == f->height);
    } else {
        *i0 = clamp(i, (OmI)0, f->width - 1);
        *i1 = clamp(i + 1, (OmI)0, f->width - 1);
        *j0 = clamp(j, (OmI)0, f->height - 1);
        *j1 = clamp(j + 1, (OmI)0, f->height - 1);
    }
}

// One stored texel (i, j) per lane, after the address mode.
OM_INLINE OmF om_texel(const OmField* f, OmI i, OmI j OM_IMG_PARAM) {
    OmI i0, i1, j0, j1;
    om_patch_address(f, i, j, &i0, &i1, &j0, &j1);
    return OM_HEIGHTS(f->heights, f->offset + j0 * f->width + i0);
}

// Words i and i + 1 of `p` per lane, as ints.
OM_INLINE void om_word_pairs(__global const uint* p, OmI i, OmI* first, OmI* second) {
#if OM_LANES == 1
    *first = (int)p[i];
    *second = (int)p[i + 1];
#elif defined(OM_PAIR_GATHER)
    OmF a, b;
    om_gather_pairs((__global const float*)p, i, &a, &b);
    *first = OM_AS_INT(a);
    *second = OM_AS_INT(b);
#else
    *first = OM_AS_INT(OM_GATHER((__global const float*)p, i));
    *second = OM_AS_INT(OM_GATHER((__global const float*)p, i + 1));
#endif
}

// The heights of a word's two unorm16 values: its texel's (low) and the one below's (high).
#define OM_UNORM16_LOW(w) (OM_TO_FLOAT((w)&0xffff) * OM_UNORM16_STEP)
#define OM_UNORM16_HIGH(w) (OM_TO_FLOAT(((w) >> 16) & 0xffff) * OM_UNORM16_STEP)

// The four corners of each lane's patch (i, j) (integer texel-centre coordinates): k00 at (i, j),
// k10 at (i + 1, j), k01, k11.
OM_INLINE void om_corners(const OmField* f, OmI i, OmI j, OmF* k00, OmF* k10, OmF* k01,
                          OmF* k11 OM_IMG_PARAM) {
    OmI i0, i1, j0, j1;
    om_patch_address(f, i, j, &i0, &i1, &j0, &j1);
    OmI r0 = f->offset + j0 * f->width, r1 = f->offset + j1 * f->width;
#ifndef OM_IMAGES
    // Unorm16 words: the patch is one pair of words (half the gathered elements of two float
    // pairs, and one cache line), unless a lane's column or row wraps or is clamped at the edge.
    // The floats beside them hold the same values, so either way gives the same bits.
    if (f->packed && OM_LIKELY(!OM_ANY_NE2(i1, i0 + 1, j1, j0 + 1))) {
        OmI w0, w1;
        om_word_pairs(f->packed, r0 + i0, &w0, &w1);
        *k00 = OM_UNORM16_LOW(w0);
        *k01 = OM_UNORM16_HIGH(w0);
        *k10 = OM_UNORM16_LOW(w1);
        *k11 = OM_UNORM16_HIGH(w1);
        return;
    }
#endif
#ifdef OM_PAIR_GATHER
    // Each row's two corners as one pair, unless a lane's row wraps or is clamped at the edge
    // (and p[i + 1] could lie past the buffer). A branch, not a lane mask on the gathers: a
    // predicted branch lets the gathers start before the test is done, a mask delays every
    // dependent fetch by its reduction. Without the hint, the code PoCL made for pom's search
    // was slower than with the mask; with it no method is slower (docs/throughput.md).
    if (OM_LIKELY(!OM_ANY_NE(i1, i0 + 1))) {
        om_gather_pairs(f->heights, r0 + i0, k00, k10);
        om_gather_pairs(f->heights, r1 + i0, k01, k11);
        return;
    }
#endif
    *k00 = OM_HEIGHTS(f->heights, r0 + i0);
    *k10 = OM_HEIGHTS(f->heights, r0 + i1);
    *k01 = OM_HEIGHTS(f->heights, r1 + i0);
    *k11 = OM_HEIGHTS(f->heights, r1 + i1);
}

// The four corners of the patch under cell coordinates (cx, cy) = (u W - 1/2, v H - 1/2) and the
// position (a, b) inside it. Coordinates beyond +-1e8 are clamped there, so the cell index stays an
// int and the address mode still sees a point far outside the map.
OM_INLINE void om_patch_cell(const OmField* f, OmF cx, OmF cy, OmF* a, OmF* b, OmF* k00, OmF* k10,
                             OmF* k01, OmF* k11 OM_IMG_PARAM) {
    cx = clamp(cx, -1.0e8f, 1.0e8f);
    cy = clamp(cy, -1.0e8f, 1.0e8f);
    OmF fx = OM_LFLOOR(cx), fy = OM_LFLOOR(cy);
    *a = cx - fx;
    *b = cy - fy;
    om_corners(f, OM_TO_INT(fx), OM_TO_INT(fy), k00, k10, k01, k11 OM_IMG_ARG);
}

// The four corners of the patch under (u, v) and the position (a, b) inside it.
OM_INLINE void om_patch(const OmField* f, OmF u, OmF v, OmF* a, OmF* b, OmF* k00, OmF* k10,
                        OmF* k01, OmF* k11 OM_IMG_PARAM) {
    om_patch_cell(f, OM_CELL(u, f->fw), OM_CELL(v, f->fh), a, b, k00, k10, k01, k11 OM_IMG_ARG);
}

// The patch's height at (a, b): each lerp one fused multiply-add (PoCL's mix is a subtraction, a
// product and a sum).
OM_INLINE OmF om_bilinear(OmF k00, OmF k10, OmF k01, OmF k11, OmF a, OmF b) {
    OmF top = OM_FMA(k10 - k00, a, k00), bottom = OM_FMA(k11 - k01, a, k01);
    return OM_FMA(bottom - top, b, top);
}

// Bilinear height in [0, 1] per lane at cell coordinates (om_patch_cell).
OM_INLINE OmF om_height_at_cell(const OmField* f, OmF cx, OmF cy OM_IMG_PARAM) {
    OmF a, b, k00, k10, k01, k11;
    om_patch_cell(f, cx, cy, &a, &b, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    return om_bilinear(k00, k10, k01, k11, a, b);
}

// Bilinear height H(u, v) in [0, 1] per lane.
OM_INLINE OmF om_height_at(const OmField* f, OmF u, OmF v OM_IMG_PARAM) {
    return om_height_at_cell(f, OM_CELL(u, f->fw), OM_CELL(v, f->fh) OM_IMG_ARG);
}

// The same, counting one fetch in the lanes of `active` (the methods' cost measure).
OM_INLINE OmF om_height(const OmField* f, OmF u, OmF v, OmI active, OmI* fetches OM_IMG_PARAM) {
    *fetches += OM_ONE(active);
    return om_height_at(f, u, v OM_IMG_ARG);
}

// The same at cell coordinates: a search whose samples are evenly spaced along the ray steps them
// there, one multiply-add per axis and sample (pom 0.93-0.97 of the time, both targets).
OM_INLINE OmF om_height_cell(const OmField* f, OmF cx, OmF cy, OmI active,
                             OmI* fetches OM_IMG_PARAM) {
    *fetches += OM_ONE(active);
    return om_height_at_cell(f, cx, cy OM_IMG_ARG);
}

// Bilinear height and its exact gradient (dH/du, dH/dv) on the patch: the gradient of the bilinear
// surface itself, so slope methods follow the same relief that `exact` intersects.
OM_INLINE OmF om_height_grad(const OmField* f, OmF u, OmF v, OmI active, OmI* fetches, OmF* gu,
                             OmF* gv OM_IMG_PARAM) {
    OmF a, b, k00, k10, k01, k11;
    om_patch(f, u, v, &a, &b, &k00, &k10, &k01, &k11 OM_IMG_ARG);
    *fetches += OM_ONE(active);
    *gu = mix(k10 - k00, k11 - k01, b) * f->fw;
    *gv = mix(k01 - k00, k11 - k10, a) * f->fh;
    return om_bilinear(k00, k10, k01, k11, a, b);
}
