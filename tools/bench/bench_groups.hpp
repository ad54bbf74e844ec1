// Each method's cost in a GPU's SIMD groups, modelled from its steps per pixel: the part of a
// GPU's cost that a CPU run hides.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_util.hpp"

namespace offsetmap::bench {

// The methods at their defaults (and the beam's variants of the walks that take it) on three
// G-buffers at `res` with the 1024^2 terrain map: the rendered room (its geometry; every material
// the terrain), the camera plane and random rays. Per method and scene: steps (height fetches) per
// traced pixel, the group efficiency (a group's steps over its slowest pixel's, summed) and the
// lane-steps per traced pixel for groups of 8 (4 x 2), 16 (4 x 4), 32 (8 x 4) and 64 (8 x 8)
// neighbouring pixels, the uv error against exact (texels), and this device's ns per pixel timed in
// turns with pom at its defaults (8/32) for about `target_ms` a row: the time and its ratio to
// pom's.
nlohmann::json bench_groups(std::shared_ptr<Runtime> runtime, const Resolution& res,
                            const std::string& data_dir, double target_ms,
                            const std::vector<const MethodInfo*>& methods);

}  // namespace offsetmap::bench
