// The second layer's depth (depth peeling): a fragment at or before the first layer's depth is
// dropped, so the depth test keeps the nearest surface behind it. Depth only: this shader, run on
// every fragment of the box where a rasterizer gives up its early depth test for a discard, is
// the cheap one; the G-buffer is drawn after it at GL_EQUAL, with no discard.
uniform sampler2D u_front_depth;

void main() {
    if (gl_FragCoord.z <= texelFetch(u_front_depth, ivec2(gl_FragCoord.xy), 0).r) discard;
}
