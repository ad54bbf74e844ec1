// The layer behind drawn only where the first layer needs it: one point at each such pixel's
// centre (its index in GL's rows, bottom first), on the far plane.
layout(location = 0) in uint a_pixel;
uniform int u_width;
uniform vec2 u_size;

void main() {
    vec2 p = vec2(float(a_pixel % uint(u_width)), float(a_pixel / uint(u_width))) + 0.5;
    gl_Position = vec4(2.0 * p / u_size - 1.0, 1.0, 1.0);
}
