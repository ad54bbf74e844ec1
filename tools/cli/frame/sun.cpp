#ifdef OFFSETMAP_HAVE_RENDERER
#include "sun.hpp"

#include <cstdio>

namespace offsetmap::cli {

using namespace offsetmap::renderer;

namespace {

// The lit fraction of each point the frame shows: white lit, dark in shadow, black where nothing
// is drawn.
Rgb8 mask_picture(int w, int h, const FrameRun& run, size_t& covered, size_t& shadowed) {
    Rgb8 picture{w, h, std::vector<std::uint8_t>(run.shadow_mask.size() * 3)};
    for (size_t k = 0; k < run.shadow_mask.size(); ++k) {
        const bool drawn = run.depth_after[k] < 1.0f;
        covered += drawn;
        shadowed += drawn && run.shadow_mask[k] < 0.5f;
        const std::uint8_t g = drawn ? std::uint8_t(40 + 215 * run.shadow_mask[k]) : 0;
        picture.rgb[3 * k] = picture.rgb[3 * k + 1] = picture.rgb[3 * k + 2] = g;
    }
    return picture;
}

}  // namespace

nlohmann::json sun_section(const FrameRequest& r, const FrameRuns& f, Tiles& tiles) {
    const Sun& sun = *r.sun;
    const LightMaps& maps = f.light_maps;
    const FrameRun& run = *f.sun;
    const int n = maps.size;
    const std::string d = r.cmd->out_dir + "/";
    write_depth_exr(d + "shadow-map.exr", n, n, maps.displaced);
    write_depth_exr(d + "shadow-map-base.exr", n, n, maps.base);
    // The relief's depth below the base along the light's ray, in world units.
    const Camera lit = light_camera(r.scene, sun.toward);
    const double range = lit.far_plane - lit.near_plane;
    std::vector<double> moved;
    for (size_t k = 0; k < maps.base.size(); ++k)
        if (maps.base[k] < 1.0f) moved.push_back((maps.displaced[k] - maps.base[k]) * range);
    const ErrorStats relief = error_stats(moved);
    std::printf(
        "sun at %.1f, %.1f degrees: %dx%d shadow map over %zu covered pixels in %.2f ms (offset "
        "%.2f); the relief moves it by up to %.4g m (p95 %.4g)\n",
        sun.elevation, sun.azimuth, n, n, moved.size(), run.shadow_map_ms.total,
        run.shadow_map_ms.offset, relief.max, relief.p95);
    tiles.push_back(
        {"the sun's view: displaced shadow map against the base's (log, white = "
         "16e-4 of its depth range)",
         depth_change_image(n, n, maps.base, maps.displaced)});
    size_t covered = 0, shadowed = 0;
    const Rgb8 picture = mask_picture(r.cmd->width, r.cmd->height, run, covered, shadowed);
    std::printf("the frame's points against it (3 x 3 taps): %zu of %zu in shadow\n", shadowed,
                covered);
    write_image(d + "shadow-mask.png", picture);
    tiles.push_back(
        {"the frame's points against the sun's displaced map (white lit, dark in "
         "shadow; in the shading with --shadows map)",
         picture});
    return {{"sun_deg", {sun.elevation, sun.azimuth}},
            {"toward_light", sun.toward},
            {"size", n},
            {"half_extent_m", lit.ortho_half_height},
            {"depth_range_m", range},
            {"covered_pixels", moved.size()},
            {"passes", pass_json(run.shadow_map_ms)},
            {"relief_depth_m", {{"p95", relief.p95}, {"max", relief.max}}},
            {"frame_pixels_in_shadow", shadowed}};
}

}  // namespace offsetmap::cli
#endif
