// The forward methods as a full-screen pass over an explicit G-buffer (uv and tangent-space V per
// pixel, in textures): what the fragment shader pays per pixel for the method alone, with no
// geometry rasterized, the peer the bench times against the offset kernels.
#include "relief.glsl"
uniform sampler2D u_uv;    // RG32F
uniform sampler2D u_view;  // RGBA32F: tangent-space V
uniform sampler2D u_curvature;  // RGBA32F: k_uu, k_uv, k_vv, stretch (read where u_curved)
uniform int u_curved;
// uv', t, fetches; the fetch count negative where the ray left a curved base (a silhouette)
layout(location = 0) out vec4 o_offset;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 k = u_curved != 0 ? texelFetch(u_curvature, p, 0) : vec4(0.0, 0.0, 0.0, 1.0);
    o_offset = om_offset(texelFetch(u_uv, p, 0).xy, texelFetch(u_view, p, 0).xyz, k,
                         OmMetric(vec4(0.0), vec3(0.0), vec3(0.0)));
    if (om_silhouette) o_offset.w = -o_offset.w;
}
