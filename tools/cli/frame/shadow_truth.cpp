#ifdef OFFSETMAP_HAVE_RENDERER
#include "shadow_truth.hpp"

#include <algorithm>
#include <cstdio>

#include "offsetmap/renderer/truth.hpp"

namespace offsetmap::cli {

using namespace offsetmap::renderer;

nlohmann::json shadow_truth_section(const FrameRequest& r, const std::shared_ptr<Runtime>& rt,
                                    FrameRuns& runs, Tiles& tiles) {
    const FrameCommand& cmd = *r.cmd;
    FrameRenderer& frame = *runs.renderer;
    const int w = cmd.width, h = cmd.height;
    // The light's view holds the whole scene: the lattice of both views no finer than a texel a
    // quad (the tessellation table puts that lattice's uv error at hundredths of a texel). Its
    // map as the frame's, filtered alike, unless --shadow-truth-size asks for a finer one.
    const ShadowMapSettings as_frame;
    const int truth_size = cmd.shadow_truth_size ? cmd.shadow_truth_size : cmd.shadow_size;
    const ShadowTruth t = shadow_truth(rt, frame, r.scene, r.table, r.methods, w, h, truth_size,
                                       as_frame.pcf_radius, std::max(cmd.truth_level, 1.0f));
    const std::array<float, 3> toward = r.scene.light.vector;
    struct Variant {
        const char* name;
        bool displaced;
        ShadowMode march;
    };
    const ShadowMode march = r.shadows.march == "hard" ? ShadowMode::Hard : ShadowMode::Soft;
    const Variant variants[] = {{"flat", false, ShadowMode::None},
                                {"displaced", true, ShadowMode::None},
                                {"displaced-march", true, march}};
    nlohmann::json pixels, doc;
    std::printf("truth: the displaced meshes' own shadow map, %dx%d, %zu triangles, in %.0f ms\n",
                truth_size, truth_size, t.triangles, t.ms);
    size_t compared = 0;
    for (const Variant& v : variants) {
        ShadeSettings s = r.shading;
        s.shadow = v.march;
        frame.set_shading(s);
        ShadowMapSettings map;
        map.size = cmd.shadow_size;
        map.displaced = v.displaced;
        frame.set_shadow_map(map);
        frame.set_curvature(cmd.curvature);
        const FrameRun run = frame.render(FrameMode::Deferred, false, 1);
        frame.set_curvature(false);
        std::vector<std::uint8_t> mismatched;
        const ShadowMismatch m =
            shadow_mismatch(t, run.light_visibility, run.depth_after, toward, &mismatched);
        compared = m.compared;
        pixels[v.name] = m.mismatch;
        std::printf("truth: shadows %-16s %8zu of %zu lit pixels differ from the truth's\n", v.name,
                    m.mismatch, m.compared);
        // The frame's light visibility, mismatches in red.
        std::vector<cl_float4> c(run.light_visibility.size());
        for (size_t k = 0; k < c.size(); ++k) {
            const float g = run.depth_after[k] < 1.0f ? 0.15f + 0.6f * run.light_visibility[k] : 0;
            c[k] = mismatched[k] ? cl_float4{{1.0f, 0.05f, 0.02f, 1.0f}} : cl_float4{{g, g, g, 1}};
        }
        const Rgb8 picture = to_srgb8(w, h, c);
        write_image(cmd.out_dir + "/shadow-truth-" + v.name + ".png", picture);
        tiles.push_back({std::string("shadows, ") + v.name +
                             ": light visibility, red where lit or shadowed unlike the truth",
                         picture});
    }
    frame.set_shading(r.shading);
    frame.set_shadow_map(r.shadow_map);
    doc["pixels"] = pixels;
    doc["compared_pixels"] = compared;
    doc["sun_deg"] = {r.sun->elevation, r.sun->azimuth};
    doc["map_size"] = cmd.shadow_size;
    doc["truth_map_size"] = truth_size;
    doc["truth_triangles"] = t.triangles;
    return doc;
}

}  // namespace offsetmap::cli
#endif
