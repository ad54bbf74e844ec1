// The cone map's cells: one packed word each, in tiles; one definition for the builder
// (core/src/precompute/cone_map.cpp), the prep kernel (prep/cone.cl) and the method
// (methods/cone.cl). C++17 and OpenCL C (om_uint from offsetmap/shared.h).
#ifndef OM_CONE_MAP_H
#define OM_CONE_MAP_H

#ifndef OM_OPENCL_C  // a kernel program has the library's own at its top
#include "offsetmap/shared.h"
#endif

// The cone map's build searches rings of OM_CONE_BLOCK x OM_CONE_BLOCK blocks of cells.
#define OM_CONE_BLOCK 8
// One 32-bit word per cell: the low 16 bits q_h give the cell maximum rounded up to
// q_h / OM_CONE_HC_SCALE (65535 decodes above 1, so every height in [0, 1] has a bound), the high 16 bits q_c the cone ratio
// rounded down to (q_c / OM_CONE_C_SCALE)^2 (up to 1024, the largest max_ratio; the square root
// keeps narrow cones precise). Both roundings only shorten steps, so the hit is still exact's.
// Cells lie in 32 x 32 tiles (4 KiB, a page) of 4 x 4 blocks (64 bytes, a cache line), the map
// padded to whole tiles, so neighbouring cells share lines and pages (row-major rows of a 1024^2
// map are a page apart). A cone jump waits on its read, which misses the caches more the larger
// the map (the layout's gain: docs/throughput.md).
#define OM_CONE_HC_SCALE 65534.0f
#define OM_CONE_C_SCALE 2047.0f
#define OM_CONE_TILE 32
static inline int om_cone_tiles(int size) { return (size + OM_CONE_TILE - 1) / OM_CONE_TILE; }
// The decoding, once for the build's check, the host and the method's lanes: a half-word already
// converted to float (or to lanes of floats) gives the maximum, or the cone ratio's square root.
#define OM_CONE_HC_OF(qh) ((qh) * (1.0f / OM_CONE_HC_SCALE))
#define OM_CONE_ROOT_OF(qc) ((qc) * (1.0f / OM_CONE_C_SCALE))
static inline float om_cone_hc(om_uint q) { return OM_CONE_HC_OF((float)(q & 0xffffu)); }
static inline float om_cone_ratio(om_uint q) {
    const float r = OM_CONE_ROOT_OF((float)(q >> 16));
    return r * r;
}
// Cell (i, j)'s word, for scalars or lane vectors; tiles_x = om_cone_tiles(width).
#define OM_CONE_INDEX(i, j, tiles_x)                                           \
    (((((j) >> 5) * (tiles_x) + ((i) >> 5)) << 10) + ((((j) >> 2) & 7) << 7) + \
     ((((i) >> 2) & 7) << 4) + (((j)&3) << 2) + ((i)&3))
// With `beam` on, maxmip's pyramid of the same field follows the cone map's tiles.
static inline long om_cone_words(int width, int height) {
    return (long)om_cone_tiles(width) * om_cone_tiles(height) * OM_CONE_TILE * OM_CONE_TILE;
}
#define om_cone_pyramid(aux, width, height) ((aux) + om_cone_words(width, height))

#endif
