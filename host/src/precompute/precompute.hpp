// The precomputed data of the methods that have some: each spec (bytes, builder) lives beside its
// prep kernel (kernels/prep/) and is named by its method's registry row.
#pragma once
#include "offsetmap/registry.hpp"

namespace offsetmap {

extern const PrecomputeSpec kDistanceMap;  // sphere: prep/distance.cl
extern const PrecomputeSpec kMaxPyramid;   // maxmip: prep/maxmip.cl
extern const PrecomputeSpec kConeMap;      // cone: prep/cone.cl

}  // namespace offsetmap
