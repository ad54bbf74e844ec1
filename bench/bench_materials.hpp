// The material frame's part of the bench.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>

#include "bench_util.hpp"

namespace offsetmap::bench {

// At `res` on the plane scene: four materials against pom for all, one method on a tenth of the
// screen against the whole, and the tile height; each comparison timed in turns.
nlohmann::json bench_materials(std::shared_ptr<Runtime> runtime, const Resolution& res,
                               double target_ms);

}  // namespace offsetmap::bench
