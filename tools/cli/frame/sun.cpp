#ifdef OFFSETMAP_HAVE_RENDERER
#include "sun.hpp"

#include <cmath>
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

// The relief's depth below the base along the light's rays, in world units, at each texel the
// base covers: an orthographic map's window depth is linear along them (its range), a spot's is
// unprojected at both depths.
std::vector<double> relief_depths(const FrameRequest& r, const LightMaps& maps, double range) {
    std::vector<double> moved;
    const int n = maps.size;
    const std::array<float, 16>& m = maps.inverse_view_projection;
    auto point = [&](int k, float d) {
        const double x = (2.0 * (k % n) + 1) / n - 1, y = 1 - (2.0 * (k / n) + 1) / n,
                     z = 2.0 * d - 1;
        double p[4];
        for (int c = 0; c < 4; ++c) p[c] = m[c] * x + m[4 + c] * y + m[8 + c] * z + m[12 + c];
        return std::array<double, 3>{p[0] / p[3], p[1] / p[3], p[2] / p[3]};
    };
    for (size_t k = 0; k < maps.base.size(); ++k) {
        if (!(maps.base[k] < 1.0f)) continue;
        if (!r.spot) {
            moved.push_back((maps.displaced[k] - maps.base[k]) * range);
            continue;
        }
        const auto a = point(int(k), maps.base[k]), b = point(int(k), maps.displaced[k]);
        moved.push_back(std::sqrt(std::pow(b[0] - a[0], 2) + std::pow(b[1] - a[1], 2) +
                                  std::pow(b[2] - a[2], 2)));
    }
    return moved;
}

}  // namespace

nlohmann::json sun_section(const FrameRequest& r, const FrameRuns& f, Tiles& tiles) {
    const LightMaps& maps = f.light_maps;
    const FrameRun& run = *f.sun;
    const int n = maps.size;
    const std::string d = r.cmd->out_dir + "/";
    write_depth_exr(d + "shadow-map.exr", n, n, maps.displaced);
    write_depth_exr(d + "shadow-map-base.exr", n, n, maps.base);
    const Camera lit =
        r.spot ? spot_camera(r.scene, *r.spot) : light_camera(r.scene, r.sun->toward);
    const double range = lit.far_plane - lit.near_plane;
    const std::vector<double> moved = relief_depths(r, maps, range);
    const ErrorStats relief = error_stats(moved);
    nlohmann::json doc;
    if (r.spot) {
        const EngineLight& s = *r.spot;
        std::printf("spot at (%.3g, %.3g, %.3g), cone %.1f-%.1f degrees", s.vector[0], s.vector[1],
                    s.vector[2], s.cone_inner * 180.0 / M_PI, s.cone_outer * 180.0 / M_PI);
        doc = {{"spot",
                {{"position", s.vector},
                 {"axis", s.axis},
                 {"cone_deg", {s.cone_inner * 180.0 / M_PI, s.cone_outer * 180.0 / M_PI}}}},
               {"fov_deg", lit.fov_y_deg}};
    } else {
        const Sun& sun = *r.sun;
        std::printf("sun at %.1f, %.1f degrees", sun.elevation, sun.azimuth);
        doc = {{"sun_deg", {sun.elevation, sun.azimuth}},
               {"toward_light", sun.toward},
               {"half_extent_m", lit.ortho_half_height}};
    }
    std::printf(
        ": %dx%d shadow map over %zu covered pixels in %.2f ms (offset %.2f); the relief moves "
        "it by up to %.4g m (p95 %.4g)\n",
        n, n, moved.size(), run.shadow_map_ms.total, run.shadow_map_ms.offset, relief.max,
        relief.p95);
    const std::string who = r.spot ? "spot" : "sun";
    tiles.push_back({"the " + who +
                         "'s view: displaced shadow map against the base's (log, white = "
                         "16e-4 of its depth range)",
                     depth_change_image(n, n, maps.base, maps.displaced)});
    size_t covered = 0, shadowed = 0;
    const Rgb8 picture = mask_picture(r.cmd->width, r.cmd->height, run, covered, shadowed);
    std::printf("the frame's points against it (3 x 3 taps): %zu of %zu in shadow\n", shadowed,
                covered);
    write_image(d + "shadow-mask.png", picture);
    tiles.push_back(
        {"the frame's points against the " + who +
             "'s displaced map (white lit, dark in shadow; in the shading with --shadows map)",
         picture});
    doc["size"] = n;
    doc["depth_range_m"] = range;
    doc["covered_pixels"] = moved.size();
    doc["passes"] = pass_json(run.shadow_map_ms);
    doc["relief_depth_m"] = {{"p95", relief.p95}, {"max", relief.max}};
    doc["frame_pixels_in_shadow"] = shadowed;
    return doc;
}

}  // namespace offsetmap::cli
#endif
