// One-texel height sampling for the prep kernels and the shade pass (the methods sample in lanes:
// lane_sampling.cl, same arithmetic). Conventions (DESIGN.md): texel (i, j) has its centre at
// uv = ((i + 0.5) / W, (j + 0.5) / H); bilinear between texel centres; wrap (tiling) or clamp.

// PoCL's scalar floor() is a slow branchy routine; its builtin is a single instruction.
#ifdef OM_POCL
#define om_floor(x) __builtin_floorf(x)
#else
#define om_floor(x) floor(x)
#endif

typedef struct {
    __global const float* h;  // level 0 texels
    int w, hgt;
    int wrap;
    int pot;  // both sizes are powers of two: wrap by mask
    float fw, fh;
} OmHeightField;

inline OmHeightField om_heightfield_of(__global const float* h, int w, int hgt, int wrap) {
    OmHeightField f;
    f.h = h;
    f.w = w;
    f.hgt = hgt;
    f.wrap = wrap;
    f.pot = (w & (w - 1)) == 0 && (hgt & (hgt - 1)) == 0;
    f.fw = (float)w;
    f.fh = (float)hgt;
    return f;
}

inline OmHeightField om_heightfield(__global const float* h, const OmOffsetParams* P) {
    return om_heightfield_of(h, P->hf_width, P->hf_height, P->address_mode == OM_ADDRESS_WRAP);
}

inline int om_wrap_index(int i, int n) {
    int r = i % n;
    return r < 0 ? r + n : r;
}

// One stored texel, addressed by integer texel index with the field's address mode.
inline float om_texel(const OmHeightField* f, int i, int j) {
    if (f->wrap) {
        i = om_wrap_index(i, f->w);
        j = om_wrap_index(j, f->hgt);
    } else {
        i = clamp(i, 0, f->w - 1);
        j = clamp(j, 0, f->hgt - 1);
    }
    return f->h[j * f->w + i];
}

// Texel-space coordinate whose integer part is the patch's lower-left texel centre.
// Clamping keeps the int conversion defined for any finite input (wrap callers pass local uv).
inline float2 om_cell_coord(const OmHeightField* f, float2 uv) {
    float2 c = OM_F2(uv.x * f->fw - 0.5f, uv.y * f->fh - 0.5f);
    return clamp(c, OM_F2(-1.0e8f, -1.0e8f), OM_F2(1.0e8f, 1.0e8f));
}

// The four corners of bilinear patch (i, j): h00 at (i, j), h10 at (i+1, j), h01, h11.
// Addresses are resolved once per patch, not per texel: integer % costs tens of cycles on a CPU,
// and power-of-two maps need none (a mask also wraps negative indices).
inline float4 om_patch(const OmHeightField* f, int i, int j) {
    int i0, i1, j0, j1;
    if (f->wrap && f->pot) {
        i0 = i & (f->w - 1);
        i1 = (i + 1) & (f->w - 1);
        j0 = j & (f->hgt - 1);
        j1 = (j + 1) & (f->hgt - 1);
    } else if (f->wrap) {
        i0 = om_wrap_index(i, f->w);
        i1 = i0 + 1 == f->w ? 0 : i0 + 1;
        j0 = om_wrap_index(j, f->hgt);
        j1 = j0 + 1 == f->hgt ? 0 : j0 + 1;
    } else {
        i0 = clamp(i, 0, f->w - 1);
        i1 = clamp(i + 1, 0, f->w - 1);
        j0 = clamp(j, 0, f->hgt - 1);
        j1 = clamp(j + 1, 0, f->hgt - 1);
    }
    __global const float* r0 = f->h + j0 * f->w;
    __global const float* r1 = f->h + j1 * f->w;
    return OM_F4(r0[i0], r0[i1], r1[i0], r1[i1]);
}

// Bilinear height H(uv) in [0,1].
inline float om_height(const OmHeightField* f, float2 uv) {
    float2 c = om_cell_coord(f, uv);
    float fx = om_floor(c.x), fy = om_floor(c.y);
    float a = c.x - fx, b = c.y - fy;
    float4 k = om_patch(f, (int)fx, (int)fy);
    return mix(mix(k.x, k.y, a), mix(k.z, k.w, a), b);
}
