// The G-buffer pass's fragment stage: the engine-shaped G-buffer (world normal, tangent with its
// handedness, uv, uv derivatives per pixel step, material id and uv density). With OM_FORWARD it
// is the forward peer: the material's method traced here, in the fragment shader, as engines do
// it, and uv' (with the depth t and the fetch count) written beside the rest.
in vec3 v_position;
in vec3 v_normal;
in vec4 v_tangent;
in vec2 v_uv;
in float v_uv_density;
in vec3 v_curvature;
in float v_uv_log_stretch;
in vec3 v_dpdu;
in vec3 v_dpdv;
in vec3 v_gamma_u;
in vec3 v_gamma_v;

uniform float u_material;

layout(location = 0) out vec4 o_normal;
layout(location = 1) out vec4 o_tangent;
layout(location = 2) out vec2 o_uv;
layout(location = 3) out vec4 o_uv_derivatives;  // du/dx, dv/dx, du/dy, dv/dy (y up, GL's rows)
layout(location = 4) out vec2 o_material;         // id, uv density (world units per uv unit)
// The base surface's second fundamental form in the pixel's tangent frame, uv units (the pass's
// unit of length is one uv density): k_uu, k_uv, k_vv; and the uv's stretch sqrt(|dP/du| /
// |dP/dv|), exactly 1 where the mesh has none.
layout(location = 6) out vec4 o_curvature;
#ifdef OM_COUNT
// Counting fragments shaded: depth tested before the shader, as a driver does for a shader that
// writes no depth, so the count is what the method's cost is paid on.
layout(early_fragment_tests) in;
layout(binding = 0, offset = 0) uniform atomic_uint om_shaded;
#endif
#ifdef OM_PEEL
// The whole second layer (depth peeling): at each pixel the nearest surface behind the first
// layer's, whose depth this is (the same vertex stage, invariant, gives its own fragment the same
// depth). The layer drawn only where it is needed takes the test in a depth-only pass instead
// (peel_depth_frag.glsl).
uniform sampler2D u_front_depth;
#endif
#ifdef OM_FORWARD
#include "relief.glsl"
uniform vec3 u_eye;
uniform int u_curved;  // trace over the curved base (the curvature target's values)
uniform int u_metric;  // and with the uv metric (uv_metric_frag.glsl's values)
layout(location = 5) out vec4 o_offset;  // uv', t, fetches
// A triplanar material (docs/design.md, "Triplanar relief"): world_scale, sharpness, cutoff, 1;
// zeros for the others. Its fragments trace each projection whose weight is not 0 and write the
// three axes' uv' (x's in o_offset.xy, y's and z's here; a projection of weight 0 its uv), the
// weighted t and the fetches: the frame picks them by the projections the reconstruct pass gives
// the pixel, so the shading sees one choice of projections.
uniform vec4 u_triplanar;
layout(location = 7) out vec4 o_offset_yz;

// Projection p's frame, as kernels/common/triplanar.cl's.
void om_tri_frame(int p, out vec3 t, out vec3 b, out vec3 n) {
    float s = (p & 1) != 0 ? -1.0 : 1.0;
    int a = p >> 1;
    if (a == 0) {
        t = vec3(0.0, 0.0, -s);
        b = vec3(0.0, 1.0, 0.0);
        n = vec3(s, 0.0, 0.0);
    } else if (a == 1) {
        t = vec3(1.0, 0.0, 0.0);
        b = vec3(0.0, 0.0, -s);
        n = vec3(0.0, s, 0.0);
    } else {
        t = vec3(s, 0.0, 0.0);
        b = vec3(0.0, 1.0, 0.0);
        n = vec3(0.0, 0.0, s);
    }
}

vec3 om_tri_weights(vec3 n, float k, float cutoff) {
    vec3 a = pow(abs(n), vec3(k));
    a /= a.x + a.y + a.z;
    a = max(a - cutoff, 0.0);
    return a / (a.x + a.y + a.z);
}
#endif

void main() {
#ifdef OM_PEEL
    if (gl_FragCoord.z <= texelFetch(u_front_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
#endif
#ifdef OM_COUNT
    atomicCounterIncrement(om_shaded);
#endif
    vec3 n = normalize(v_normal);
    float handedness = v_tangent.w < 0.0 ? -1.0 : 1.0;
    o_normal = vec4(n, 0.0);
    o_tangent = vec4(v_tangent.xyz, handedness);
    o_uv = v_uv;
    o_uv_derivatives = vec4(dFdx(v_uv), dFdy(v_uv));
    o_material = vec2(u_material, v_uv_density);
    o_curvature = vec4(v_curvature * v_uv_density,
                       v_uv_log_stretch == 0.0 ? 1.0 : exp2(v_uv_log_stretch));
#ifdef OM_FORWARD
    // Tangent-space V as the reconstruct pass builds it: the tangent made orthogonal to the
    // normal, B = h N x T, V = (V.T, V.B, V.N).
    vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));
    vec3 b = handedness * cross(n, t);
    vec3 view = normalize(u_eye - v_position);
    vec3 tv = vec3(dot(view, t), dot(view, b), dot(view, n));
    vec4 k = u_curved != 0 ? o_curvature : vec4(0.0, 0.0, 0.0, 1.0);
    OmMetric mt = OmMetric(vec4(0.0), vec3(0.0), vec3(0.0));
    if (u_curved != 0 && u_metric != 0)  // as uv_metric_frag.glsl writes it
        mt = OmMetric(vec4(dot(v_dpdu, t), dot(v_dpdu, b), dot(v_dpdv, t), dot(v_dpdv, b)) /
                          v_uv_density,
                      v_gamma_u, v_gamma_v);
    o_offset_yz = vec4(0.0);
    if (u_material == 0.0 || u_triplanar.w == 0.0) {
        o_offset = u_material == 0.0 ? vec4(v_uv, 0.0, 0.0) : om_offset(v_uv, tv, k, mt);
    } else {
        vec3 w = om_tri_weights(n, u_triplanar.y, u_triplanar.z);
        vec2 uvs[3];
        float t_sum = 0.0;
        for (int a = 0; a < 3; ++a) {
            vec3 pt, pb, pn;
            om_tri_frame(2 * a + (n[a] < 0.0 ? 1 : 0), pt, pb, pn);
            vec2 uvp = u_triplanar.x * vec2(dot(v_position, pt), dot(v_position, pb));
            vec4 o = vec4(uvp, 0.0, 0.0);
            float scale = 1.0;
            if (w[a] > 0.0) {
                // The ray over the surface (om_tri_over_surface): uv moves by the step's T and B
                // components less its normal share; as it was where n is the axis. Its t times
                // 1 / the sheared length is t along the world ray.
                vec3 pv = vec3(dot(view, pt), dot(view, pb), dot(view, pn));
                float nt = dot(n, pt), nb = dot(n, pb), d = dot(view, n);
                if (nt != 0.0 || nb != 0.0) {
                    vec3 r = vec3(pv.x - d * nt, pv.y - d * nb, d);
                    scale = 1.0 / length(r);
                    pv = r * scale;
                }
                o = om_offset(uvp, pv, vec4(0.0, 0.0, 0.0, 1.0),
                              OmMetric(vec4(0.0), vec3(0.0), vec3(0.0)));
            }
            uvs[a] = o.xy;
            t_sum += w[a] * o.z * scale;
        }
        o_offset = vec4(uvs[0], t_sum, float(om_fetches));
        o_offset_yz = vec4(uvs[1], uvs[2]);
    }
    // The forward renderer's silhouette (the tile mask's, or a ray that left the curved base):
    // the fragment is dropped and whatever lies behind it stays (drawn before or after), which
    // a one-layer G-buffer cannot show (the deferred frame's second layer does). After a depth
    // pre-pass nothing behind is drawn, so the pixel is left empty, as the one-layer deferred
    // frame's is.
    if (u_material != 0.0 && (om_out_of_tile(o_offset.xy) || om_silhouette)) discard;
#endif
}
