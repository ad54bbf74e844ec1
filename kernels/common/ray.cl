// The eye ray in tangent space: p(t) = (u, v, 0) - t * V. It enters the relief at the top plane
// z = s (1 - r) and leaves it at the bottom z = -s r (DESIGN.md, "The ray").
typedef struct {
    float2 uv;      // start point in the local frame (wrap: fractional part of the G-buffer uv)
    float3 v;       // unit view vector, toward the eye, V.z >= min_vz
    float scale;    // s
    float ref;      // r
    float t_enter;  // ray parameter at the top plane (negative when r < 1)
    float t_exit;   // ray parameter at the bottom plane
    float detail;   // LOD step-count factor in (0, 1]: 1 near the viewer
    int step_cap;   // LOD footprint mode: no more steps than the texels the ray crosses
} OmRay;

// A method's step count under LOD: scaled by the detail factor, capped, at least 1.
inline int om_lod_count(const OmRay* r, float n) {
    return max(1, min((int)(n * r->detail + 0.5f), r->step_cap));
}

// Height of the relief surface at H, in the ray's z units.
inline float om_surface_z(const OmRay* r, float h) { return r->scale * (h - r->ref); }

inline float2 om_ray_uv(const OmRay* r, float t) { return r->uv - t * r->v.xy; }

// Marching methods parametrise the slab by lambda in [0,1]: lambda = 0 at the top plane (ray height
// H = 1), 1 at the bottom plane (H = 0); the ray is below the relief where H(uv) >= 1 - lambda.
inline float om_ray_t(const OmRay* r, float lambda) {
    return r->t_enter + lambda * (r->t_exit - r->t_enter);
}

// Validates one G-buffer pixel and builds its ray. Returns flags; a pixel with EMPTY, INVALID or
// BACKFACING set is passed through unchanged by the caller.
// Grazing rule (clamp and cap policies): V.z is raised to min_vz and V.xy rescaled to keep |V| = 1
// and the azimuth, so every march spans at most s / min_vz in uv and every loop count is bounded;
// the cap policy only raises min_vz (host side). The limit policy replaces V by normalize(V.xy, 1).
// Views below min_vz are flagged GRAZING under every policy.
inline uint om_setup_ray(float2 uv, float4 v4, const OmOffsetParams* P, OmRay* r, float2* base) {
    if (isnan(uv.x) || isnan(uv.y)) return OM_FLAG_EMPTY;
    float3 v = v4.xyz;
    if (!isfinite(uv.x) || !isfinite(uv.y) || !isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z))
        return OM_FLAG_INVALID;
    // Scale by the largest component first so |V| neither overflows nor underflows.
    float m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (!(m > 0.0f)) return OM_FLAG_INVALID;
    v /= m;  // not * (1 / m): the reciprocal of a denormal overflows
    float len = sqrt(v.x * v.x + v.y * v.y + v.z * v.z);  // in [1, sqrt 3]; as lane_ray.cl
    uint flags = 0u;
    if (fabs(len * m - 1.0f) > 1.0e-3f) flags |= OM_FLAG_RENORMALIZED;
    v *= 1.0f / len;
    if (!(v.z > 0.0f)) return flags | OM_FLAG_BACKFACING;
    if (v.z < P->min_vz) flags |= OM_FLAG_GRAZING;
    if (P->grazing_limit) {
        // Welsh's offset limiting as a ray: horizontal travel per unit of depth is |V.xy|, not
        // |V.xy| / V.z, so no offset exceeds the depth it crosses; biased at every angle but 90.
        v = OM_F3(v.x, v.y, 1.0f) * rsqrt(v.x * v.x + v.y * v.y + 1.0f);
    } else if (v.z < P->min_vz) {
        float lxy = sqrt(v.x * v.x + v.y * v.y);
        float k = sqrt(1.0f - P->min_vz * P->min_vz) / lxy;
        v = OM_F3(v.x * k, v.y * k, P->min_vz);
    }
    // Tracing in a local frame keeps float precision for any tile index; the offset is added back.
    *base = P->address_mode == OM_ADDRESS_WRAP ? OM_F2(om_floor(uv.x), om_floor(uv.y))
                                               : OM_F2(0.0f, 0.0f);
    r->uv = uv - *base;
    r->v = v;
    r->scale = P->scale;
    r->ref = P->ref_plane;
    float inv_vz = 1.0f / v.z;
    r->t_enter = -P->scale * (1.0f - P->ref_plane) * inv_vz;
    r->t_exit = P->scale * P->ref_plane * inv_vz;
    r->detail = 1.0f;
    r->step_cap = 0x7fffffff;
    return flags;
}
