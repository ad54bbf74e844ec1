// A height field that changes every frame: what its update and each method's precomputed data
// cost to rebuild, per map size.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

#include "bench_util.hpp"

namespace offsetmap::bench {

// For each size: the field updated in place (from the host, and from a unorm16 buffer already on
// the device), then every method with precomputed data rebuilt for it; medians of `rounds`.
nlohmann::json bench_rebuild(std::shared_ptr<Runtime> runtime, const std::vector<int>& sizes,
                             int rounds);

}  // namespace offsetmap::bench
