// The layer behind drawn only where the first layer needs it: one rectangle a run of such pixels
// along a row (its first pixel's index in GL's rows, bottom first, and its length), its edges on
// the pixels' edges so that it covers their centres and no other, at window depth u_depth.
layout(location = 0) in uvec2 a_run;
uniform int u_width;
uniform vec2 u_size;
uniform float u_depth;  // in normalized device coordinates: 1, the far plane; -1, 0

void main() {
    vec2 p = vec2(float(a_run.x % uint(u_width)), float(a_run.x / uint(u_width)));
    p += vec2((gl_VertexID & 1) != 0 ? float(a_run.y) : 0.0, (gl_VertexID & 2) != 0 ? 1.0 : 0.0);
    gl_Position = vec4(2.0 * p / u_size - 1.0, u_depth, 1.0);
}
