// The one offset kernel entry: G-buffer load, validation, LOD, one method's om_trace, store,
// for a group of OM_LANES pixels per work-item (lanes.h), or two groups under OM_LANE_PAIRS (a
// method that also defines om_trace_pair, on lanes). A group is a block of the G-buffer image
// (OM_BLOCK_W x OM_BLOCK_H, om_shared.h); the host launches ceil(blocks / groups per work-item)
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
// Specialised at build time (the host sets these from the pass, one program each): OM_LANES,
// OM_LANE_PAIRS, OM_IMAGES, OM_LOD when the LOD system is on, OM_OUT_DEPTH / OM_OUT_FETCHES /
// OM_OUT_FLAGS for the optional outputs bound.

// A group's G-buffer (interleaved uv and view) gathered into private memory, split into planes with
// vector loads and shuffles.
#if OM_LANES == 8
#define om_load_full(pu, pv, u, v, vx, vy, vz)            \
    do {                                                  \
        float16 a_ = vload16(0, pu);                      \
        float16 b_ = vload16(0, pv), c_ = vload16(1, pv); \
        *(u) = a_.even;                                   \
        *(v) = a_.odd;                                    \
        *(vx) = (float8)(b_.s048c, c_.s048c);             \
        *(vy) = (float8)(b_.s159d, c_.s159d);             \
        *(vz) = (float8)(b_.s26ae, c_.s26ae);             \
    } while (0)
#elif OM_LANES == 16
#define om_load_full(pu, pv, u, v, vx, vy, vz)                                 \
    do {                                                                       \
        float16 a_ = vload16(0, pu), b_ = vload16(1, pu);                      \
        float16 c_ = vload16(0, pv), d_ = vload16(1, pv), e_ = vload16(2, pv), \
                f_ = vload16(3, pv);                                           \
        *(u) = (float16)(a_.even, b_.even);                                    \
        *(v) = (float16)(a_.odd, b_.odd);                                      \
        *(vx) = OM_CAT4(c_.s048c, d_.s048c, e_.s048c, f_.s048c);               \
        *(vy) = OM_CAT4(c_.s159d, d_.s159d, e_.s159d, f_.s159d);               \
        *(vz) = OM_CAT4(c_.s26ae, d_.s26ae, e_.s26ae, f_.s26ae);               \
    } while (0)
#endif

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
                              OmI skip, OmF m, __global const float* heights,
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
}

// The group's outputs from the trace's t, fetches and flags. Every method returns the hit's ray
// parameter t: uv' is the ray's footprint there, and the LOD fade moves it toward normal mapping.
OM_INLINE void om_lanes_end(const OmOffsetParams* P, const OmLaneGroup* g, OmF u, OmF v, OmF t,
                            OmI fetches, OmI trace_flags, OmF* ou_out, OmF* ov_out, OmF* t_out,
                            OmI* fetches_out, OmI* flags_out) {
    const OmRay* ray = &g->ray;
    OmF hu = ray->u - t * ray->vx, hv = ray->v - t * ray->vy;
    hu = ray->u + g->blend * (hu - ray->u);
    hv = ray->v + g->blend * (hv - ray->v);
    OmF ou = hu + g->base_u, ov = hv + g->base_v;
    // On a non-tiling surface a ray that leaves the tile sees past the polygon's edge.
    OmI outside = P->tile_mask ? (OmI)(ou < 0.0f || ou > 1.0f || ov < 0.0f || ov > 1.0f) : (OmI)0;
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

// One work-item's lanes: ray setup, LOD, the method, the LOD fade. Shared by om_offset and the
// material frame's tile entry, so a pixel gets the same bits through either.
OM_INLINE void om_offset_lanes(const OmOffsetParams* P, OmF u, OmF v, OmF vx, OmF vy, OmF vz,
                               OmI skip, OmF m, __global const float* heights,
                               __global const float* aux, OmF* ou_out, OmF* ov_out, OmF* t_out,
                               OmI* fetches_out, OmI* flags_out OM_IMG_PARAM) {
    OmLaneGroup g;
    om_lanes_begin(P, u, v, vx, vy, vz, skip, m, heights, aux, &g);
    OmF t = 0.0f;
    OmI fetches = 0, trace_flags = 0;
    if (OM_ANY(g.traced))
        t = om_trace(&g.ray, &g.f, P, g.traced, &fetches, &trace_flags OM_IMG_ARG);
    om_lanes_end(P, &g, u, v, t, fetches, trace_flags, ou_out, ov_out, t_out, fetches_out,
                 flags_out);
}

#ifdef OM_LANE_PAIRS
// A group's inputs (G-buffer planes, mip level, lanes to skip) and outputs, for the pair below.
typedef struct {
    OmF u, v, vx, vy, vz, m;
    OmI skip;
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
    om_lanes_begin(P, in_a->u, in_a->v, in_a->vx, in_a->vy, in_a->vz, in_a->skip, in_a->m, heights,
                   aux, &a);
    om_lanes_begin(P, in_b->u, in_b->v, in_b->vx, in_b->vy, in_b->vz, in_b->skip, in_b->m, heights,
                   aux, &b);
    OmF t_a = 0.0f, t_b = 0.0f;
    OmI fetches_a = 0, fetches_b = 0, trace_a = 0, trace_b = 0;
    if (OM_ANY(a.traced) || OM_ANY(b.traced))
        om_trace_pair(&a.ray, &a.f, a.traced, &b.ray, &b.f, b.traced, P, &t_a, &fetches_a,
                      &trace_a, &t_b, &fetches_b, &trace_b OM_IMG_ARG);
    om_lanes_end(P, &a, in_a->u, in_a->v, t_a, fetches_a, trace_a, &out_a->ou, &out_a->ov,
                 &out_a->t, &out_a->fetches, &out_a->flags);
    om_lanes_end(P, &b, in_b->u, in_b->v, t_b, fetches_b, trace_b, &out_b->ou, &out_b->ov,
                 &out_b->t, &out_b->fetches, &out_b->flags);
}
#endif

// Lane groups as blocks of the image rather than runs of a row: the rays of a 4 x 4 block start
// closer together than those of 16 pixels in a row, so their fetches share more cache lines and
// their walks end closer together (1080p camera frame, 4 x 4 against 16 x 1, in turns: AVX-512
// pom 0.91, steep 0.90, exact 0.92, cone 0.95 of the time; AVX2 target pom 0.83, steep 0.87;
// random rays 0.88-1.05). The offset entry takes OM_BW x OM_BH blocks of the whole image; the
// material frame's tiles take blocks no taller than a tile (om_tile_block_h), so a block's width
// is 4, 8 or 16 pixels.
#define OM_BW OM_BLOCK_W(OM_LANES)
#define OM_BH OM_BLOCK_H(OM_LANES)
#if OM_LANES > 1 && OM_BW % 4 != 0
#error "the block loads and stores below move runs of 4 pixels"
#endif

typedef struct {
    int x0, y0;  // the block's first pixel
    int x1, y1;  // its pixels lie in [x0, x1) x [y0, y1): the image's or the tile's edge cuts it
    int bw;      // pixels per block row: lane k is pixel (x0 + k % bw, y0 + k / bw)
    int stride;  // the image's width
    int full;    // no edge cuts it
} OmBlock;

OM_INLINE OmBlock om_block_at(int x0, int y0, int x1, int y1, int bw, int stride) {
    OmBlock b;
    b.x0 = x0;
    b.y0 = y0;
    b.x1 = min(x1, x0 + bw);
    b.y1 = min(y1, y0 + OM_LANES / bw);
    b.bw = bw;
    b.stride = stride;
    b.full = b.x1 - x0 == bw && b.y1 - y0 == OM_LANES / bw;
    return b;
}

// The offset entry's group-th block of the image.
OM_INLINE OmBlock om_block(const OmOffsetParams* P, int group) {
    const int per_row = (P->gb_width + OM_BW - 1) / OM_BW;
    const int x0 = group % per_row * OM_BW, y0 = group / per_row * OM_BH;
    return om_block_at(x0, y0, P->gb_width, P->gb_height, OM_BW, P->gb_width);
}

// Lane k's pixel: lanes past the block's cut repeat its last column or row.
OM_INLINE int om_block_pixel(OmBlock b, int k) {
    const int x = min(b.x0 + k % b.bw, b.x1 - 1);
    const int y = min(b.y0 + k / b.bw, b.y1 - 1);
    return y * b.stride + x;
}

OM_INLINE int om_block_has(OmBlock b, int k) {
    return b.x0 + k % b.bw < b.x1 && b.y0 + k / b.bw < b.y1;
}

// The G-buffer lines of the blocks after this one, asked for before this block's trace: a block
// reads 4 rows of the image, and with a trace's reads in between the hardware prefetcher no longer
// follows those rows (random rays, 4 x 4 blocks against runs of 16 pixels: pom 1.09x and steep
// 1.08x the time without it, 1.00 and 1.02x with it). PoCL's clang; elsewhere nothing.
#ifdef OM_POCL
#define OM_PREFETCH(p) __builtin_prefetch(p)
#else
#define OM_PREFETCH(p)
#endif

// Lanes 4 r .. 4 r + 3 of a group are 4 neighbouring pixels of a row of its block, from OM_RUN4.
#define OM_RUN4(b, r) (((b).y0 + 4 * (r) / (b).bw) * (b).stride + (b).x0 + 4 * (r) % (b).bw)
#if OM_LANES == 16
#define OM_ROW4(x, r) \
    ((r) == 0 ? (x).lo.lo : (r) == 1 ? (x).lo.hi : (r) == 2 ? (x).hi.lo : (x).hi.hi)
#define OM_JOIN4(a) OM_CAT4((a)[0], (a)[1], (a)[2], (a)[3])
#elif OM_LANES == 8
#define OM_ROW4(x, r) ((r) == 0 ? (x).lo : (x).hi)
#define OM_JOIN4(a) ((OmF)((a)[0], (a)[1]))
#endif

// The block's G-buffer as lane planes: each row of 4 pixels two vector loads and shuffles when the
// block is whole, a load per lane when an edge cuts it.
OM_INLINE void om_load_block(__global const float* gb_uv, __global const float* gb_view, OmBlock b,
                             OmF* u, OmF* v, OmF* vx, OmF* vy, OmF* vz) {
#if OM_LANES == 1
    const int id = om_block_pixel(b, 0);
    *u = gb_uv[2 * id];
    *v = gb_uv[2 * id + 1];
    *vx = gb_view[4 * id];
    *vy = gb_view[4 * id + 1];
    *vz = gb_view[4 * id + 2];
#else
    if (b.full) {
        float4 ru[OM_LANES / 4], rv[OM_LANES / 4], rx[OM_LANES / 4], ry[OM_LANES / 4],
            rz[OM_LANES / 4];
        for (int r = 0; r < OM_LANES / 4; ++r) {
            const int id = OM_RUN4(b, r);
            const float8 a = vload8(0, gb_uv + 2 * id);
            const float16 c = vload16(0, gb_view + 4 * id);
            OM_PREFETCH(gb_view + 4 * (id + b.bw));
            OM_PREFETCH(gb_view + 4 * (id + 2 * b.bw));
            OM_PREFETCH(gb_uv + 2 * (id + 2 * b.bw));
            ru[r] = a.even;
            rv[r] = a.odd;
            rx[r] = c.s048c;
            ry[r] = c.s159d;
            rz[r] = c.s26ae;
        }
        *u = OM_JOIN4(ru);
        *v = OM_JOIN4(rv);
        *vx = OM_JOIN4(rx);
        *vy = OM_JOIN4(ry);
        *vz = OM_JOIN4(rz);
        return;
    }
    float tu[2 * OM_LANES], tv[4 * OM_LANES];
    for (int k = 0; k < OM_LANES; ++k) {
        const int id = om_block_pixel(b, k);
        tu[2 * k] = gb_uv[2 * id];
        tu[2 * k + 1] = gb_uv[2 * id + 1];
        for (int c = 0; c < 4; ++c) tv[4 * k + c] = gb_view[4 * id + c];
    }
    om_load_full(tu, tv, u, v, vx, vy, vz);
#endif
}

// One float per pixel (the lod plane, the material ids) as lanes.
OM_INLINE OmF om_load_block_f(__global const float* p, OmBlock b) {
#if OM_LANES == 1
    return p[om_block_pixel(b, 0)];
#else
    if (b.full) {
        float4 rows[OM_LANES / 4];
        for (int r = 0; r < OM_LANES / 4; ++r) rows[r] = vload4(0, p + OM_RUN4(b, r));
        return OM_JOIN4(rows);
    }
    float t[OM_LANES];
    for (int k = 0; k < OM_LANES; ++k) t[k] = p[om_block_pixel(b, k)];
    return OM_VLOAD(t);
#endif
}

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
                        __global uint* out_fetches, __global uint* out_flags OM_IMG_PARAM) {
#ifdef OM_LANE_PAIRS
    const int group = (int)get_global_id(0) * 2;
#else
    const int group = (int)get_global_id(0);
#endif
    const int groups = om_image_blocks(P.gb_width, P.gb_height, OM_LANES);
    if (group >= groups) return;
    const OmBlock blk = om_block(&P, group);
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
#ifdef OM_LANE_PAIRS
    // The method's two-group walk (om_trace_pair) over this work-item's two blocks; past the last
    // block the second repeats the first and stores nothing.
    const int has_b = group + 1 < groups;
    const OmBlock blk_b = om_block(&P, has_b ? group + 1 : group);
    OmLaneIn in_a, in_b;
    in_a.u = u;
    in_a.v = v;
    in_a.vx = vx;
    in_a.vy = vy;
    in_a.vz = vz;
    in_a.m = m;
    in_a.skip = in_b.skip = 0;
    in_b.m = 0.0f;
    om_load_block(gb_uv, gb_view, blk_b, &in_b.u, &in_b.v, &in_b.vx, &in_b.vy, &in_b.vz);
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
    om_offset_lanes(&P, u, v, vx, vy, vz, (OmI)0, m, heights, aux, &ou, &ov, &t, &fetches,
                    &flags OM_IMG_ARG);
    om_store_block(out_uv, out_depth, out_fetches, out_flags, blk, (OmI)1, ou, ov, t, fetches,
                   flags);
#endif
}
