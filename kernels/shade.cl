// Shading pass: Blinn-Phong at the displaced uv' with the relief normal map and an albedo map (or a
// neutral procedural checker). It does not know which method produced uv'.

OM_INLINE float4 om_fetch4(__global const float4* img, int w, int h, int wrap, int i, int j) {
    return img[om_address(j, h, wrap) * w + om_address(i, w, wrap)];
}

// Bilinear, texel centres at (i + 0.5) / W as for heights.
OM_INLINE float4 om_sample4(__global const float4* img, int w, int h, int wrap, float2 uv) {
    if (wrap) uv -= floor(uv);
    float2 c =
        clamp((float2)(uv.x * w - 0.5f, uv.y * h - 0.5f), (float2)(-1.0e8f), (float2)(1.0e8f));
    float fx = om_floor(c.x), fy = om_floor(c.y);
    int i = (int)fx, j = (int)fy;
    float a = c.x - fx, b = c.y - fy;
    float4 k00 = om_fetch4(img, w, h, wrap, i, j), k10 = om_fetch4(img, w, h, wrap, i + 1, j);
    float4 k01 = om_fetch4(img, w, h, wrap, i, j + 1),
           k11 = om_fetch4(img, w, h, wrap, i + 1, j + 1);
    return mix(mix(k00, k10, a), mix(k01, k11, a), b);
}

// Two greys, 8 x 8 squares per tile: shows the texture shift without suggesting any relief.
OM_INLINE float3 om_checker(float2 uv) {
    float2 cell = floor(uv * 8.0f);
    float odd = fmod(fabs(cell.x + cell.y), 2.0f);
    return odd > 0.5f ? (float3)(0.80f, 0.78f, 0.74f) : (float3)(0.52f, 0.54f, 0.58f);
}

OM_INLINE float3 om_unit_or(float3 v, float3 fallback) {
    float l = length(v);
    return (isfinite(l) && l > 0.0f) ? v / l : fallback;
}

// Visibility of the light from the relief point above uv (height H0 = H(uv)): 1 lit, 0 shadowed.
// n samples march from the point toward L.xy up to the top plane (McGuire's shadow loop, with L
// pointing toward the light, so the march runs along +L.xy). A sample at fraction f of the way
// sees the relief at height H; its blocker angle above the horizon, seen from the point, is
// atan(s (H - H0) / (f |D|)), where D is the uv travel; the light is at elevation alpha. hard:
// shadowed if any blocker angle exceeds alpha; D reaches the top plane along L. soft (Tatarchuk's
// blocker-distance weighting made geometric): a light of angular diameter light_size is seen half
// when the worst blocker angle equals alpha, so visibility = clamp(1/2 - (worst - alpha) /
// light_size, 0, 1): near blockers subtend large angles (sharp penumbra), far ones small. A blocker
// below alpha still hides the light's lower part, so D reaches the top plane along the light's
// lowest ray (elevation alpha - light_size / 2): a march that stopped along L would cut the
// penumbra's lit half off wherever the relief reaches the top plane. The light's march obeys the
// view's grazing rule (the host's GrazingRule): raised to min_vz (clamp, cap), or along
// normalize(L.xy, 1) under offset limiting, so the march is bounded and sees the relief the view
// rays see.
OM_INLINE float om_light_visibility(const OmField* f, float2 uv, float3 l, const OmShadeParams* P) {
    float h0 = om_height_at(f, uv.x, uv.y);
    if (h0 >= 1.0f || P->scale <= 0.0f) return 1.0f;
    float lxy = length(l.xy);
    float lz = l.z;
    if (P->grazing == OM_GRAZING_LIMIT) {
        float k = rsqrt(lxy * lxy + 1.0f);
        lxy *= k;
        lz = k;
    } else if (lz < P->min_vz) {
        lz = P->min_vz;
        lxy = sqrt(1.0f - lz * lz);
    }
    if (lxy <= 1.0e-6f) return 1.0f;  // light straight above: nothing rises above it
    float2 dir = l.xy / length(l.xy);
    float alpha = atan2(lz, lxy);
    float lowest = alpha;
    if (P->shadow_mode == OM_SHADOW_SOFT)
        lowest = fmax(alpha - 0.5f * P->light_size, asin(P->min_vz));
    float run = (1.0f - h0) * P->scale / tan(lowest);  // uv distance to the top plane
    float worst = -M_PI_F;
    int n = max(P->shadow_steps, 1);
    for (int i = 1; i <= n; ++i) {
        float frac = (float)i / (float)n;
        float2 p = uv + frac * run * dir;
        float h = om_height_at(f, p.x, p.y);
        worst = fmax(worst, atan2(P->scale * (h - h0), frac * run));
        if (P->shadow_mode == OM_SHADOW_HARD && worst > alpha) return 0.0f;
    }
    if (P->shadow_mode == OM_SHADOW_HARD) return 1.0f;
    return clamp(0.5f - (worst - alpha) / fmax(P->light_size, 1.0e-4f), 0.0f, 1.0f);
}

// One pixel's colour at uv'. Without normals the surface is flat (n = z), without heights it
// casts no shadows (the material frame's id 0: no relief).
OM_INLINE float4 om_shade_pixel(const OmShadeParams* P, float2 uv, uint flags, float3 v, float3 l,
                                __global const float4* normals, __global const float* heights,
                                __global const float4* albedo) {
    if ((flags & (OM_FLAG_EMPTY | OM_FLAG_OUT_OF_TILE)) || !isfinite(uv.x) || !isfinite(uv.y))
        return (float4)(0.16f, 0.17f, 0.20f, 0.0f);  // background: no surface here
    int wrap = P->address_mode == OM_ADDRESS_WRAP;
    float3 n = (float3)(0.0f, 0.0f, 1.0f);
    if (normals) n = om_unit_or(om_sample4(normals, P->hf_width, P->hf_height, wrap, uv).xyz, n);
    float3 base = P->has_albedo
                      ? om_sample4(albedo, P->albedo_width, P->albedo_height, wrap, uv).xyz
                      : om_checker(uv);
    l = om_unit_or(l, (float3)(0.0f, 0.0f, 1.0f));
    v = om_unit_or(v, (float3)(0.0f, 0.0f, 1.0f));
    // A light below the polygon lights nothing on it, whatever the relief normal says.
    float lit = l.z > 0.0f ? 1.0f : 0.0f;
    float ndl = fmax(dot(n, l), 0.0f) * lit;
    if (ndl > 0.0f && heights && P->shadow_mode != OM_SHADOW_NONE) {
        OmField f = om_field_of(heights, P->hf_width, P->hf_height, wrap);
        ndl *= om_light_visibility(&f, uv, l, P);
    }
    float3 hv = om_unit_or(l + v, n);
    float spec = ndl > 0.0f ? pow(fmax(dot(n, hv), 0.0f), P->shininess) : 0.0f;
    float3 c = base * (P->ambient + P->diffuse * ndl) + (float3)(P->specular * spec);
    return (float4)(c, 1.0f);
}

__kernel void om_shade(const OmShadeParams P, __global const float2* uv_in,
                       __global const uint* flags_in, __global const float4* gb_view,
                       __global const float4* gb_light, __global const float4* normals,
                       __global const float* heights, __global const float4* albedo,
                       __global float4* out_rgba) {
    int id = get_global_id(0);
    if (id >= P.pixel_count) return;
    float3 l = P.has_light ? gb_light[id].xyz : (float3)(P.light_x, P.light_y, P.light_z);
    out_rgba[id] = om_shade_pixel(&P, uv_in[id], flags_in ? flags_in[id] : 0u, gb_view[id].xyz, l,
                                  normals, heights, albedo);
}

// The material frame's shading: each pixel with its material's normals, albedo and relief (the
// slot table of the offset pass's tiles); id 0 and ids without a slot flat, with frame's
// parameters F.
__kernel void om_shade_materials(const OmShadeParams F, __global const OmMaterialSlot* slots,
                                 __global const int* slot_of_id, const int id_limit,
                                 __global const float* material, __global const float2* uv_in,
                                 __global const uint* flags_in, __global const float4* gb_view,
                                 __global const float4* gb_light, __global const float4* normals,
                                 __global const float* heights, __global const float4* albedo,
                                 __global float4* out_rgba) {
    int id = get_global_id(0);
    if (id >= F.pixel_count) return;
    float m = material[id];
    int k = om_slot_of(m, id_limit, slot_of_id);
    OmShadeParams P = F;
    __global const float4* n = 0;
    __global const float* h = 0;
    __global const float4* a = 0;
    if (k >= 0) {
        __global const OmMaterialSlot* S = slots + k;
        P = S->shade;
        n = normals + S->normals_offset;
        h = heights + S->heights_offset;
        a = P.has_albedo ? albedo + S->albedo_offset : 0;
    }
    float3 l = F.has_light ? gb_light[id].xyz : (float3)(F.light_x, F.light_y, F.light_z);
    out_rgba[id] =
        om_shade_pixel(&P, uv_in[id], flags_in ? flags_in[id] : 0u, gb_view[id].xyz, l, n, h, a);
}
