// The receivers' shadow test: each pixel's point after the depth offset (so a relief's groove is
// tested at its depth) against the light's displaced shadow map, with percentage-closer filtering
// over (2 r + 1)^2 texels. Each in its own camera's conventions (depth and row order); 1 is lit, 0
// in shadow.
//
// The bias is the receiver's own plane (receiver-plane depth bias): the point p and its two
// neighbours in the frame (on the side nearer in depth, so across an outline the same surface)
// projected into the map give the plane's depth gradient (a, b) per texel, and each tap compares
// the plane's depth at the tap's texel centre, z + a (i - s) + b (j - t), with the map there. A
// planar receiver meets its own map entry exactly at every light angle; what bends within the
// taps (the relief between pixels) is allowed slack_texels of the plane's change, and the float
// rounding of the points slack_depth. A tap outside the map is lit (nothing there casts).

// Camera pixel (x, y) at window depth d in the map: texel coordinates (centres at integers) and
// window depth, each grid in its own conventions (common/unproject.cl).
float3 om_light_point(const OmShadowMaskParams* P, int x, int y, float d) {
    const float nx = OM_PIXEL_NDC_X((float)(2 * x + 1), P->frame.width);
    const float ny = OM_PIXEL_NDC_Y(P->frame.row0_ndc_y, y, P->frame.height);
    const float nz = OM_PIXEL_NDC_Z(P->frame, d);
    OM_UNPROJECT(float, P->inv_view_proj, nx, ny, nz, px, py, pz);
    const float* c = P->light_view_proj;
    const float cx = c[0] * px + c[4] * py + c[8] * pz + c[12];
    const float cy = c[1] * px + c[5] * py + c[9] * pz + c[13];
    const float cz = c[2] * px + c[6] * py + c[10] * pz + c[14];
    const float cw = c[3] * px + c[7] * py + c[11] * pz + c[15];
    // Texel row j at NDC y = row0 (1 - (2 j + 1) / H): j + 0.5 = (0.5 - 0.5 row0 y) H.
    const float half_y = -0.5f * P->map.row0_ndc_y;
    return (float3)((0.5f * cx / cw + 0.5f) * (float)P->map.width - 0.5f,
                    (half_y * cy / cw + 0.5f) * (float)P->map.height - 0.5f,
                    P->map.ndc_depth_scale * cz / cw + P->map.ndc_depth_offset);
}

// The side (+1 or -1) of the neighbour along one axis whose depth is nearer d; 0: neither is
// drawn.
int om_receiver_neighbour(const OmPixelGrid* G, __global const float* depth, int k, int step,
                          int lo_ok, int hi_ok, float d) {
    const float lo = lo_ok ? depth[k - step] : NAN, hi = hi_ok ? depth[k + step] : NAN;
    const float dl = lo_ok && OM_PIXEL_DRAWN(*G, lo) ? fabs(lo - d) : INFINITY;
    const float dh = hi_ok && OM_PIXEL_DRAWN(*G, hi) ? fabs(hi - d) : INFINITY;
    if (isinf(dl) && isinf(dh)) return 0;
    return dh <= dl ? 1 : -1;
}

// Pixel (x, y)'s lit fraction.
float om_shadow_mask_pixel(const OmShadowMaskParams* P, __global const float* depth,
                           __global const float* map, int x, int y) {
    const int k = y * P->frame.width + x;
    const float d = depth[k];
    if (!OM_PIXEL_DRAWN(P->frame, d)) return 1.0f;  // sky: nothing to shadow
    const float3 p = om_light_point(P, x, y, d);
    const int sx = om_receiver_neighbour(&P->frame, depth, k, 1, x > 0, x + 1 < P->frame.width, d);
    const int sy = om_receiver_neighbour(&P->frame, depth, k, P->frame.width, y > 0,
                                         y + 1 < P->frame.height, d);
    float a = 0.0f, b = 0.0f;
    if (sx != 0 && sy != 0) {
        const float3 e1 = om_light_point(P, x + sx, y, depth[k + sx]) - p;
        const float3 e2 = om_light_point(P, x, y + sy, depth[k + sy * P->frame.width]) - p;
        const float det = e1.x * e2.y - e1.y * e2.x;
        // A plane seen edge-on by the light (its texels do not span it) keeps no gradient.
        if (fabs(det) > 1.0e-6f * (fabs(e1.x * e2.y) + fabs(e1.y * e2.x))) {
            a = (e1.z * e2.y - e2.z * e1.y) / det;
            b = (e2.z * e1.x - e1.z * e2.x) / det;
        }
    }
    const float slack = P->slack_texels * (fabs(a) + fabs(b)) + P->slack_depth;
    const int r = P->pcf_radius;
    // A reversed map's nearer surfaces have the larger depth.
    const int nearer_is_less = P->map.far_sign > 0.0f;
    const int i0 = (int)floor(p.x + 0.5f), j0 = (int)floor(p.y + 0.5f);
    int lit = 0;
    for (int j = j0 - r; j <= j0 + r; ++j)
        for (int i = i0 - r; i <= i0 + r; ++i) {
            if (i < 0 || j < 0 || i >= P->map.width || j >= P->map.height) {
                ++lit;
                continue;
            }
            const float z = p.z + a * ((float)i - p.x) + b * ((float)j - p.y);
            const float m = map[j * P->map.width + i];
            lit += nearer_is_less ? z <= m + slack : z >= m - slack;
        }
    return (float)lit / (float)((2 * r + 1) * (2 * r + 1));
}

__kernel void om_shadow_mask(const OmShadowMaskParams P, __global const float* depth,
                             __global const float* map, __global float* mask) {
    const int x = (int)get_global_id(0), y = (int)get_global_id(1);
    if (x >= P.frame.width || y >= P.frame.height) return;
    mask[y * P.frame.width + x] = om_shadow_mask_pixel(&P, depth, map, x, y);
}
