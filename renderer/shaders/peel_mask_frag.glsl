// What the G-buffer's clear writes (no surface: a NaN uv, id 0, zeros) at the pixels the layer
// behind is drawn for, whose depth the vertex stage sets to the far plane; every other pixel keeps
// a depth of 0, so the peel's fragments there fail the depth test.
layout(location = 0) out vec4 o_normal;
layout(location = 1) out vec4 o_tangent;
layout(location = 2) out vec2 o_uv;
layout(location = 4) out vec2 o_material;
layout(location = 6) out vec4 o_curvature;

void main() {
    float nan = uintBitsToFloat(0x7fc00000u);
    o_normal = vec4(0.0);
    o_tangent = vec4(0.0);
    o_uv = vec2(nan);
    o_material = vec2(0.0);
    o_curvature = vec4(0.0);
}
