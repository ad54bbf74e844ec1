#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/passes.hpp"

namespace offsetmap {

// Error of one method at its defaults for one (view elevation, depth scale) cell, against the true
// hit (`exact` under the clamp rule, whatever grazing policy `settings` selects).
struct FailureCell {
    std::string method;
    double elevation_deg = 0;
    double scale = 0;
    ErrorStats uv;  // texels against exact (uv.count: the views compared)
    double fetches_mean = 0;
};

struct FailureMapOptions {
    std::vector<double> elevations_deg = {90, 75, 60, 45, 35, 25, 20, 15, 10, 7, 5, 3, 2, 1};
    std::vector<double> scales = {0.01, 0.02, 0.035, 0.05, 0.075, 0.1, 0.15, 0.2};
    int samples = 256;  // random (uv, azimuth) pairs per cell
    std::uint64_t seed = 7;
    PassSettings settings;  // scale is swept; reference plane, grazing rule and address from here
    std::vector<std::string> methods;  // empty: every method
    std::function<void(const std::string&)> progress;
    // A rendered G-buffer's views instead of random ones (null: random): each elevation row holds
    // up to `samples` of its pixels (uv and V as rendered) whose view elevation is nearest that
    // row's, drawn at random (seeded); a row no pixel is nearest to gives no cells.
    const GBuffer* views = nullptr;
};

std::vector<FailureCell> run_failure_map(std::shared_ptr<Runtime> runtime, const HeightMap& map,
                                         const FailureMapOptions& options);

void write_failure_csv(const std::string& path, const std::vector<FailureCell>& cells);

}  // namespace offsetmap
