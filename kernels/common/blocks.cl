// Lane groups as blocks of an image: which pixels a work-item's OM_LANES lanes hold, and the loads
// and stores that move a block's planes between the caller's interleaved buffers and lane vectors.
// The offset entry (offset.cl), the material frame's tiles (frame/tiles.cl) and the shade pass
// (shade.cl) share them, so every pass walks the image in the same blocks.

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

// Lane groups as blocks of the image rather than runs of a row: the rays of a 4 x 4 block start
// closer together than those of 16 pixels in a row, so their fetches share more cache lines and
// their walks end closer together (measured on camera frames under both instruction sets:
// docs/throughput.md, "Lanes as blocks of the image"). The offset entry takes OM_BW x OM_BH blocks of the whole image; the
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

// The group-th OM_BW x OM_BH block of a width x height image (the offset and shade entries).
OM_INLINE OmBlock om_block(int width, int height, int group) {
    const int per_row = (width + OM_BW - 1) / OM_BW;
    const int x0 = group % per_row * OM_BW, y0 = group / per_row * OM_BH;
    return om_block_at(x0, y0, width, height, OM_BW, width);
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
// follows those rows, and random rays in blocks ran slower than in runs of a row without it
// (docs/throughput.md). PoCL's clang; elsewhere nothing.
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

// A float2 plane (uv, interleaved) as two lane vectors.
OM_INLINE void om_load_block2(__global const float* p, OmBlock b, OmF* x, OmF* y) {
#if OM_LANES == 1
    const int id = om_block_pixel(b, 0);
    *x = p[2 * id];
    *y = p[2 * id + 1];
#else
    if (b.full) {
        float4 rx[OM_LANES / 4], ry[OM_LANES / 4];
        for (int r = 0; r < OM_LANES / 4; ++r) {
            const float8 a = vload8(0, p + 2 * OM_RUN4(b, r));
            rx[r] = a.even;
            ry[r] = a.odd;
        }
        *x = OM_JOIN4(rx);
        *y = OM_JOIN4(ry);
        return;
    }
    float tx[OM_LANES], ty[OM_LANES];
    for (int k = 0; k < OM_LANES; ++k) {
        const int id = om_block_pixel(b, k);
        tx[k] = p[2 * id];
        ty[k] = p[2 * id + 1];
    }
    *x = OM_VLOAD(tx);
    *y = OM_VLOAD(ty);
#endif
}

// A float4 plane (curvature) as four lane vectors.
OM_INLINE void om_load_block4(__global const float* p, OmBlock b, OmF* x, OmF* y, OmF* z, OmF* w) {
#if OM_LANES == 1
    const int id = om_block_pixel(b, 0);
    *x = p[4 * id];
    *y = p[4 * id + 1];
    *z = p[4 * id + 2];
    *w = p[4 * id + 3];
#else
    if (b.full) {
        float4 rx[OM_LANES / 4], ry[OM_LANES / 4], rz[OM_LANES / 4], rw[OM_LANES / 4];
        for (int r = 0; r < OM_LANES / 4; ++r) {
            const float16 c = vload16(0, p + 4 * OM_RUN4(b, r));
            rx[r] = c.s048c;
            ry[r] = c.s159d;
            rz[r] = c.s26ae;
            rw[r] = c.s37bf;
        }
        *x = OM_JOIN4(rx);
        *y = OM_JOIN4(ry);
        *z = OM_JOIN4(rz);
        *w = OM_JOIN4(rw);
        return;
    }
    float tx[OM_LANES], ty[OM_LANES], tz[OM_LANES], tw[OM_LANES];
    for (int k = 0; k < OM_LANES; ++k) {
        const int id = om_block_pixel(b, k);
        tx[k] = p[4 * id];
        ty[k] = p[4 * id + 1];
        tz[k] = p[4 * id + 2];
        tw[k] = p[4 * id + 3];
    }
    *x = OM_VLOAD(tx);
    *y = OM_VLOAD(ty);
    *z = OM_VLOAD(tz);
    *w = OM_VLOAD(tw);
#endif
}

// The first three values of a float4 plane (view, light) as lane vectors.
OM_INLINE void om_load_block3(__global const float* p, OmBlock b, OmF* x, OmF* y, OmF* z) {
    OmF w;
    om_load_block4(p, b, x, y, z, &w);
}

// One float a pixel, the lanes whose pixels lie in the block.
OM_INLINE void om_store_block_f(__global float* p, OmBlock b, OmF x) {
#if OM_LANES == 1
    if (om_block_has(b, 0)) p[om_block_pixel(b, 0)] = x;
#else
    if (b.full) {
        for (int r = 0; r < OM_LANES / 4; ++r) vstore4(OM_ROW4(x, r), 0, p + OM_RUN4(b, r));
        return;
    }
    float t[OM_LANES];
    OM_VSTORE(x, t);
    for (int k = 0; k < OM_LANES; ++k)
        if (om_block_has(b, k)) p[om_block_pixel(b, k)] = t[k];
#endif
}

// Stores a float4 plane (colour) from four lane vectors, for the lanes whose pixels lie in the
// block: a row of 4 pixels as one 16-float store when the block is whole.
OM_INLINE void om_store_block4(__global float* p, OmBlock b, OmF x, OmF y, OmF z, OmF w) {
#if OM_LANES == 1
    if (!om_block_has(b, 0)) return;
    const int id = om_block_pixel(b, 0);
    p[4 * id] = x;
    p[4 * id + 1] = y;
    p[4 * id + 2] = z;
    p[4 * id + 3] = w;
#else
    if (b.full) {
        for (int r = 0; r < OM_LANES / 4; ++r) {
            const uint8 zip = (uint8)(0, 4, 1, 5, 2, 6, 3, 7);
            const float8 xy = shuffle2(OM_ROW4(x, r), OM_ROW4(y, r), zip);
            const float8 zw = shuffle2(OM_ROW4(z, r), OM_ROW4(w, r), zip);
            vstore16(
                shuffle2(xy, zw, (uint16)(0, 1, 8, 9, 2, 3, 10, 11, 4, 5, 12, 13, 6, 7, 14, 15)), 0,
                p + 4 * OM_RUN4(b, r));
        }
        return;
    }
    float tx[OM_LANES], ty[OM_LANES], tz[OM_LANES], tw[OM_LANES];
    OM_VSTORE(x, tx);
    OM_VSTORE(y, ty);
    OM_VSTORE(z, tz);
    OM_VSTORE(w, tw);
    for (int k = 0; k < OM_LANES; ++k)
        if (om_block_has(b, k))
            vstore4((float4)(tx[k], ty[k], tz[k], tw[k]), om_block_pixel(b, k), p);
#endif
}
