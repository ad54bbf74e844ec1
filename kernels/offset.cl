// The one offset kernel entry: G-buffer load, validation, LOD, one method's om_trace, store,
// for a group of OM_LANES pixels per work-item (lanes.h), or two groups under OM_LANE_PAIRS (a
// method that also defines om_trace_pair, on lanes). A group is a block of the G-buffer image
// (OM_BLOCK_W x OM_BLOCK_H, offsetmap/shared.h); the host launches ceil(blocks / groups per work-item)
// work-items. Compiled once per method; the method file is pasted in before this file.
// aux is the method's precomputed data (NULL for most); lod is the per-pixel mip level (NULL unless
// the LOD system is on). Optional outputs (depth, fetches, flags) may be NULL buffers.
//
// LOD (Tatarchuk 2006): at mip level m the heights are read from level floor(m) of the pyramid,
// step counts are scaled by mix(1, min_detail, m / threshold) (more samples near the viewer), and
// the offset fades linearly to plain normal mapping over the `fade` levels below the threshold:
// uv' = uv + w (uv'_method - uv), w = clamp((threshold - m) / fade, 0, 1); w = 0 skips the trace.
// Footprint mode instead caps step counts at the texels (of level floor(m)) the ray's footprint
// crosses, plus one, and fades by that count over [fade_lo, fade_hi] texels: a ray that crosses
// less than a texel at the pixel's level cannot show parallax.
//
// Curvature (optional, OM_CURVED): the base's second fundamental form per pixel in uv units
// (float4: k_uu, k_uv, k_vv, the uv's stretch); lanes over a curved base trace the ray against the
// relief over that base (ray.cl, curved.cl), the rest the tangent plane, bit for bit as without
// it. The uv metric (optional beside it, OM_UV_METRIC) replaces the stretch with the uv's
// Jacobian and its rates (docs/design.md, "The uv metric").
//
// Specialised at build time (the host sets these from the pass, one program each): OM_LANES,
// OM_LANE_PAIRS, OM_IMAGES, OM_LOD when the LOD system is on, OM_CURVED when a curvature plane is
// bound (OM_UV_METRIC when a uv metric plane is too), OM_OUT_DEPTH / OM_OUT_FETCHES /
// OM_OUT_FLAGS for the optional outputs bound.

// The base's second fundamental form at each lane's pixel, in uv units (zero: the tangent plane),
// and the uv's stretch a = sqrt(|dP/du| / |dP/dv|) (1, or not above 0: none).
// With the uv metric plane (OM_UV_METRIC), the metric there too.
typedef struct {
    OmF uu, uv, vv, stretch;
#ifdef OM_UV_METRIC
    OmUvMetric m;
#endif
} OmCurvature;

// The curvature plane (float4 a pixel: k_uu, k_uv, k_vv, stretch) as lanes; zero, and nothing
// read, in a program without OM_CURVED. The uv metric plane (OM_UV_METRIC) is three float4 planes
// of `pixels` each: dP/du and dP/dv in the frame, Gamma^u (uu, uv, vv, -), Gamma^v (the same).
OM_INLINE OmCurvature om_load_curvature(__global const float4* curvature,
                                        __global const float4* uv_metric, int pixels, OmBlock b) {
    OmCurvature k;
#ifdef OM_CURVED
    om_load_block4((__global const float*)curvature, b, &k.uu, &k.uv, &k.vv, &k.stretch);
#ifdef OM_UV_METRIC
    __global const float* m = (__global const float*)uv_metric;
    const size_t plane = 4 * (size_t)pixels;
    OmF unused;
    om_load_block4(m, b, &k.m.j00, &k.m.j10, &k.m.j01, &k.m.j11);
    k.m.guu = k.m.guv = k.m.gvv = k.m.huu = k.m.huv = k.m.hvv = 0.0f;
    // A pixel on the tangent plane (no curvature, no stretch, J within 2^-12 of the identity:
    // om_metric_flat) traces the plane, its symbols unread; a block of them reads none.
    const OmI flat = om_metric_flat(k.uu, k.uv, k.vv, k.stretch, &k.m);
    if (OM_ANY(!flat)) {
        om_load_block4(m + plane, b, &k.m.guu, &k.m.guv, &k.m.gvv, &unused);
        om_load_block4(m + 2 * plane, b, &k.m.huu, &k.m.huv, &k.m.hvv, &unused);
        k.m.guu = OM_SEL(k.m.guu, (OmF)0.0f, flat);
        k.m.guv = OM_SEL(k.m.guv, (OmF)0.0f, flat);
        k.m.gvv = OM_SEL(k.m.gvv, (OmF)0.0f, flat);
        k.m.huu = OM_SEL(k.m.huu, (OmF)0.0f, flat);
        k.m.huv = OM_SEL(k.m.huv, (OmF)0.0f, flat);
        k.m.hvv = OM_SEL(k.m.hvv, (OmF)0.0f, flat);
    }
#endif
#else
    k.uu = k.uv = k.vv = k.stretch = 0.0f;
#endif
    return k;
}

// One group of lanes before and after its trace: the ray, the field at each lane's level, and
// what the entry needs to finish the pixels.
typedef struct {
    OmRay ray;
    OmField f;
    OmF base_u, base_v;  // the tile the local frame starts in
    OmF blend;           // LOD fade toward normal mapping (1 without LOD)
    OmI flags;           // the ray set-up's
    OmI rejected;        // empty, invalid, back-facing or skipped: passed through
    OmI traced;          // not rejected and not faded out: the method runs
} OmLaneGroup;

// Ray setup and LOD for one group. Lanes in `skip` are rejected as empty pixels are (no fetches;
// the caller does not store them). `m` is the lanes' mip level (read under OM_LOD only).
OM_INLINE void om_lanes_begin(const OmOffsetParams* P, OmF u, OmF v, OmF vx, OmF vy, OmF vz,
                              const OmCurvature* k, OmI skip, OmF m, __global const float* heights,
                              __global const float* aux, OmLaneGroup* g) {
    g->flags = om_ray_setup(u, v, vx, vy, vz, P, &g->ray, &g->base_u, &g->base_v);
    g->blend = 1.0f;
    OmI level = 0;
#ifdef OM_LOD
    m = OM_SEL(m, 0.0f, !isfinite(m));
    level = OM_TO_INT(clamp(m, 0.0f, 16.0f));  // truncation is floor for m >= 0
    if (P->lod_footprint) {
        OmF texels = (g->ray.t_exit - g->ray.t_enter) *
                     sqrt(g->ray.vx * g->ray.vx + g->ray.vy * g->ray.vy) *
                     fmax((float)P->hf_width, (float)P->hf_height) / OM_TO_FLOAT((OmI)1 << level);
        g->ray.step_cap = OM_TO_INT(ceil(texels)) + 1;
        g->blend =
            clamp((texels - P->lod_fade_lo) / (P->lod_fade_hi - P->lod_fade_lo), 0.0f, 1.0f);
    } else {
        g->blend = clamp((P->lod_threshold - m) / P->lod_fade, 0.0f, 1.0f);
        g->ray.detail =
            mix((OmF)1.0f, (OmF)P->lod_min_detail, clamp(m / P->lod_threshold, 0.0f, 1.0f));
    }
#endif
    g->f = om_field(heights, P, level);
    g->f.aux = aux;
    g->rejected =
        (g->flags & (int)(OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING)) != 0 || skip != 0;
    g->traced = !g->rejected && g->blend > 0.0f;
#ifdef OM_CURVED
#ifdef OM_UV_METRIC
    om_ray_curve(&g->ray, k->uu, k->uv, k->vv, k->stretch, g->traced, &k->m);
#else
    om_ray_curve(&g->ray, k->uu, k->uv, k->vv, k->stretch, g->traced);
#endif
#endif
}

// The group's outputs from the trace's t, fetches and flags. Every method returns the hit's ray
// parameter t: uv' is the ray's footprint there, and the LOD fade moves it toward normal mapping.
OM_INLINE void om_lanes_end(const OmOffsetParams* P, const OmLaneGroup* g, OmF u, OmF v, OmF t,
                            OmI fetches, OmI trace_flags, OmF* ou_out, OmF* ov_out, OmF* t_out,
                            OmI* fetches_out, OmI* flags_out) {
    const OmRay* ray = &g->ray;
    OmF hu, hv;
    om_ray_footprint(ray, t, &hu, &hv);
    hu = ray->u + g->blend * (hu - ray->u);
    hv = ray->v + g->blend * (hv - ray->v);
    OmF ou = hu + g->base_u, ov = hv + g->base_v;
    // On a non-tiling surface a ray that leaves the tile sees past the polygon's edge.
    OmI outside = P->tile_mask ? (OmI)(ou < P->tile_u0 || ou > P->tile_u1 || ov < P->tile_v0 ||
                                       ov > P->tile_v1)
                               : (OmI)0;
    OmI traced = g->traced;
    *flags_out = g->flags | OM_SEL(OM_SEL((OmI)OM_FLAG_LOD_FADED, (OmI)0, g->rejected),
                                   trace_flags | OM_SEL((OmI)0, (OmI)OM_FLAG_OUT_OF_TILE, outside),
                                   traced);
    // Rejected lanes pass their G-buffer uv through (NaN included).
    *ou_out = OM_SEL(u, ou, traced);
    *ov_out = OM_SEL(v, ov, traced);
    *t_out = OM_SEL((OmF)0.0f, t * g->blend, traced);
    *fetches_out = OM_SEL((OmI)0, fetches, traced);
}

// The lanes a method that walks cells (OM_CURVED_WALK) leaves to the curved walk: those over a
// curved base; none without curvature or for the marching methods, which bend their samples.
OM_INLINE OmI om_curved_lanes(const OmLaneGroup* g) {
#if defined(OM_CURVED) && defined(OM_CURVED_WALK)
    return g->traced & g->ray.curved;
#else
    return (OmI)0;
#endif
}

// The curved walk over those lanes, its answers merged into the method's.
OM_INLINE void om_curved_rest(const OmOffsetParams* P, const OmLaneGroup* g, OmI walked, OmF* t,
                              OmI* fetches, OmI* flags OM_IMG_PARAM) {
#if defined(OM_CURVED) && defined(OM_CURVED_WALK)
    if (OM_ANY(walked)) {
        OmI walk_fetches = 0, walk_flags = 0;
        const OmF tc = om_curved_walk(&g->ray, &g->f, P, walked, &walk_fetches,
                                      &walk_flags OM_IMG_ARG);
        *t = OM_SEL(*t, tc, walked);
        *fetches = OM_SEL(*fetches, walk_fetches, walked);
        *flags = OM_SEL(*flags, walk_flags, walked);
    }
#endif
}

// One work-item's lanes: ray setup, LOD, the method, the LOD fade. Shared by om_offset and the
// material frame's tile entry, so a pixel gets the same bits through either.
OM_INLINE void om_offset_lanes(const OmOffsetParams* P, OmF u, OmF v, OmF vx, OmF vy, OmF vz,
                               const OmCurvature* k, OmI skip, OmF m,
                               __global const float* heights, __global const float* aux,
                               OmF* ou_out, OmF* ov_out, OmF* t_out, OmI* fetches_out,
                               OmI* flags_out OM_IMG_PARAM) {
    OmLaneGroup g;
    om_lanes_begin(P, u, v, vx, vy, vz, k, skip, m, heights, aux, &g);
    OmF t = 0.0f;
    OmI fetches = 0, trace_flags = 0;
    const OmI walked = om_curved_lanes(&g);
    if (OM_ANY(g.traced & !walked))
        t = om_trace(&g.ray, &g.f, P, g.traced & !walked, &fetches, &trace_flags OM_IMG_ARG);
    om_curved_rest(P, &g, walked, &t, &fetches, &trace_flags OM_IMG_ARG);
    om_lanes_end(P, &g, u, v, t, fetches, trace_flags, ou_out, ov_out, t_out, fetches_out,
                 flags_out);
}

#ifdef OM_LANE_PAIRS
// A group's inputs (G-buffer planes, mip level, lanes to skip) and outputs, for the pair below.
typedef struct {
    OmF u, v, vx, vy, vz, m;
    OmI skip;
    OmCurvature k;
} OmLaneIn;
typedef struct {
    OmF ou, ov, t;
    OmI fetches, flags;
} OmLaneOut;

// Two groups of lanes through the method's two-group walk (om_trace_pair): each group gets the
// bits om_offset_lanes gives it alone. Shared by om_offset and the material frame's tile entry.
OM_INLINE void om_offset_lane_pair(const OmOffsetParams* P, const OmLaneIn* in_a,
                                   const OmLaneIn* in_b, __global const float* heights,
                                   __global const float* aux, OmLaneOut* out_a,
                                   OmLaneOut* out_b OM_IMG_PARAM) {
    OmLaneGroup a, b;
    om_lanes_begin(P, in_a->u, in_a->v, in_a->vx, in_a->vy, in_a->vz, &in_a->k, in_a->skip,
                   in_a->m, heights, aux, &a);
    om_lanes_begin(P, in_b->u, in_b->v, in_b->vx, in_b->vy, in_b->vz, &in_b->k, in_b->skip,
                   in_b->m, heights, aux, &b);
    OmF t_a = 0.0f, t_b = 0.0f;
    OmI fetches_a = 0, fetches_b = 0, trace_a = 0, trace_b = 0;
    const OmI walked_a = om_curved_lanes(&a), walked_b = om_curved_lanes(&b);
    const OmI plane_a = a.traced & !walked_a, plane_b = b.traced & !walked_b;
    if (OM_ANY(plane_a) || OM_ANY(plane_b))
        om_trace_pair(&a.ray, &a.f, plane_a, &b.ray, &b.f, plane_b, P, &t_a, &fetches_a, &trace_a,
                      &t_b, &fetches_b, &trace_b OM_IMG_ARG);
    om_curved_rest(P, &a, walked_a, &t_a, &fetches_a, &trace_a OM_IMG_ARG);
    om_curved_rest(P, &b, walked_b, &t_b, &fetches_b, &trace_b OM_IMG_ARG);
    om_lanes_end(P, &a, in_a->u, in_a->v, t_a, fetches_a, trace_a, &out_a->ou, &out_a->ov,
                 &out_a->t, &out_a->fetches, &out_a->flags);
    om_lanes_end(P, &b, in_b->u, in_b->v, t_b, fetches_b, trace_b, &out_b->ou, &out_b->ov,
                 &out_b->t, &out_b->fetches, &out_b->flags);
}
#endif

// Stores the lanes whose `keep` is non-zero and whose pixels lie in the block: a row of 4 at a
// time with vector stores when that is all of them.
OM_INLINE void om_store_block(__global float* out_uv, __global float* out_depth,
                              __global uint* out_fetches, __global uint* out_flags, OmBlock b,
                              OmI keep, OmF ou, OmF ov, OmF t, OmI fetches, OmI flags) {
#if OM_LANES == 1
    if (!keep || !om_block_has(b, 0)) return;
    const int id = om_block_pixel(b, 0);
    out_uv[2 * id] = ou;
    out_uv[2 * id + 1] = ov;
#ifdef OM_OUT_DEPTH
    out_depth[id] = t;
#endif
#ifdef OM_OUT_FETCHES
    out_fetches[id] = (uint)fetches;
#endif
#ifdef OM_OUT_FLAGS
    out_flags[id] = (uint)flags;
#endif
#else
    if (b.full && all(keep != 0)) {
        for (int r = 0; r < OM_LANES / 4; ++r) {
            const int id = OM_RUN4(b, r);
            vstore8(shuffle2(OM_ROW4(ou, r), OM_ROW4(ov, r), (uint8)(0, 4, 1, 5, 2, 6, 3, 7)), 0,
                    out_uv + 2 * id);
#ifdef OM_OUT_DEPTH
            vstore4(OM_ROW4(t, r), 0, out_depth + id);
#endif
#ifdef OM_OUT_FETCHES
            vstore4(OM_ROW4(fetches, r), 0, (__global int*)out_fetches + id);
#endif
#ifdef OM_OUT_FLAGS
            vstore4(OM_ROW4(flags, r), 0, (__global int*)out_flags + id);
#endif
        }
        return;
    }
    float pu[OM_LANES], pv[OM_LANES], pt[OM_LANES];
    int pf[OM_LANES], pg[OM_LANES], pk[OM_LANES];
    OM_VSTORE(ou, pu);
    OM_VSTORE(ov, pv);
    OM_VSTORE(t, pt);
    OM_VSTORE(fetches, pf);
    OM_VSTORE(flags, pg);
    OM_VSTORE(keep, pk);
    for (int k = 0; k < OM_LANES; ++k) {
        if (!pk[k] || !om_block_has(b, k)) continue;
        const int id = om_block_pixel(b, k);
        out_uv[2 * id] = pu[k];
        out_uv[2 * id + 1] = pv[k];
#ifdef OM_OUT_DEPTH
        out_depth[id] = pt[k];
#endif
#ifdef OM_OUT_FETCHES
        out_fetches[id] = (uint)pf[k];
#endif
#ifdef OM_OUT_FLAGS
        out_flags[id] = (uint)pg[k];
#endif
    }
#endif
}

__kernel void om_offset(const OmOffsetParams P, __global const float2* gb_uv2,
                        __global const float4* gb_view4, __global const float* heights,
                        __global const float* aux, __global const float* lod,
                        __global float2* out_uv2, __global float* out_depth,
                        __global uint* out_fetches, __global uint* out_flags,
                        __global const float4* curvature,
                        __global const float4* uv_metric OM_IMG_PARAM) {
#ifdef OM_LANE_PAIRS
    const int group = (int)get_global_id(0) * 2;
#else
    const int group = (int)get_global_id(0);
#endif
    const int groups = om_image_blocks(P.gb_width, P.gb_height, OM_LANES);
    if (group >= groups) return;
    const OmBlock blk = om_block(P.gb_width, P.gb_height, group);
    // The G-buffer is interleaved (uv: 2 floats, view: 4 per pixel): read as floats.
    __global const float* gb_uv = (__global const float*)gb_uv2;
    __global const float* gb_view = (__global const float*)gb_view4;
    __global float* out_uv = (__global float*)out_uv2;
    OmF u, v, vx, vy, vz;
    om_load_block(gb_uv, gb_view, blk, &u, &v, &vx, &vy, &vz);
    OmF m = 0.0f;
#ifdef OM_LOD
    m = om_load_block_f(lod, blk);
#endif
    const int pixels = P.gb_width * P.gb_height;
    OmCurvature k = om_load_curvature(curvature, uv_metric, pixels, blk);
#ifdef OM_LANE_PAIRS
    // The method's two-group walk (om_trace_pair) over this work-item's two blocks; past the last
    // block the second repeats the first and stores nothing.
    const int has_b = group + 1 < groups;
    const OmBlock blk_b = om_block(P.gb_width, P.gb_height, has_b ? group + 1 : group);
    OmLaneIn in_a, in_b;
    in_a.u = u;
    in_a.v = v;
    in_a.vx = vx;
    in_a.vy = vy;
    in_a.vz = vz;
    in_a.m = m;
    in_a.skip = in_b.skip = 0;
    in_a.k = k;
    in_b.m = 0.0f;
    om_load_block(gb_uv, gb_view, blk_b, &in_b.u, &in_b.v, &in_b.vx, &in_b.vy, &in_b.vz);
    in_b.k = om_load_curvature(curvature, uv_metric, pixels, blk_b);
#ifdef OM_LOD
    in_b.m = om_load_block_f(lod, blk_b);
#endif
    OmLaneOut a, b;
    om_offset_lane_pair(&P, &in_a, &in_b, heights, aux, &a, &b OM_IMG_ARG);
    om_store_block(out_uv, out_depth, out_fetches, out_flags, blk, (OmI)1, a.ou, a.ov, a.t,
                   a.fetches, a.flags);
    if (has_b)
        om_store_block(out_uv, out_depth, out_fetches, out_flags, blk_b, (OmI)1, b.ou, b.ov, b.t,
                       b.fetches, b.flags);
#else
    OmF ou, ov, t;
    OmI fetches, flags;
    om_offset_lanes(&P, u, v, vx, vy, vz, &k, (OmI)0, m, heights, aux, &ou, &ov, &t, &fetches,
                    &flags OM_IMG_ARG);
    om_store_block(out_uv, out_depth, out_fetches, out_flags, blk, (OmI)1, ou, ov, t, fetches,
                   flags);
#endif
}
