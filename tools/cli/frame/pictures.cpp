#ifdef OFFSETMAP_HAVE_RENDERER
#include "pictures.hpp"

#include <cmath>

namespace offsetmap::cli {

Rgb8 depth_change_image(int w, int h, const std::vector<float>& before,
                        const std::vector<float>& after) {
    std::vector<float> change(before.size());
    for (size_t k = 0; k < change.size(); ++k)
        change[k] = before[k] >= 1.0f ? std::nanf("") : std::abs(after[k] - before[k]) * 1e4f;
    return heat_map(w, h, change, 16.0f);
}

nlohmann::json pass_json(const renderer::PassTimes& t) {
    return {{"gbuffer_ms", t.gbuffer},
            {"to_device_ms", t.to_device},
            {"reconstruct_ms", t.reconstruct},
            {"offset_ms", t.offset},
            {"shade_ms", t.shade},
            {"to_gl_ms", t.to_gl},
            {"depth_offset_ms", t.depth_offset},
            {"shadow_mask_ms", t.shadow_mask},
            {"total_ms", t.total}};
}

nlohmann::json pass_json(const renderer::FrameRun& r) {
    nlohmann::json j = pass_json(r.ms);
    if (!r.shadow_mask.empty()) j["shadow_map"] = pass_json(r.shadow_map_ms);
    j["frames"] = r.frames;
    j["light_draws"] = r.light_draws;
    return j;
}

}  // namespace offsetmap::cli
#endif
