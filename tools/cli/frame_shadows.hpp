// `offsetmap frame --sun ... --shadows map`: what the shadow options mean, and the frame's
// shadows against the truth's (frame.json's truth.shadow_mismatch).
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "offsetmap/image_io.hpp"
#include "offsetmap/renderer/frame.hpp"

namespace offsetmap::cli {

// --shadows' value: the self-shadow march ("none", "hard", "soft") and whether a shadow map of
// the sun joins it ("map", "map+hard", "map+soft").
struct ShadowChoice {
    std::string march = "none";
    bool map = false;
};
ShadowChoice parse_shadows(const std::string& value);

// With --sun and --truth: the truth's own shadows (renderer::shadow_truth) against three frames
// rendered for them, `flat` (the base meshes' map and depth), `displaced` (the relief in both)
// and `displaced-march` (and the self-shadow march, soft unless --shadows says hard): pixels whose
// lit or shadowed state differs. Leaves the renderer's shading and shadow map as `shading` and
// `shown_map` say. Adds a mismatch picture per variant to `tiles`.
nlohmann::json shadow_truth_section(const FrameCommand& cmd, const renderer::Scene& scene,
                                    const std::vector<LoadedMaterial>& table,
                                    const std::vector<MethodParams>& methods,
                                    const std::shared_ptr<Runtime>& rt,
                                    renderer::FrameRenderer& frame, const ShadeSettings& shading,
                                    const std::optional<renderer::ShadowMapSettings>& shown_map,
                                    std::vector<std::pair<std::string, Rgb8> >& tiles);

}  // namespace offsetmap::cli
#endif
