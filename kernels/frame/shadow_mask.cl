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

// A work-item's lanes, pixels (fx = 2 x + 1) at NDC y ny and window depth d, in the map: texel
// coordinates (centres at integers) and window depth, each grid in its own conventions
// (common/unproject.cl). The expressions are the same whatever the lanes, so a pixel's point is
// the same bits at 1, 8 or 16 lanes.
OM_INLINE void om_light_points(const OmShadowMaskParams* P, OmF fx, OmF ny, OmF d, OmF* tx, OmF* ty,
                               OmF* tz, OmF* tw) {
    const OmF nx = OM_PIXEL_NDC_X(fx, P->frame.width);
    const OmF nz = OM_PIXEL_NDC_Z(P->frame, d);
    OM_UNPROJECT(OmF, P->inv_view_proj, nx, ny, nz, px, py, pz);
    const float* c = P->light_view_proj;
    const OmF cx = c[0] * px + c[4] * py + c[8] * pz + c[12];
    const OmF cy = c[1] * px + c[5] * py + c[9] * pz + c[13];
    const OmF cz = c[2] * px + c[6] * py + c[10] * pz + c[14];
    const OmF cw = c[3] * px + c[7] * py + c[11] * pz + c[15];
    // Texel row j at NDC y = row0 (1 - (2 j + 1) / H): j + 0.5 = (0.5 - 0.5 row0 y) H.
    const float half_y = -0.5f * P->map.row0_ndc_y;
    *tx = (0.5f * cx / cw + 0.5f) * (float)P->map.width - 0.5f;
    *ty = (half_y * cy / cw + 0.5f) * (float)P->map.height - 0.5f;
    *tz = P->map.ndc_depth_scale * cz / cw + P->map.ndc_depth_offset;
    *tw = cw;
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

// The lanes' taps: each point p in the map and its receiver plane's gradient (a, b) per texel;
// the lit fraction.
OM_INLINE OmF om_shadow_taps(const OmShadowMaskParams* P, __global const float* map, OmF px, OmF py,
                             OmF pz, OmF a, OmF b) {
    const OmF slack = P->slack_texels * (fabs(a) + fabs(b)) + P->slack_depth;
    const int r = P->pcf_radius;
    // A reversed map's nearer surfaces have the larger depth.
    const int nearer_is_less = P->map.far_sign > 0.0f;
    const OmI i0 = OM_TO_INT(floor(px + 0.5f)), j0 = OM_TO_INT(floor(py + 0.5f));
    OmI lit = 0;
    for (int dj = -r; dj <= r; ++dj)
        for (int di = -r; di <= r; ++di) {
            const OmI i = i0 + di, j = j0 + dj;
            // A tap outside the map is lit (nothing there casts); its read is the map's corner.
            const OmI out = (i < 0) | (j < 0) | (i >= P->map.width) | (j >= P->map.height);
            const OmF z = pz + a * (OM_TO_FLOAT(i) - px) + b * (OM_TO_FLOAT(j) - py);
            const OmF m = OM_GATHER(map, OM_SEL(j * P->map.width + i, (OmI)0, out));
            const OmI passes = nearer_is_less ? z <= m + slack : z >= m - slack;
            lit -= OM_LANES == 1 ? -(out | passes) : (out | passes);  // vector true is -1
        }
    return OM_TO_FLOAT(lit) / (float)((2 * r + 1) * (2 * r + 1));
}

// A work-item takes OM_LANES consecutive pixels of a row (lanes.h): their points and their
// neighbours' in the map as vectors, then each pixel's taps. The host launches
// ceil(width / OM_LANES) x height.
__kernel void om_shadow_mask(const OmShadowMaskParams P, __global const float* depth,
                             __global const float* map, __global float* mask) {
    const int x0 = (int)get_global_id(0) * OM_LANES, y = (int)get_global_id(1);
    const int w = P.frame.width;
    if (x0 >= w || y >= P.frame.height) return;
    // Per lane (past the row's end, its last pixel again): the pixel's, its neighbour's along x
    // and along y (side sx, sy; 0 where neither is drawn: then the pixel's own) column and depth.
    float fx[OM_LANES], fx1[OM_LANES], d0[OM_LANES], d1[OM_LANES], d2[OM_LANES], ny2[OM_LANES];
    int drawn[OM_LANES];
    float plane[OM_LANES];
    const float ny = OM_PIXEL_NDC_Y(P.frame.row0_ndc_y, y, P.frame.height);
    const float ny_lo = OM_PIXEL_NDC_Y(P.frame.row0_ndc_y, y - 1, P.frame.height);
    const float ny_hi = OM_PIXEL_NDC_Y(P.frame.row0_ndc_y, y + 1, P.frame.height);
    for (int l = 0; l < OM_LANES; ++l) {
        const int x = min(x0 + l, w - 1), k = y * w + x;
        const float d = depth[k];
        drawn[l] = OM_PIXEL_DRAWN(P.frame, d);
        const int sx = om_receiver_neighbour(&P.frame, depth, k, 1, x > 0, x + 1 < w, d);
        const int sy =
            om_receiver_neighbour(&P.frame, depth, k, w, y > 0, y + 1 < P.frame.height, d);
        plane[l] = sx != 0 && sy != 0 ? 1.0f : 0.0f;
        fx[l] = (float)(2 * x + 1);
        fx1[l] = (float)(2 * (x + sx) + 1);
        d0[l] = d;
        d1[l] = depth[k + sx];
        d2[l] = depth[k + sy * w];
        ny2[l] = sy > 0 ? ny_hi : ny_lo;
    }
    OmF px, py, pz, pw, e1x, e1y, e1z, e2x, e2y, e2z, unused;
    om_light_points(&P, OM_VLOAD(fx), (OmF)ny, OM_VLOAD(d0), &px, &py, &pz, &pw);
    om_light_points(&P, OM_VLOAD(fx1), (OmF)ny, OM_VLOAD(d1), &e1x, &e1y, &e1z, &unused);
    om_light_points(&P, OM_VLOAD(fx), OM_VLOAD(ny2), OM_VLOAD(d2), &e2x, &e2y, &e2z, &unused);
    e1x -= px, e1y -= py, e1z -= pz;
    e2x -= px, e2y -= py, e2z -= pz;
    const OmF det = e1x * e2y - e1y * e2x;
    // A plane seen edge-on by the light (its texels do not span it) keeps no gradient.
    const OmI spans = fabs(det) > 1.0e-6f * (fabs(e1x * e2y) + fabs(e1y * e2x));
    const OmF a = OM_SEL((OmF)0.0f, (e1z * e2y - e2z * e1y) / det, spans);
    const OmF b = OM_SEL((OmF)0.0f, (e2z * e1x - e1z * e2x) / det, spans);
    const OmI has_plane = OM_VLOAD(plane) != 0.0f;
    // A point the float range cannot place in texels (sky, a point at infinity), or behind a
    // perspective light (a spot's: outside its view, w <= 0), reads no texel: lit, as a tap
    // outside the map (a spot's cone darkens what lies outside its view).
    const OmI wild = !(fabs(px) < 1.0e8f) | !(fabs(py) < 1.0e8f) | !(pw > 0.0f);
    px = OM_SEL(px, (OmF)-1.0e6f, wild);
    py = OM_SEL(py, (OmF)-1.0e6f, wild);
    float lit[OM_LANES];
    OM_VSTORE(om_shadow_taps(&P, map, px, py, pz, OM_SEL((OmF)0.0f, a, has_plane),
                             OM_SEL((OmF)0.0f, b, has_plane)),
              lit);
    for (int l = 0; l < OM_LANES && x0 + l < w; ++l)
        mask[y * w + x0 + l] = drawn[l] ? lit[l] : 1.0f;  // sky: nothing to shadow
}
