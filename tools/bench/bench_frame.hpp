// The rendered frame's part of the bench: each pass of the deferred room against the offset pass.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench_util.hpp"

namespace offsetmap::bench {

// The built-in room (data_dir's maps and table) at `res`, every shadow mode, `rounds` frames
// each, taken in turns (mode after mode, round after round) so a noisy machine moves them
// together; per pass the median, and the ratios the frame's targets are stated in: each pass
// against the offset pass of the same frames, the copies against a host memcpy of the same bytes
// timed beside them. With two kernel folders (`kernel_dirs`), the same for each, in turns: an
// A/B of a kernel change on the whole frame.
nlohmann::json bench_frame(std::shared_ptr<Runtime> runtime, const Resolution& res,
                           const std::string& data_dir, int rounds,
                           const std::vector<std::string>& kernel_dirs = {});

// The curved scene (data_dir's curved.gltf and its table) at `res`: the deferred frame over the
// tangent plane, over the curved base, and with the layer behind, `rounds` frames each in turns;
// per pass the median and the ratios per round (curved over plane, two layers over curved and over
// plane). Beside it the curvature plane's read alone: the offset pass (pom, the camera plane, a
// 1024^2 map) with a plane of zeros bound against none, in turns.
nlohmann::json bench_curved_frame(std::shared_ptr<Runtime> runtime, const Resolution& res,
                                  const std::string& data_dir, int rounds, double target_ms);

// The room under a sun at 20 degrees (azimuth 60) at `res`: its deferred frame without a shadow map
// and with a displaced map of `map_size`^2, `rounds` frames each in turns. Reports the light's
// passes (G-buffer to depth offset) per map pixel against the camera's same passes per frame pixel
// (the same methods), the receivers' test, and the shade pass with and without the mask.
nlohmann::json bench_shadow_map(std::shared_ptr<Runtime> runtime, const Resolution& res,
                                const std::string& data_dir, int rounds, int map_size);

// The terrain scene (data/terrain.gltf, no uv) at `res`, its materials triplanar against the same
// scene and table with a uv from the world's x and z (the ground's projection from above) and no
// projection: the same method over the same pixels, `rounds` frames each in turns. Reports both
// frames' passes, the ratios a round, and the triplanar pixels traced in one, two and three
// projections.
nlohmann::json bench_triplanar_frame(std::shared_ptr<Runtime> runtime, const Resolution& res,
                                     const std::string& data_dir, int rounds);

}  // namespace offsetmap::bench
