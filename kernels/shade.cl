// Shading pass: Blinn-Phong at the displaced uv' with the relief normal map and an albedo map (or a
// neutral procedural checker). It does not know which method produced uv'.

inline float4 om_fetch4(__global const float4* img, int w, int h, int wrap, int i, int j) {
    if (wrap) {
        i = om_wrap_index(i, w);
        j = om_wrap_index(j, h);
    } else {
        i = clamp(i, 0, w - 1);
        j = clamp(j, 0, h - 1);
    }
    return img[j * w + i];
}

// Bilinear, texel centres at (i + 0.5) / W as for heights.
inline float4 om_sample4(__global const float4* img, int w, int h, int wrap, float2 uv) {
    if (wrap) uv -= floor(uv);
    float2 c = clamp((float2)(uv.x * w - 0.5f, uv.y * h - 0.5f), (float2)(-1.0e8f), (float2)(1.0e8f));
    float fx = om_floor(c.x), fy = om_floor(c.y);
    int i = (int)fx, j = (int)fy;
    float a = c.x - fx, b = c.y - fy;
    float4 k00 = om_fetch4(img, w, h, wrap, i, j), k10 = om_fetch4(img, w, h, wrap, i + 1, j);
    float4 k01 = om_fetch4(img, w, h, wrap, i, j + 1), k11 = om_fetch4(img, w, h, wrap, i + 1, j + 1);
    return mix(mix(k00, k10, a), mix(k01, k11, a), b);
}

// Two greys, 8 x 8 squares per tile: shows the texture shift without suggesting any relief.
inline float3 om_checker(float2 uv) {
    float2 cell = floor(uv * 8.0f);
    float odd = fmod(fabs(cell.x + cell.y), 2.0f);
    return odd > 0.5f ? (float3)(0.80f, 0.78f, 0.74f) : (float3)(0.52f, 0.54f, 0.58f);
}

inline float3 om_unit_or(float3 v, float3 fallback) {
    float l = length(v);
    return (isfinite(l) && l > 0.0f) ? v / l : fallback;
}

__kernel void om_shade(const OmShadeParams P, __global const float2* uv_in,
                       __global const uint* flags_in, __global const float4* gb_view,
                       __global const float4* gb_light, __global const float4* normals,
                       __global const float4* albedo, __global float4* out_rgba) {
    int id = get_global_id(0);
    if (id >= P.pixel_count) return;
    float2 uv = uv_in[id];
    uint flags = flags_in ? flags_in[id] : 0u;
    if ((flags & OM_FLAG_EMPTY) || !isfinite(uv.x) || !isfinite(uv.y)) {
        out_rgba[id] = (float4)(0.16f, 0.17f, 0.20f, 0.0f);  // background: no surface here
        return;
    }
    int wrap = P.address_mode == OM_ADDRESS_WRAP;
    float3 n = om_unit_or(om_sample4(normals, P.hf_width, P.hf_height, wrap, uv).xyz,
                          (float3)(0.0f, 0.0f, 1.0f));
    float3 base = P.has_albedo
                      ? om_sample4(albedo, P.albedo_width, P.albedo_height, wrap, uv).xyz
                      : om_checker(uv);
    float3 l = P.has_light ? gb_light[id].xyz : (float3)(P.light_x, P.light_y, P.light_z);
    l = om_unit_or(l, (float3)(0.0f, 0.0f, 1.0f));
    float3 v = om_unit_or(gb_view[id].xyz, (float3)(0.0f, 0.0f, 1.0f));
    // A light below the polygon lights nothing on it, whatever the relief normal says.
    float lit = l.z > 0.0f ? 1.0f : 0.0f;
    float ndl = fmax(dot(n, l), 0.0f) * lit;
    float3 hv = om_unit_or(l + v, n);
    float spec = ndl > 0.0f ? pow(fmax(dot(n, hv), 0.0f), P.shininess) : 0.0f;
    float3 c = base * (P.ambient + P.diffuse * ndl) + (float3)(P.specular * spec);
    out_rgba[id] = (float4)(c, 1.0f);
}
