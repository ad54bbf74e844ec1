// Height sampling shared by every method. Conventions (DESIGN.md): texel (i, j) has its centre at
// uv = ((i + 0.5) / W, (j + 0.5) / H); bilinear between texel centres; wrap (tiling) or clamp.

// PoCL's scalar floor() is a slow branchy routine; its builtin is a single instruction.
#ifdef OM_POCL
#define om_floor(x) __builtin_floorf(x)
#else
#define om_floor(x) floor(x)
#endif

typedef struct {
    __global const float* h;     // this level's texels
    __global const float* base;  // level 0 (the pyramid's start)
    int level;
    int w, hgt;
    int wrap;
    int pot;  // both sizes are powers of two: wrap by mask
    float fw, fh;
    uint fetches;               // bilinear height fetches made so far by this pixel
    __global const float* aux;  // the method's precomputed data (distance map...), or NULL
} OmHeightField;

inline OmHeightField om_heightfield_of(__global const float* h, int w, int hgt, int wrap) {
    OmHeightField f;
    f.h = h;
    f.base = h;
    f.level = 0;
    f.w = w;
    f.hgt = hgt;
    f.wrap = wrap;
    f.pot = (w & (w - 1)) == 0 && (hgt & (hgt - 1)) == 0;
    f.fw = (float)w;
    f.fh = (float)hgt;
    f.fetches = 0u;
    f.aux = 0;
    return f;
}

inline OmHeightField om_heightfield(__global const float* h, const OmOffsetParams* P) {
    return om_heightfield_of(h, P->hf_width, P->hf_height, P->address_mode == OM_ADDRESS_WRAP);
}

// A view of mip level `level` (clamped to those present) of the height pyramid. Level k is
// max(1, W >> k) x max(1, H >> k) texels, stored after level k - 1; texel centres follow the same
// convention at every level, so a level samples the same uv as level 0.
inline OmHeightField om_heightfield_level(__global const float* h, const OmOffsetParams* P,
                                          int level) {
    OmHeightField f = om_heightfield(h, P);
    level = clamp(level, 0, max(P->mip_levels - 1, 0));
    f.level = level;
    for (int k = 0; k < level; ++k) {
        f.h += f.w * f.hgt;
        f.w = max(1, f.w / 2);
        f.hgt = max(1, f.hgt / 2);
    }
    f.pot = (f.w & (f.w - 1)) == 0 && (f.hgt & (f.hgt - 1)) == 0;
    f.fw = (float)f.w;
    f.fh = (float)f.hgt;
    return f;
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

// Bilinear height H(uv) in [0,1]; counts one fetch.
inline float om_height(OmHeightField* f, float2 uv) {
    float2 c = om_cell_coord(f, uv);
    float fx = om_floor(c.x), fy = om_floor(c.y);
    float a = c.x - fx, b = c.y - fy;
    float4 k = om_patch(f, (int)fx, (int)fy);
    f->fetches += 1u;
    return mix(mix(k.x, k.y, a), mix(k.z, k.w, a), b);
}

// Bilinear height and its exact gradient (dH/du, dH/dv) on the patch at uv; counts one fetch.
// The gradient is that of the bilinear surface itself, so slope methods follow the same relief
// that `exact` intersects (a normal map is a smoothed estimate of it).
inline float om_height_grad(OmHeightField* f, float2 uv, float2* grad) {
    float2 c = om_cell_coord(f, uv);
    float fx = om_floor(c.x), fy = om_floor(c.y);
    float a = c.x - fx, b = c.y - fy;
    float4 k = om_patch(f, (int)fx, (int)fy);
    f->fetches += 1u;
    grad->x = mix(k.y - k.x, k.w - k.z, b) * f->fw;
    grad->y = mix(k.z - k.x, k.w - k.y, a) * f->fh;
    return mix(mix(k.x, k.y, a), mix(k.z, k.w, a), b);
}
