// The material frame's part of the bench.
#pragma once
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "bench_util.hpp"

namespace offsetmap::bench {

// A material of the bench's tables: `method` with `params` over field f.
FrameMaterial bench_material(int id, const std::string& name, const DeviceHeightField& f,
                             const PassSettings& s, const std::string& method,
                             const std::map<std::string, std::string>& params = {});

// At `res` on the plane scene: four materials against pom for all, one method on a tenth of the
// screen against the whole, and the tile height; each comparison timed in turns.
nlohmann::json bench_materials(std::shared_ptr<Runtime> runtime, const Resolution& res,
                               double target_ms);

}  // namespace offsetmap::bench
