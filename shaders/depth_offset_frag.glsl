// The pixel depth offset written back into the depth buffer: the surface point P (from the depth
// and the inverse view-projection) moved along the eye ray by the offset pass's depth t, which is
// in uv units along unit tangent-space V: t times the uv density (world units per uv unit) in
// the world, away from the eye for t > 0. Sky and pixels the pass left alone (t = 0) keep their
// depth.
uniform sampler2D u_depth;    // window depth before, GL convention
uniform sampler2D u_t;        // the offset pass's depth output (rows bottom first)
uniform sampler2D u_material; // the G-buffer's id and uv density
uniform mat4 u_inverse_view_projection;
uniform mat4 u_view_projection;
uniform vec3 u_eye;
uniform vec2 u_size;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    float d = texelFetch(u_depth, p, 0).r;
    float t = texelFetch(u_t, p, 0).r;
    float density = texelFetch(u_material, p, 0).g;
    if (d >= 1.0 || !(abs(t) > 0.0) || isinf(t)) {
        gl_FragDepth = d;
        return;
    }
    vec4 ndc = vec4(gl_FragCoord.xy / u_size * 2.0 - 1.0, 2.0 * d - 1.0, 1.0);
    vec4 w = u_inverse_view_projection * ndc;
    vec3 surface = w.xyz / w.w;
    vec3 moved = surface - t * density * normalize(u_eye - surface);
    vec4 clip = u_view_projection * vec4(moved, 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}
