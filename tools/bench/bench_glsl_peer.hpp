// The fragment-shader peer in the bench: pom, steep and relief in GLSL (shaders/relief.glsl) as a
// full-screen pass over the same G-buffer and map, timed in turns with the offset kernels.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>

#include "bench_util.hpp"

namespace offsetmap::bench {

// At `res`, on the camera plane and on random rays (elevation 10-90 degrees), each method at its
// defaults: kernel and GLSL wall-clock ns/pixel (each run finished), their ratio, and both
// results' error against exact. Without the renderer built: {"skipped": why}.
nlohmann::json bench_glsl_peer(std::shared_ptr<Runtime> runtime, const Resolution& res,
                               const HeightMap& map, const PassSettings& settings,
                               double target_ms);

}  // namespace offsetmap::bench
