// The forward methods as a full-screen pass over an explicit G-buffer (uv and tangent-space V per
// pixel, in textures): what the fragment shader pays per pixel for the method alone, with no
// geometry rasterized, the peer the bench times against the offset kernels.
#include "relief.glsl"
uniform sampler2D u_uv;    // RG32F
uniform sampler2D u_view;  // RGBA32F: tangent-space V
layout(location = 0) out vec4 o_offset;  // uv', t, fetches

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    o_offset = om_offset(texelFetch(u_uv, p, 0).xy, texelFetch(u_view, p, 0).xyz);
}
