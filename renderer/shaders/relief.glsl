// The classic methods in GLSL, as a forward renderer runs them in its G-buffer fragment shader:
// parallax, steep, relief and pom, in the project's conventions (docs/design.md): H in [0,1]
// bilinear between texel centres (the height texture's GL_LINEAR, level 0, GL_REPEAT or
// GL_CLAMP_TO_EDGE), p(t) = uv - t V.xy entering at the top plane z = s (1 - r) and leaving at
// z = -s r, the grazing rule of the kernels (V.z raised to u_min_vz, or Welsh's limit). Each method
// is its kernel's search step for step (kernels/methods), with the same step counts. Over a
// curved base (om_offset's curvature, docs/design.md "Curved surfaces") the ray is the kernels'
// curved one (kernels/common/ray.cl, om_ray_curve and om_curve_point) and a ray that leaves the
// slab through its top before a hit sets om_silhouette (the kernels' SILHOUETTE); with the uv
// metric (docs/design.md, "The uv metric") its footprint and depth factor are the kernels' too.
uniform sampler2D u_heights;
uniform int u_method;  // OM_GLSL_<row's glsl>: the renderer defines them from the registry
uniform vec4 u_params;  // the method's parameters in its registry order
uniform float u_scale;
uniform float u_ref;
uniform float u_min_vz;
uniform int u_limit;  // Welsh's offset limiting for every view
uniform int u_tile_mask;     // the tile mask: uv' outside the tile is not this surface's
uniform vec4 u_tile_bounds;  // the tile: u_min, v_min, u_max, v_max

int om_fetches = 0;
bool om_silhouette = false;

float om_height(vec2 p) {
    ++om_fetches;
    return textureLod(u_heights, p, 0.0).r;
}

struct OmRay {
    vec2 uv;
    vec3 v;
    float t_enter, t_exit;
    // Over a curved base: the normal curvature kn along e = -V.xy / |V.xy| and the cross term kc,
    // |V.xy|, the uv's stretch as su = 1 / a and sv = a, and whether the ray leaves through the top.
    bool curved, exits_top;
    float kn, kc, lxy, su, sv;
    vec2 e;
    // The uv metric's footprint l m + side n + l^2 g and the density's log rate d (om_ray_metric).
    bool metric;
    vec2 m, n, g, d;
};

// The uv metric at the fragment: (dP/du.T, dP/du.B, dP/dv.T, dP/dv.B) over the uv density, and
// the Christoffel symbols Gamma^u and Gamma^v (uu, uv, vv); zeros: none.
struct OmMetric {
    vec4 j;
    vec3 gu, gv;
};

// The kernels' om_metric_usable.
bool om_metric_usable(OmMetric mt) {
    float det = mt.j.x * mt.j.w - mt.j.z * mt.j.y, norm = dot(mt.j, mt.j);
    float g = mt.gu.x + mt.gu.y + mt.gu.z + mt.gv.x + mt.gv.y + mt.gv.z;
    return !isnan(det) && !isinf(det) && !isnan(norm) && !isinf(norm) && !isnan(g) && !isinf(g) &&
           det > 1.0e-6 * norm;
}

// The kernels' om_ray_metric, for a usable metric (r.e set).
void om_ray_metric(inout OmRay r, OmMetric mt) {
    float inv = 1.0 / (mt.j.x * mt.j.w - mt.j.z * mt.j.y);
    float a00 = mt.j.w * inv, a01 = -mt.j.z * inv, a10 = -mt.j.y * inv, a11 = mt.j.x * inv;
    r.m = vec2(a00 * r.e.x + a01 * r.e.y, a10 * r.e.x + a11 * r.e.y);
    r.n = vec2(a01 * r.e.x - a00 * r.e.y, a11 * r.e.x - a10 * r.e.y);
    vec3 q = vec3(r.m.x * r.m.x, 2.0 * r.m.x * r.m.y, r.m.y * r.m.y);
    r.g = -0.5 * vec2(dot(mt.gu, q), dot(mt.gv, q));
    r.d = 0.5 * vec2(mt.gu.x + mt.gv.y, mt.gu.y + mt.gv.z);
}

float om_ray_t(OmRay r, float lambda) { return r.t_enter + lambda * (r.t_exit - r.t_enter); }

// The kernels' om_ray_curve: K = (k_uu, k_uv, k_vv) and the stretch in k.w, and the uv metric.
void om_ray_curve(inout OmRay r, vec4 k, OmMetric mt) {
    float a = (!(k.w > 0.0) || isinf(k.w)) ? 1.0 : k.w;
    bool finite = !any(isnan(k.xyz)) && !any(isinf(k.xyz));
    r.metric = om_metric_usable(mt);
    // The kernels' om_metric_bends: a Jacobian beyond 2^-12 of the identity.
    bool bends = any(greaterThan(abs(mt.j - vec4(1.0, 0.0, 0.0, 1.0)), vec4(1.0 / 4096.0)));
    r.curved = u_scale > 0.0 && finite &&
               (k.x != 0.0 || k.y != 0.0 || k.z != 0.0 || a != 1.0 || (r.metric && bends));
    if (!r.curved) return;
    float lxy = sqrt(r.v.x * r.v.x + r.v.y * r.v.y);
    bool plumb = !(lxy > 0.0);
    r.e = plumb ? vec2(1.0, 0.0) : -r.v.xy / lxy;
    float kx = k.x * r.e.x + k.y * r.e.y, ky = k.y * r.e.x + k.z * r.e.y;
    float k_max = 0.5 / u_scale;
    r.kn = clamp(r.e.x * kx + r.e.y * ky, -k_max, k_max);
    r.kc = r.e.x * ky - r.e.y * kx;
    r.lxy = plumb ? 0.0 : lxy;
    r.su = 1.0 / a;
    r.sv = a;
    if (r.metric) om_ray_metric(r, mt);
    float top = u_scale * (1.0 - u_ref), bottom = -u_scale * u_ref;
    float vz = r.v.z, kn = r.kn;
    float c_top = top * (2.0 + kn * top), c_bottom = bottom * (2.0 + kn * bottom);
    float q_top = vz + sqrt(max(vz * vz + kn * c_top, 0.0));
    float d_bottom = vz * vz + kn * c_bottom;
    r.exits_top = d_bottom < 0.0;
    float t_bottom = -c_bottom / (vz + sqrt(max(d_bottom, 0.0)));
    r.t_enter = -c_top / q_top;
    r.t_exit = r.exits_top ? q_top / kn : t_bottom;
}

// The curved ray's point at t: its footprint's offset from the pixel in uv (xy) and its height
// above the base (z), the kernels' om_curve_point and om_curve_offset.
vec3 om_curve_at(OmRay r, float t) {
    float a = t * r.lxy, z = -t * r.v.z;
    float c = 1.0 + r.kn * z, ka = r.kn * a;
    float q = sqrt(c * c + ka * ka);
    float h = (2.0 * z + r.kn * (t * t)) / (q + 1.0);
    float arc = ka == 0.0 ? a : a * (atan(ka, c) / ka);
    float side = -h * r.kc * arc;
    if (!r.metric)
        return vec3((arc * r.e.x - side * r.e.y) * r.su, (arc * r.e.y + side * r.e.x) * r.sv, h);
    // The metric's footprint, and the height times the reciprocal of the relief's depth factor.
    vec2 o = arc * r.m + side * r.n + (arc * arc) * r.g;
    return vec3(o, h * clamp(1.0 - dot(r.d, o), 0.25, 4.0));
}

// uv' of a hit at t.
vec2 om_footprint(OmRay r, float t) {
    return r.curved ? r.uv + om_curve_at(r, t).xy : r.uv - t * r.v.xy;
}

// The ray's height at lambda in the heights' units (H >= it: at or below the relief), and its
// footprint there, for the curved ray.
float om_curve_sample(OmRay r, float lambda, out vec2 p) {
    vec3 c = om_curve_at(r, om_ray_t(r, lambda));
    p = r.uv + c.xy;
    return c.z / u_scale + u_ref;
}

int om_step_count(float n) { return max(1, int(n + 0.5)); }

// The first sample i in 0..n at or below the relief, with the heights at i - 1 (1 at i = 0)
// and i, and the ray's there (1 - lambda flat); over a curved base a ray that reaches n without
// meeting the relief has left through the top (om_silhouette).
int om_linear_search(OmRay r, int n, out float h_prev, out float h_cur, out float eta_prev,
                     out float eta_cur) {
    float hp = 1.0, ep = 1.0, inv_n = 1.0 / float(n);
    // Sample i at uv0 + i duv: the top plane's point, then steps of (t_exit - t_enter) / n.
    vec2 uv0 = r.uv - r.t_enter * r.v.xy, duv = -(r.t_exit - r.t_enter) * inv_n * r.v.xy;
    for (int i = 0;; ++i) {
        float lambda = float(i) * inv_n, eta = 1.0 - lambda;
        vec2 p = fma(vec2(float(i)), duv, uv0);
        if (r.curved) eta = om_curve_sample(r, lambda, p);
        float h = om_height(p);
        bool below = h >= eta;
        if (below || i >= n) {
            h_prev = hp;
            h_cur = h;
            eta_prev = ep;
            eta_cur = eta;
            om_silhouette = r.curved && !below;
            return i;
        }
        hp = h;
        ep = eta;
    }
}

float om_trace(OmRay r) {
    float h_prev, h_cur, eta0, eta1;
    // parallax: the relief taken flat at the height read at the entry point; over a curved base
    // the ray meets that level's circle, or leaves through the top short of it (kernels'
    // methods/parallax.cl).
    if (u_method == OM_GLSL_PARALLAX) {
        float h = om_height(r.uv);
        if (!r.curved) return -u_scale * (h - u_ref) / r.v.z;
        float d = u_scale * (h - u_ref), c = d * (2.0 + r.kn * d);
        float disc = r.v.z * r.v.z + r.kn * c;
        bool short_of = disc < 0.0, away = short_of && r.kn > 0.0;
        om_silhouette = away;
        if (away) return r.t_exit;
        if (short_of) return clamp(r.v.z / r.kn, r.t_enter, r.t_exit);
        return -c / (r.v.z + sqrt(max(disc, 0.0)));
    }
    if (u_method == OM_GLSL_STEEP) {
        int n = om_step_count(u_params.x);
        int i = om_linear_search(r, n, h_prev, h_cur, eta0, eta1);
        return om_ray_t(r, float(i) / float(n));
    }
    if (u_method == OM_GLSL_RELIEF) {
        int n = om_step_count(u_params.x);
        int i = om_linear_search(r, n, h_prev, h_cur, eta0, eta1);
        float fn = float(n), hi = float(i) / fn, lo = i > 0 ? float(i - 1) / fn : 0.0;
        for (int k = 0; i > 0 && !om_silhouette && k < int(u_params.y); ++k) {
            float mid = 0.5 * (lo + hi);
            float tm = om_ray_t(r, mid);
            vec2 p = r.uv - tm * r.v.xy;
            float eta = 1.0 - mid;
            if (r.curved) eta = om_curve_sample(r, mid, p);
            bool below = om_height(p) >= eta;
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
    int i = om_linear_search(r, n, h_prev, h_cur, eta0, eta1);
    float fn = float(n), l0 = float(i - 1) / fn, l1 = float(i) / fn;
    if (!r.curved) {
        eta0 = 1.0 - l0;
        eta1 = 1.0 - l1;
    }
    float d0 = h_prev - eta0, d1 = h_cur - eta1;
    if (om_silhouette) return om_ray_t(r, 1.0);
    return om_ray_t(r, i > 0 ? l0 + (l1 - l0) * (d0 / (d0 - d1)) : 0.0);
}

// uv', t and the fetch count for a pixel at uv seen along tangent-space V over a base of
// curvature k (k_uu, k_uv, k_vv in uv units, and the uv's stretch; (0, 0, 0, 1): the plane) and uv
// metric mt (zeros: none); uv passes through (t 0) where V is not finite, zero or faces away, as
// the kernels flag such pixels.
vec4 om_offset(vec2 uv, vec3 view, vec4 k, OmMetric mt) {
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
    r.curved = false;
    r.metric = false;
    om_ray_curve(r, k, mt);
    float t = om_trace(r);
    return vec4(om_footprint(r, t), t, float(om_fetches));
}

// The kernels' OUT_OF_TILE test (kernels/offset.cl).
bool om_out_of_tile(vec2 uv) {
    return u_tile_mask != 0 && (any(lessThan(uv, u_tile_bounds.xy)) ||
                                any(greaterThan(uv, u_tile_bounds.zw)));
}
