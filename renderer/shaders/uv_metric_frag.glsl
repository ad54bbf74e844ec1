// The uv metric's draw (Raster::draw_metric): after the G-buffer, at GL_EQUAL on its depth, each
// pixel's dP/du and dP/dv in the tangent frame the reconstruct pass builds (the tangent made
// orthogonal to the normal, B = h N x T), over the uv density, and the interpolated Christoffel
// symbols: the offset pass's uv metric planes (docs/design.md, "The uv metric").
in vec3 v_normal;
in vec4 v_tangent;
in float v_uv_density;
in vec3 v_dpdu;
in vec3 v_dpdv;
in vec3 v_gamma_u;
in vec3 v_gamma_v;

layout(location = 0) out vec4 o_jacobian;  // dP/du.T, dP/du.B, dP/dv.T, dP/dv.B
layout(location = 1) out vec4 o_gamma_u;   // Gamma^u_uu, _uv, _vv, 0
layout(location = 2) out vec4 o_gamma_v;   // Gamma^v_uu, _uv, _vv, 0

void main() {
    vec3 n = normalize(v_normal);
    float handedness = v_tangent.w < 0.0 ? -1.0 : 1.0;
    vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));
    vec3 b = handedness * cross(n, t);
    float inv = 1.0 / v_uv_density;
    o_jacobian = vec4(dot(v_dpdu, t), dot(v_dpdu, b), dot(v_dpdv, t), dot(v_dpdv, b)) * inv;
    o_gamma_u = vec4(v_gamma_u, 0.0);
    o_gamma_v = vec4(v_gamma_v, 0.0);
}
