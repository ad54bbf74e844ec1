// Pictures and json pieces the frame's report, truth and sun sections share.
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "offsetmap/image_io.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/truth.hpp"

namespace offsetmap::cli {

// The frame sheet's tiles: a caption and its picture.
using Tiles = std::vector<std::pair<std::string, Rgb8> >;

// Depth offset as a picture: grey where unchanged, darker where pushed away from the eye.
Rgb8 depth_change_image(int w, int h, const std::vector<float>& before,
                        const std::vector<float>& after);

nlohmann::json pass_json(const renderer::PassTimes& t);
// A run's passes; with the sun's shadow map the light's passes that drew it, once a frame
// (their times are in the frame's total), and the frames and light draws.
nlohmann::json pass_json(const renderer::FrameRun& r);
// An error's mean, p95 and max (renderer::ErrorSummary, ErrorStats).
template <typename Error>
nlohmann::json summary_json(const Error& e) {
    return {{"mean", e.mean}, {"p95", e.p95}, {"max", e.max}};
}

}  // namespace offsetmap::cli
#endif
