// The G-buffer pass's vertex stage: world-space meshes (the renderer bakes placements), so the
// only transform is the camera's.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec4 a_tangent;
layout(location = 3) in vec2 a_uv;
layout(location = 4) in float a_uv_density;
layout(location = 5) in vec3 a_curvature;  // k_TT, k_TB, k_BB in world units (1 / m)
layout(location = 6) in float a_uv_log_stretch;  // log2 sqrt(|dP/du| / |dP/dv|)
layout(location = 7) in vec3 a_dpdu;  // the uv metric (world units per uv unit)
layout(location = 8) in vec3 a_dpdv;
layout(location = 9) in vec3 a_gamma_u;  // Christoffel symbols Gamma^u_uu, _uv, _vv
layout(location = 10) in vec3 a_gamma_v;

uniform mat4 u_view_projection;

invariant gl_Position;  // the depth pre-pass and the G-buffer pass meet at GL_EQUAL

out vec3 v_position;
out vec3 v_normal;
out vec4 v_tangent;
out vec2 v_uv;
out float v_uv_density;
out vec3 v_curvature;
out float v_uv_log_stretch;
out vec3 v_dpdu;
out vec3 v_dpdv;
out vec3 v_gamma_u;
out vec3 v_gamma_v;

void main() {
    v_position = a_position;
    v_normal = a_normal;
    v_tangent = a_tangent;
    v_uv = a_uv;
    v_uv_density = a_uv_density;
    v_curvature = a_curvature;
    v_uv_log_stretch = a_uv_log_stretch;
    v_dpdu = a_dpdu;
    v_dpdv = a_dpdv;
    v_gamma_u = a_gamma_u;
    v_gamma_v = a_gamma_v;
    gl_Position = u_view_projection * vec4(a_position, 1.0);
}
