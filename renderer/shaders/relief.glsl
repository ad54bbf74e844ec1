// The classic methods in GLSL, as a forward renderer runs them in its G-buffer fragment shader:
// parallax, steep, relief and pom, in the project's conventions (docs/design.md): H in [0,1]
// bilinear between texel centres (the height texture's GL_LINEAR, level 0, GL_REPEAT or
// GL_CLAMP_TO_EDGE), p(t) = uv - t V.xy entering at the top plane z = s (1 - r) and leaving at
// z = -s r, the grazing rule of the kernels (V.z raised to u_min_vz, or Welsh's limit). Each method
// is its kernel's search step for step (kernels/methods), with the same step counts.
uniform sampler2D u_heights;
uniform int u_method;  // OM_GLSL_<row's glsl>: the renderer defines them from the registry
uniform vec4 u_params;  // the method's parameters in its registry order
uniform float u_scale;
uniform float u_ref;
uniform float u_min_vz;
uniform int u_limit;  // Welsh's offset limiting for every view
uniform int u_tile_mask;  // the tile mask: uv' outside [0,1]^2 is not this surface's

int om_fetches = 0;

float om_height(vec2 p) {
    ++om_fetches;
    return textureLod(u_heights, p, 0.0).r;
}

struct OmRay {
    vec2 uv;
    vec3 v;
    float t_enter, t_exit;
};

float om_ray_t(OmRay r, float lambda) { return r.t_enter + lambda * (r.t_exit - r.t_enter); }

int om_step_count(float n) { return max(1, int(n + 0.5)); }

// The first sample i in 0..n at or below the relief, with the heights at i - 1 (1 at i = 0)
// and i.
int om_linear_search(OmRay r, int n, out float h_prev, out float h_cur) {
    float hp = 1.0, inv_n = 1.0 / float(n);
    // Sample i at uv0 + i duv: the top plane's point, then steps of (t_exit - t_enter) / n.
    vec2 uv0 = r.uv - r.t_enter * r.v.xy, duv = -(r.t_exit - r.t_enter) * inv_n * r.v.xy;
    for (int i = 0;; ++i) {
        float lambda = float(i) * inv_n;
        float h = om_height(fma(vec2(float(i)), duv, uv0));
        if (h >= 1.0 - lambda || i >= n) {
            h_prev = hp;
            h_cur = h;
            return i;
        }
        hp = h;
    }
}

float om_trace(OmRay r) {
    float h_prev, h_cur;
    // parallax: the relief taken flat at the height read at the entry point.
    if (u_method == OM_GLSL_PARALLAX) return -u_scale * (om_height(r.uv) - u_ref) / r.v.z;
    if (u_method == OM_GLSL_STEEP) {
        int n = om_step_count(u_params.x);
        int i = om_linear_search(r, n, h_prev, h_cur);
        return om_ray_t(r, float(i) / float(n));
    }
    if (u_method == OM_GLSL_RELIEF) {
        int n = om_step_count(u_params.x);
        int i = om_linear_search(r, n, h_prev, h_cur);
        float fn = float(n), hi = float(i) / fn, lo = i > 0 ? float(i - 1) / fn : 0.0;
        for (int k = 0; i > 0 && k < int(u_params.y); ++k) {
            float mid = 0.5 * (lo + hi);
            float tm = om_ray_t(r, mid);
            bool below = om_height(r.uv - tm * r.v.xy) >= 1.0 - mid;
            hi = below ? mid : hi;
            lo = below ? lo : mid;
        }
        return om_ray_t(r, hi);
    }
    // pom: Tatarchuk's dynamic sample count (with a spacing, one sample per that many texels the
    // ray crosses, within [n_min, n_max]), then the segment between the last two samples.
    float want = mix(u_params.y, u_params.x, r.v.z);
    if (u_params.z > 0.0) {
        vec2 size = vec2(textureSize(u_heights, 0));
        float across = (r.t_exit - r.t_enter) * length(r.v.xy * size);
        want = clamp(ceil(across / u_params.z), u_params.x, u_params.y);
    }
    int n = om_step_count(want);
    int i = om_linear_search(r, n, h_prev, h_cur);
    float fn = float(n), l0 = float(i - 1) / fn, l1 = float(i) / fn;
    float d0 = h_prev - (1.0 - l0), d1 = h_cur - (1.0 - l1);
    return om_ray_t(r, i > 0 ? l0 + (l1 - l0) * (d0 / (d0 - d1)) : 0.0);
}

// uv', t and the fetch count for a pixel at uv seen along tangent-space V; uv passes through (t
// 0) where V is not finite, zero or faces away, as the kernels flag such pixels.
vec4 om_offset(vec2 uv, vec3 view) {
    if (u_method == OM_GLSL_NONE || any(isnan(view)) || any(isinf(view))) return vec4(uv, 0.0, 0.0);
    float m = max(abs(view.x), max(abs(view.y), abs(view.z)));
    if (!(m > 0.0)) return vec4(uv, 0.0, 0.0);
    vec3 v = view / m;
    v /= length(v);
    if (!(v.z > 0.0)) return vec4(uv, 0.0, 0.0);
    if (u_limit != 0) {
        float k = inversesqrt(dot(v.xy, v.xy) + 1.0);
        v = vec3(v.xy * k, k);
    } else if (v.z < u_min_vz) {
        v.xy *= sqrt(1.0 - u_min_vz * u_min_vz) / length(v.xy);
        v.z = u_min_vz;
    }
    OmRay r;
    r.uv = uv;
    r.v = v;
    r.t_enter = -u_scale * (1.0 - u_ref) / v.z;
    r.t_exit = u_scale * u_ref / v.z;
    float t = om_trace(r);
    return vec4(uv - t * v.xy, t, float(om_fetches));
}

// The kernels' OUT_OF_TILE test (kernels/offset.cl).
bool om_out_of_tile(vec2 uv) {
    return u_tile_mask != 0 && (uv.x < 0.0 || uv.x > 1.0 || uv.y < 0.0 || uv.y > 1.0);
}
