// `offsetmap frame`'s report: each run's passes and its materials' error against exact (the
// printed tables and frame.json's modes), and the frame's pictures and planes.
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <nlohmann/json.hpp>
#include <vector>

#include "pictures.hpp"
#include "runs.hpp"

namespace offsetmap::cli {

// frame.json's modes, a row a run; each run's uv error against exact a pixel into `errors`.
nlohmann::json modes_section(const FrameRequest& request, const FrameRuns& runs, Runtime& rt,
                             std::vector<std::vector<float> >& errors);

// final.png (the shown run), the G-buffer and depth planes, triplanar.png and final-forward.png
// where they apply; the frame sheet's tiles of the runs.
Tiles write_frame_pictures(const FrameRequest& request, const FrameRuns& runs,
                           const std::vector<std::vector<float> >& errors);

}  // namespace offsetmap::cli
#endif
