// Shading pass: Blinn-Phong at the displaced uv' with the relief normal map and an albedo map (or a
// neutral procedural checker). It does not know which method produced uv'. Written over lanes
// (lanes.h) as the offset pass is: a work-item shades one block of OM_LANES pixels (blocks.cl)
// through the same sampling layer, so a CPU keeps a block's pixels in SIMD registers and a GPU
// gets one pixel a work-item from the same source.

// Bilinear xyz of a float4 image, texel centres at (i + 0.5) / W as for heights. Under wrap the
// tile index comes off uv first, as the offset pass's local frame does, so huge uv keeps its
// precision inside the tile.
OM_INLINE void om_sample3(__global const float4* img, int w, int h, int wrap, OmF u, OmF v, OmF* x,
                          OmF* y, OmF* z) {
    const OmField f = om_field_of((__global const float*)img, w, h, wrap);  // its addressing
    if (wrap) {
        u -= OM_LFLOOR(u);
        v -= OM_LFLOOR(v);
    }
    const OmF cx = clamp(OM_CELL(u, f.fw), -1.0e8f, 1.0e8f);
    const OmF cy = clamp(OM_CELL(v, f.fh), -1.0e8f, 1.0e8f);
    const OmF fx = OM_LFLOOR(cx), fy = OM_LFLOOR(cy);
    const OmF a = cx - fx, b = cy - fy;
    OmI i0, i1, j0, j1;
    om_patch_address(&f, OM_TO_INT(fx), OM_TO_INT(fy), &i0, &i1, &j0, &j1);
    const OmI p00 = 4 * (j0 * w + i0), p10 = 4 * (j0 * w + i1), p01 = 4 * (j1 * w + i0),
              p11 = 4 * (j1 * w + i1);
    __global const float* p = (__global const float*)img;
    *x = om_bilinear(OM_GATHER(p, p00), OM_GATHER(p, p10), OM_GATHER(p, p01), OM_GATHER(p, p11), a,
                     b);
    *y = om_bilinear(OM_GATHER(p, p00 + 1), OM_GATHER(p, p10 + 1), OM_GATHER(p, p01 + 1),
                     OM_GATHER(p, p11 + 1), a, b);
    *z = om_bilinear(OM_GATHER(p, p00 + 2), OM_GATHER(p, p10 + 2), OM_GATHER(p, p01 + 2),
                     OM_GATHER(p, p11 + 2), a, b);
}

// Two greys, 8 x 8 squares per tile: shows the texture shift without suggesting any relief. The
// squares' parity without fmod: t = |cell.x + cell.y| is a whole number, t - 2 floor(t / 2) its
// residue, exact (and 0 past 2^24, as fmod gives).
OM_INLINE void om_checker(OmF u, OmF v, OmF* r, OmF* g, OmF* b) {
    const OmF t = fabs(OM_LFLOOR(u * 8.0f) + OM_LFLOOR(v * 8.0f));
    const OmI odd = t - 2.0f * OM_LFLOOR(0.5f * t) > 0.5f;
    *r = OM_SEL((OmF)0.52f, (OmF)0.80f, odd);
    *g = OM_SEL((OmF)0.54f, (OmF)0.78f, odd);
    *b = OM_SEL((OmF)0.58f, (OmF)0.74f, odd);
}

// (x, y, z) made unit, or the fallback where it has no direction (zero, or not finite). Scaled by
// its largest component first, so no finite vector overflows or underflows on the way.
OM_INLINE void om_unit_or(OmF* x, OmF* y, OmF* z, OmF fx, OmF fy, OmF fz) {
    const OmF m = fmax(fabs(*x), fmax(fabs(*y), fabs(*z)));
    const OmI ok = isfinite(m) && m > 0.0f;
    const OmF s = OM_SEL((OmF)1.0f, m, ok);
    const OmF ux = *x / s, uy = *y / s, uz = *z / s;
    const OmF inv = 1.0f / sqrt(ux * ux + uy * uy + uz * uz);
    *x = OM_SEL(fx, ux * inv, ok);
    *y = OM_SEL(fy, uy * inv, ok);
    *z = OM_SEL(fz, uz * inv, ok);
}

// Visibility of the light from the relief point above (u, v) (height H0 = H(uv)): 1 lit, 0
// shadowed, for the lanes of `active` (1 elsewhere). n samples march from the point toward L.xy up
// to the top plane (McGuire's shadow loop, with L pointing toward the light, so the march runs
// along +L.xy). A sample at distance d = f |D| along the uv travel D sees the relief at height H;
// its blocker angle above the horizon, seen from the point, is atan(s (H - H0) / d); the light is
// at elevation alpha. Angles are compared as their tangents, the slopes s (H - H0) / d (atan is
// increasing), so the march takes no transcendental function. hard: shadowed if any slope
// exceeds tan(alpha); D reaches the top plane along L. soft (Tatarchuk's blocker-distance
// weighting made geometric): a light of angular diameter light_size is seen half when the worst
// blocker angle equals alpha, so visibility = clamp(1/2 - (atan(worst slope) - alpha) /
// light_size, 0, 1): near blockers subtend large angles (sharp penumbra), far ones small. A blocker
// below alpha still hides the light's lower part, so D reaches the top plane along the light's
// lowest ray (elevation alpha - light_size / 2, its tangent by the difference formula): a march
// that stopped along L would cut the penumbra's lit half off wherever the relief reaches the top
// plane. A lane stops marching once its answer is settled: hard at its first blocker, soft when
// its worst slope reaches tan(alpha + light_size / 2), where visibility is 0 (to the rounding of
// that tangent). The light's march obeys the view's grazing rule (the host's GrazingRule): raised
// to min_vz (clamp, cap), or along normalize(L.xy, 1) under offset limiting, so the march is
// bounded and sees the relief the view rays see.
OM_INLINE OmF om_light_visibility(const OmField* f, OmF u, OmF v, OmF lx, OmF ly, OmF lz,
                                  const OmShadeParams* P, OmI active) {
    const float s = P->scale;
    const OmF lxy0 = sqrt(lx * lx + ly * ly);
    OmF lxy = lxy0;
    if (P->grazing == OM_GRAZING_LIMIT) {
        const OmF k = rsqrt(lxy * lxy + 1.0f);
        lxy *= k;
        lz = k;
    } else {
        const OmI low = lz < P->min_vz;
        lz = OM_SEL(lz, (OmF)P->min_vz, low);
        lxy = OM_SEL(lxy, (OmF)sqrt(1.0f - P->min_vz * P->min_vz), low);
    }
    // Light straight above: nothing rises above it.
    OmI march = active && lxy > 1.0e-6f;
    u = OM_SEL((OmF)0.0f, u, march);
    v = OM_SEL((OmF)0.0f, v, march);
    const OmF h0 = om_height_at(f, u, v);
    march &= h0 < 1.0f;
    if (s <= 0.0f || !OM_ANY(march)) return 1.0f;
    const OmF dx = lx / OM_SEL((OmF)1.0f, lxy0, march), dy = ly / OM_SEL((OmF)1.0f, lxy0, march);
    const OmF tan_alpha = lz / OM_SEL((OmF)1.0f, lxy, march);
    const int soft = P->shadow_mode == OM_SHADOW_SOFT;
    OmF tan_lowest = tan_alpha, tan_dark = INFINITY;
    if (soft) {
        // tan(alpha -+ light_size / 2); alpha - light_size / 2 lies in (-pi / 4, pi / 2), where the
        // difference formula's denominator is positive. The lowest ray is raised to the grazing
        // rule's elevation, asin(min_vz), whose tangent is min_vz / sqrt(1 - min_vz^2).
        const float tb = tan(0.5f * P->light_size);
        const float tan_min = P->min_vz / sqrt(1.0f - P->min_vz * P->min_vz);
        tan_lowest = fmax((tan_alpha - tb) / (1.0f + tan_alpha * tb), tan_min);
        tan_dark = OM_SEL((OmF)INFINITY, (tan_alpha + tb) / (1.0f - tan_alpha * tb),
                          tan_alpha * tb < 1.0f);
    }
    const OmF run = (1.0f - h0) * s / tan_lowest;  // uv distance to the top plane
    // Sample i at cell coordinates c0 + i dc (one multiply-add an axis, as the linear search
    // steps), at distance (i / n) run; its slope s (H - H0) / d is (s / run) times the rise
    // (H - H0) n / i, so the march compares rises against thresholds scaled once.
    const int n = max(P->shadow_steps, 1);
    const OmF cx0 = OM_CELL(u, f->fw), cy0 = OM_CELL(v, f->fh);
    const OmF dcx = run * dx * f->fw / (float)n, dcy = run * dy * f->fh / (float)n;
    const OmF to_rise = run / s;
    const OmF blocking = tan_alpha * to_rise, dark = tan_dark * to_rise;
    OmF worst = -INFINITY;
    OmI blocked = 0;
    for (int i = 1; i <= n && OM_ANY(march); ++i) {
        const float fi = (float)i;
        const OmF h = om_height_at_cell(f, OM_FMA(fi, dcx, cx0), OM_FMA(fi, dcy, cy0));
        const OmF rise = (h - h0) * ((float)n / fi);
        if (soft) {
            worst = OM_SEL(worst, fmax(worst, rise), march);
            march &= worst < dark;
        } else {
            blocked |= march & (rise > blocking);
            march &= !blocked;
        }
    }
    worst = worst / to_rise;
    OmF vis;
    if (soft)
        vis =
            clamp(0.5f - (atan(worst) - atan2(lz, lxy)) / fmax(P->light_size, 1.0e-4f), 0.0f, 1.0f);
    else
        vis = OM_SEL((OmF)1.0f, (OmF)0.0f, blocked);
    return OM_SEL((OmF)1.0f, vis, active && lxy > 1.0e-6f && h0 < 1.0f);
}

// Reoriented normal mapping (Barre-Brisebois and Hill): the relief's normal d, given over a flat
// surface (z up), turned by the rotation that takes z to the base normal b. A sum or a "whiteout"
// blend adds d's slope to b's and flattens steep relief on a tilted base; the rotation keeps d's
// angle to b, and is d itself, bit for bit, where b is z. b.z > -1 (it is at least 0 here: each
// projection's axis takes the sign of the normal's component on it).
OM_INLINE void om_reorient(OmF bx, OmF by, OmF bz, OmF* dx, OmF* dy, OmF* dz) {
    const OmF tz = bz + 1.0f, ux = -*dx, uy = -*dy, uz = *dz;
    const OmF k = (bx * ux + by * uy + tz * uz) / tz;
    const OmI flat = (bx == 0.0f) & (by == 0.0f) & (bz == 1.0f);
    *dx = OM_SEL(bx * k - ux, *dx, flat);
    *dy = OM_SEL(by * k - uy, *dy, flat);
    *dz = OM_SEL(tz * k - uz, *dz, flat);
}

// A block's triplanar inputs (common/triplanar.cl): which lanes are triplanar, their projections
// (the first is the G-buffer's: its uv', V and L), weights and uv', and the world normal.
typedef struct {
    OmI on;
    OmI p[3];
    OmF w[3], u[3], v[3];
    OmF nx, ny, nz;
} OmTriShade;

// Projection j's relief normal at its uv' (the lanes' sampled normal given for j = 0), reoriented
// onto the surface's normal and expressed in the first projection's frame.
OM_INLINE void om_tri_normal(const OmTriShade* T, int j, OmF* x, OmF* y, OmF* z) {
    OmF bx, by, bz;
    om_tri_into(T->p[j], T->nx, T->ny, T->nz, &bx, &by, &bz);
    om_reorient(bx, by, bz, x, y, z);
    if (j == 0) return;
    OmF wx, wy, wz;
    om_tri_out(T->p[j], *x, *y, *z, &wx, &wy, &wz);
    om_tri_into(T->p[0], wx, wy, wz, x, y, z);
}

// The colour of the lanes of `active` at uv' (the rest get the background). Without normals the
// surface is flat (n = z), without heights it casts no shadows (the material frame's id 0: no
// relief).
// With a shadow map (has_mask), `mask` is the lit fraction its test gave the pixel; *visibility
// is what the diffuse term was scaled by.
// Triplanar lanes (T, or null) blend their projections' albedo, normals and self-shadows by their
// weights; a lane of one projection takes its own, reoriented.
OM_INLINE void om_shade_lanes(const OmShadeParams* P, OmI active, OmF u, OmF v, OmI flags, OmF vx,
                              OmF vy, OmF vz, OmF lx, OmF ly, OmF lz,
                              __global const float4* normals, __global const float* heights,
                              __global const float4* albedo, int has_mask, OmF mask, OmF cone,
                              const OmTriShade* T, OmF* r, OmF* g, OmF* b, OmF* a,
                              OmF* visibility) {
    const OmI surface = active && (flags & (int)OM_FLAGS_NOT_SHOWN) == 0 &&
                        isfinite(u) && isfinite(v);
    u = OM_SEL((OmF)0.0f, u, surface);
    v = OM_SEL((OmF)0.0f, v, surface);
    const int wrap = P->address_mode == OM_ADDRESS_WRAP;
    OmF nx = 0.0f, ny = 0.0f, nz = 1.0f;
    if (normals) {
        om_sample3(normals, P->hf_width, P->hf_height, wrap, u, v, &nx, &ny, &nz);
        om_unit_or(&nx, &ny, &nz, (OmF)0.0f, (OmF)0.0f, (OmF)1.0f);
    }
    OmF br, bg, bb;
    if (P->has_albedo)
        om_sample3(albedo, P->albedo_width, P->albedo_height, wrap, u, v, &br, &bg, &bb);
    else
        om_checker(u, v, &br, &bg, &bb);
    om_unit_or(&lx, &ly, &lz, (OmF)0.0f, (OmF)0.0f, (OmF)1.0f);
    om_unit_or(&vx, &vy, &vz, (OmF)0.0f, (OmF)0.0f, (OmF)1.0f);
    // A light below the polygon lights nothing on it, whatever the relief normal says.
    OmI facing = lz > 0.0f;
#ifdef OM_SHADE_MATERIALS
    const OmI tri = T ? T->on & surface : (OmI)0;
    OmI blended = 0;
    if (OM_ANY(tri)) {
        // Below the surface, not below the projection's plane, which the surface only leans on.
        OmF bx, by, bz;
        om_tri_into(T->p[0], T->nx, T->ny, T->nz, &bx, &by, &bz);
        facing = OM_SEL(facing, bx * lx + by * ly + bz * lz > 0.0f, tri);
        OmF x = nx, y = ny, z = nz;
        om_tri_normal(T, 0, &x, &y, &z);
        nx = OM_SEL(nx, x, tri);
        ny = OM_SEL(ny, y, tri);
        nz = OM_SEL(nz, z, tri);
        blended = tri & (T->w[0] < 1.0f);
        if (OM_ANY(blended)) {
            OmF sx = T->w[0] * nx, sy = T->w[0] * ny, sz = T->w[0] * nz;
            OmF sr = T->w[0] * br, sg = T->w[0] * bg, sb = T->w[0] * bb;
            for (int j = 1; j < 3; ++j) {
                const OmI here = blended & (T->w[j] > 0.0f);
                if (!OM_ANY(here)) continue;
                const OmF uj = OM_SEL((OmF)0.0f, T->u[j], here);
                const OmF vj = OM_SEL((OmF)0.0f, T->v[j], here);
                OmF jx = 0.0f, jy = 0.0f, jz = 1.0f, cr, cg, cb;
                if (normals) {
                    om_sample3(normals, P->hf_width, P->hf_height, wrap, uj, vj, &jx, &jy, &jz);
                    om_unit_or(&jx, &jy, &jz, (OmF)0.0f, (OmF)0.0f, (OmF)1.0f);
                }
                om_tri_normal(T, j, &jx, &jy, &jz);
                if (P->has_albedo)
                    om_sample3(albedo, P->albedo_width, P->albedo_height, wrap, uj, vj, &cr, &cg,
                               &cb);
                else
                    om_checker(uj, vj, &cr, &cg, &cb);
                const OmF w = OM_SEL((OmF)0.0f, T->w[j], here);
                sx += w * jx;
                sy += w * jy;
                sz += w * jz;
                sr += w * cr;
                sg += w * cg;
                sb += w * cb;
            }
            om_unit_or(&sx, &sy, &sz, nx, ny, nz);
            nx = OM_SEL(nx, sx, blended);
            ny = OM_SEL(ny, sy, blended);
            nz = OM_SEL(nz, sz, blended);
            br = OM_SEL(br, sr, blended);
            bg = OM_SEL(bg, sg, blended);
            bb = OM_SEL(bb, sb, blended);
        }
    }
#endif
    OmF ndl = OM_SEL((OmF)0.0f, fmax(nx * lx + ny * ly + nz * lz, 0.0f), facing);
    // The march sees the relief's own occlusion within the height field, the shadow map every
    // caster at its displaced depth, the relief's own included (docs/design.md): a blocker both
    // see darkens once, so the light reaches a pixel as far as the stricter of the two lets it.
    OmF vis = 1.0f;
    if (heights && P->shadow_mode != OM_SHADOW_NONE) {
        const OmField f = om_field_of(heights, P->hf_width, P->hf_height, wrap);
        OmF mx = lx, my = ly, mz = lz;
#ifdef OM_SHADE_MATERIALS
        // A triplanar projection marches toward the light over the surface, as its ray came.
        if (OM_ANY(tri)) {
            OmF bx, by, bz;
            om_tri_into(T->p[0], T->nx, T->ny, T->nz, &bx, &by, &bz);
            OmF unused;
            om_tri_over_surface(&mx, &my, &mz, bx * lx + by * ly + bz * lz, bx, by, &unused);
            mx = OM_SEL(lx, mx, tri);
            my = OM_SEL(ly, my, tri);
            mz = OM_SEL(lz, mz, tri);
        }
#endif
        // A projection's march needs the light above its plane; below it, it sees no blocker.
        const OmI shadowed = surface && ndl > 0.0f && mz > 0.0f;
        if (OM_ANY(shadowed)) vis = om_light_visibility(&f, u, v, mx, my, mz, P, shadowed);
#ifdef OM_SHADE_MATERIALS
        if (OM_ANY(blended)) {
            OmF sum = T->w[0] * vis;
            OmF wx, wy, wz;
            om_tri_out(T->p[0], lx, ly, lz, &wx, &wy, &wz);
            const OmF ldn = wx * T->nx + wy * T->ny + wz * T->nz;
            for (int j = 1; j < 3; ++j) {
                const OmI here = blended & (T->w[j] > 0.0f) & (ndl > 0.0f);
                OmF ljx, ljy, ljz, njx, njy, njz;
                om_tri_into(T->p[j], wx, wy, wz, &ljx, &ljy, &ljz);
                om_tri_into(T->p[j], T->nx, T->ny, T->nz, &njx, &njy, &njz);
                OmF unused;
                om_tri_over_surface(&ljx, &ljy, &ljz, ldn, njx, njy, &unused);
                const OmI march = here & (ljz > 0.0f);
                const OmF vj = OM_ANY(march) ? om_light_visibility(&f, T->u[j], T->v[j], ljx, ljy,
                                                                   ljz, P, march)
                                             : (OmF)1.0f;
                sum += OM_SEL((OmF)0.0f, T->w[j] * vj, blended & (T->w[j] > 0.0f));
            }
            vis = OM_SEL(vis, sum, blended);
        }
#endif
    }
    if (has_mask) vis = fmin(vis, mask);
    ndl *= vis;
    *visibility = OM_SEL((OmF)0.0f, OM_SEL((OmF)0.0f, vis, lz > 0.0f), surface);
    OmF hx = lx + vx, hy = ly + vy, hz = lz + vz;
    om_unit_or(&hx, &hy, &hz, nx, ny, nz);
    // (n.h)^shininess as exp2(shininess log2(n.h)): n.h is never negative here, and the general
    // pow took a fifth of the shade's time without shadows. n.h = 0 gives 0 (FLT_MIN's log2 is
    // -126), and 1 with shininess 0, as pow does.
    const OmF ndh = fmax(nx * hx + ny * hy + nz * hz, FLT_MIN);
    OmF spec = OM_SEL((OmF)0.0f, exp2(P->shininess * log2(ndh)), ndl > 0.0f);
    if (has_mask) spec *= mask;  // a map's penumbra dims the glint too
    // A spot light's cone (the light plane's w; 1 for every other light) dims both terms; the
    // others' values stay the same bits.
    const OmI coned = cone < 1.0f;
    if (OM_ANY(coned)) {
        ndl = OM_SEL(ndl, ndl * cone, coned);
        spec = OM_SEL(spec, spec * cone, coned);
    }
    const OmF lit = P->ambient + P->diffuse * ndl, glint = P->specular * spec;
    // The background: no surface here.
    *r = OM_SEL((OmF)0.16f, br * lit + glint, surface);
    *g = OM_SEL((OmF)0.17f, bg * lit + glint, surface);
    *b = OM_SEL((OmF)0.20f, bb * lit + glint, surface);
    *a = OM_SEL((OmF)0.0f, (OmF)1.0f, surface);
}

// A block's inputs: uv' and flags from the offset pass, V and L from the G-buffer (L from the
// parameters where the G-buffer has none).
typedef struct {
    OmF u, v, vx, vy, vz, lx, ly, lz, mask;
    OmF cone;  // the light's share its cone lets through (a spot's; 1 otherwise)
    OmI flags;
} OmShadeIn;

OM_INLINE OmShadeIn om_shade_in(const OmShadeParams* P, OmBlock blk, __global const float2* uv_in,
                                __global const uint* flags_in, __global const float4* gb_view,
                                __global const float4* gb_light, __global const float* mask) {
    OmShadeIn in;
    in.mask = mask ? om_load_block_f(mask, blk) : (OmF)1.0f;
    om_load_block2((__global const float*)uv_in, blk, &in.u, &in.v);
    in.flags = flags_in ? OM_AS_INT(om_load_block_f((__global const float*)flags_in, blk)) : (OmI)0;
    om_load_block3((__global const float*)gb_view, blk, &in.vx, &in.vy, &in.vz);
    in.cone = 1.0f;
    if (P->has_light) {
        OmF dark;
        om_load_block4((__global const float*)gb_light, blk, &in.lx, &in.ly, &in.lz, &dark);
        in.cone = 1.0f - dark;
    } else {
        in.lx = P->light_x;
        in.ly = P->light_y;
        in.lz = P->light_z;
    }
    return in;
}

#ifndef OM_SHADE_MATERIALS
__kernel void om_shade(const OmShadeParams P, __global const float2* uv_in,
                       __global const uint* flags_in, __global const float4* gb_view,
                       __global const float4* gb_light, __global const float4* normals,
                       __global const float* heights, __global const float4* albedo,
                       __global const float* shadow_mask, __global float4* out_rgba,
                       __global float* out_visibility) {
    const int group = (int)get_global_id(0);
    if (group >= om_image_blocks(P.gb_width, P.gb_height, OM_LANES)) return;
    const OmBlock blk = om_block(P.gb_width, P.gb_height, group);
    const OmShadeIn in = om_shade_in(&P, blk, uv_in, flags_in, gb_view, gb_light, shadow_mask);
    OmF r, g, b, a, vis;
    om_shade_lanes(&P, (OmI)(-1), in.u, in.v, in.flags, in.vx, in.vy, in.vz, in.lx, in.ly, in.lz,
                   normals, heights, albedo, shadow_mask != 0, in.mask, in.cone, 0, &r, &g, &b, &a,
                   &vis);
    om_store_block4((__global float*)out_rgba, blk, r, g, b, a);
    if (out_visibility) om_store_block_f(out_visibility, blk, vis);
}

#else
// The material frame's shading: each pixel with its material's normals, albedo and relief (the
// slot table of the offset pass's tiles); id 0 and ids without a slot flat, with the frame's
// parameters F. A block takes one pass per material it holds (most hold one), each over that
// material's lanes with its parameters and maps, so a pixel gets the bits the single-material
// shade gives it. Its own program (OM_SHADE_MATERIALS, with the triplanar blend above): the
// single-material shade carries none of it. The passes take the block's slots from the smallest
// up, a loop whose count the compiler cannot know: over an array of the lanes' slots, NIR
// (rusticl) unrolled the loop with the whole shade inlined once per lane, and took minutes to
// build the program at 16 lanes.
__kernel void om_shade_materials(const OmShadeParams F, __global const OmMaterialSlot* slots,
                                 __global const int* slot_of_id, const int id_limit,
                                 __global const float* material, __global const float2* uv_in,
                                 __global const uint* flags_in, __global const float4* gb_view,
                                 __global const float4* gb_light, __global const float4* normals,
                                 __global const float* heights, __global const float4* albedo,
                                 __global const float* shadow_mask, __global float4* out_rgba,
                                 __global float* out_visibility, __global const float4* tri_blend,
                                 __global const float2* uv2, __global const float2* uv3) {
    const int group = (int)get_global_id(0);
    if (group >= om_image_blocks(F.gb_width, F.gb_height, OM_LANES)) return;
    const OmBlock blk = om_block(F.gb_width, F.gb_height, group);
    const OmShadeIn in = om_shade_in(&F, blk, uv_in, flags_in, gb_view, gb_light, shadow_mask);
    OmTriShade tri;
    const OmTriShade* T = 0;
    if (tri_blend) {
        OmF bx, by, bz, bw;
        om_load_block4((__global const float*)tri_blend, blk, &bx, &by, &bz, &bw);
        tri.on = bx >= 0.0f;
        if (OM_ANY(tri.on)) {
            T = &tri;
            om_tri_unpack(bx, by, bz, bw, tri.p, tri.w, &tri.nx, &tri.ny, &tri.nz);
            tri.u[0] = in.u;
            tri.v[0] = in.v;
            tri.u[1] = tri.v[1] = tri.u[2] = tri.v[2] = 0.0f;
            // Most blocks hold one projection: their other planes are not read.
            if (OM_ANY(tri.on & (tri.w[1] > 0.0f)))
                om_load_block2((__global const float*)uv2, blk, &tri.u[1], &tri.v[1]);
            if (OM_ANY(tri.on & (tri.w[2] > 0.0f)))
                om_load_block2((__global const float*)uv3, blk, &tri.u[2], &tri.v[2]);
        }
    }
    float ids[OM_LANES];
    int slot[OM_LANES];
    OM_VSTORE(om_load_block_f(material, blk), ids);
    for (int k = 0; k < OM_LANES; ++k) slot[k] = om_slot_of(ids[k], id_limit, slot_of_id);
    const OmI slots_v = OM_VLOAD(slot);
    OmF r = 0.0f, g = 0.0f, b = 0.0f, a = 0.0f, vis = 0.0f;
    OmI left = (OmI)(-1);  // lanes no pass has shaded yet
    while (OM_ANY(left)) {
        const int s = OM_LANE_MIN(OM_SEL((OmI)INT_MAX, slots_v, left));
        const OmI mine = left & (slots_v == s);
        left &= !mine;
        OmShadeParams P = F;
        __global const float4* n = 0;
        __global const float* h = 0;
        __global const float4* c = 0;
        if (s >= 0) {
            __global const OmMaterialSlot* S = slots + s;
            P = S->shade;
            n = normals + S->normals_offset;
            h = heights + S->heights_offset;
            c = P.has_albedo ? albedo + S->albedo_offset : 0;
        }
        OmF pr, pg, pb, pa, pv;
        om_shade_lanes(&P, mine, in.u, in.v, in.flags, in.vx, in.vy, in.vz, in.lx, in.ly, in.lz, n,
                       h, c, shadow_mask != 0, in.mask, in.cone, T, &pr, &pg, &pb, &pa, &pv);
        r = OM_SEL(r, pr, mine);
        g = OM_SEL(g, pg, mine);
        b = OM_SEL(b, pb, mine);
        a = OM_SEL(a, pa, mine);
        vis = OM_SEL(vis, pv, mine);
    }
    om_store_block4((__global float*)out_rgba, blk, r, g, b, a);
    if (out_visibility) om_store_block_f(out_visibility, blk, vis);
}
#endif  // OM_SHADE_MATERIALS
