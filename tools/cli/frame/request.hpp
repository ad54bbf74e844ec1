// `offsetmap frame`'s command line read once into what the frame renders: every option checked,
// the table and scene read, each material's method resolved, before anything renders (a refusal
// leaves nothing written).
#pragma once
#ifdef OFFSETMAP_HAVE_RENDERER
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "../cli.hpp"
#include "offsetmap/renderer/frame.hpp"

namespace offsetmap::cli {

// --shadows' value: the self-shadow march ("none", "hard", "soft") and whether a shadow map of
// the sun joins it ("map", "map+hard", "map+soft").
struct ShadowChoice {
    std::string march = "none";
    bool map = false;
};
ShadowChoice parse_shadows(const std::string& value);

// --sun: the directional light, in degrees and as the world direction toward it.
struct Sun {
    double elevation = 0, azimuth = 0;
    std::array<float, 3> toward{};
};
// --sun's "ELEVATION,AZIMUTH" (y up, azimuth from +x toward +z). Throws UsageError naming --sun.
Sun parse_sun(const std::string& text);
// --spot's "X,Y,Z,AX,AY,AZ,INNER,OUTER" (the cone's half-angles in degrees). Throws UsageError
// naming --spot.
EngineLight parse_spot(const std::string& text);

struct FrameRequest {
    const FrameCommand* cmd = nullptr;  // the options as given
    std::string table_file;
    renderer::Scene scene;  // --camera and --sun applied
    std::vector<LoadedMaterial> table;
    // One a table entry: --method's, the entry's own, or for `auto` none until chosen on the
    // frame's own G-buffer (auto_slots).
    std::vector<MethodParams> methods;
    std::vector<size_t> auto_slots;
    std::optional<Sun> sun;
    std::optional<EngineLight> spot;  // --spot (never with --sun)
    ShadowChoice shadows;
    ShadeSettings shading;  // the march; the map is the renderer's (shadow_map)
    // The sun's shadow map as the shading takes it (--shadows map), at --shadow-size.
    std::optional<renderer::ShadowMapSettings> shadow_map;
    bool any_triplanar = false;
};

// Checks every option and input (UsageError for an option, Error for a file), reads the table,
// its maps and the scene, and makes the output folder.
FrameRequest read_frame_request(const FrameCommand& cmd);

}  // namespace offsetmap::cli
#endif
