// maxmip's pyramid of maxima: its levels and padding, one rule for the builder
// (core/src/precompute/max_pyramid.cpp), the prep kernel (prep/maxmip.cl) and the method
// (methods/maxmip.cl). C++17 and OpenCL C.
#ifndef OM_MAXMIP_PYRAMID_H
#define OM_MAXMIP_PYRAMID_H

#ifndef OM_OPENCL_C  // a kernel program has the library's own at its top
#include "offsetmap/shared.h"
#endif

// Level k holds 2^k x 2^k blocks, up to this level.
#define OM_MAXMIP_MAX_LEVEL 15
// The most steps a beam takes over the pyramid (common/beam.cl): each doubles, halves or ends its
// interval, and counts as a fetch on each of its lanes.
#define OM_BEAM_STEPS 16
// The pyramid is stored over the map padded up to a multiple of 2^levels on each side, so
// every level is an exact halving of the one below; `levels` is the largest count whose padding
// adds at most an eighth to either side (none for powers of two: 1024 has 10 levels, 1025 has 7)
// and whose blocks are no wider than the map. Any size and either address mode.
static inline int om_maxmip_padded(int size, int levels) {
    return ((size + (1 << levels) - 1) >> levels) << levels;
}
// Where level k (>= 1) of a pyramid over wp x hp padded cells starts, in floats: after levels
// 1 .. k - 1, sum of wp hp / 4^m (the padded sizes halve exactly at every level).
static inline int om_maxmip_level_start(int wp, int hp, int k) {
    return (wp >> (k - 1)) * (hp >> (k - 1)) * ((1 << (2 * (k - 1))) - 1) / 3;
}
static inline int om_maxmip_levels(int width, int height, int address_mode) {
    int levels = 0;
    (void)address_mode;
    const int longest = width > height ? width : height;
    while (levels < OM_MAXMIP_MAX_LEVEL && (1 << (levels + 1)) <= longest &&
           8 * om_maxmip_padded(width, levels + 1) <= 9 * width &&
           8 * om_maxmip_padded(height, levels + 1) <= 9 * height)
        ++levels;
    return levels;
}

#endif
