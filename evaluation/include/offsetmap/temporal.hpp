#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/passes.hpp"
#include "offsetmap/scenes.hpp"

namespace offsetmap {

// Temporal stability between frames f and f + 1 of a camera path: per screen pixel traced in both
// frames, the method's change of uv' minus exact's change of uv', in texels. A method that tracks
// the true hit has 0; swimming shows as a steady small value, layer stepping and popping as a
// large share of pixels over one texel.
struct TemporalRecord {
    std::string method;
    int frame = 0;    // the pair (frame, frame + 1)
    double mean = 0;  // texels
    double p95 = 0;
    double pop_share = 0;  // share of pixels whose change is off by more than one texel
};

struct TemporalOptions {
    PlaneScene start;  // frame 0
    int frames = 24;
    double step = 0.001;        // camera travel per frame along its heading (world units)
    double yaw_step_deg = 0.1;  // heading change per frame
    PassSettings settings;
    std::vector<std::string> methods;  // empty: every method
    std::function<void(const std::string&)> progress;
};

std::vector<TemporalRecord> run_temporal(std::shared_ptr<Runtime> runtime, const HeightMap& map,
                                         const TemporalOptions& options);

void write_temporal_csv(const std::string& path, const std::vector<TemporalRecord>& records);

}  // namespace offsetmap
