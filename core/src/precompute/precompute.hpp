// The precomputed data of the methods that have some: each spec (bytes, builder) lives beside its
// prep kernel (kernels/prep/) and is named by its method's registry row.
#pragma once
#include <string>
#include <vector>

#include "offsetmap/heightmap.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap {

extern const PrecomputeSpec kDistanceMap;  // sphere: prep/distance.cl
extern const PrecomputeSpec kMaxPyramid;   // maxmip: prep/maxmip.cl
extern const PrecomputeSpec kConeMap;      // cone: prep/cone.cl

// Enqueues `kernel` over `range` (2 or 3 dimensions) after `wait`. Without a progress callback on
// the runtime, as one launch; with one, in slices along the last dimension, waiting for each and
// reporting `what` as it goes. Returns the events (all of them, for the profiling sum).
std::vector<cl::Event> enqueue_with_progress(Runtime& runtime, cl::Kernel& kernel,
                                             const cl::NDRange& range, const std::string& what,
                                             const std::vector<cl::Event>& wait = {});

// Kernel milliseconds of the events, once they are complete (0 without a profiling queue).
double events_ms(const Runtime& runtime, const std::vector<cl::Event>& events);

}  // namespace offsetmap
