// The truth: the relief meshes tessellated and displaced for real, drawn by the G-buffer raster.
// On a flat quad it is the tangent-plane model itself, so the exact method's hit must agree with it
// within the truth's own bound on every pixel.
#include <algorithm>
#include <cstring>
#include <functional>
#include <glm/glm.hpp>

#include "support.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/truth.hpp"
#include "truth_support.hpp"
#endif

namespace omtest {
namespace {

#ifdef OFFSETMAP_HAVE_RENDERER
using namespace offsetmap::renderer;

struct FlatCase {
    const char* name;  // its figure key's middle too: the first word
    HeightMap map;
    AddressMode address;
    float scale, reference;
    double elevation_deg;  // the camera's pitch down onto the quad
    double eye_height = 0.35;
    float tiles = 16.0f;  // across the quad (a clamped map past its one tile is flat)
};

LoadedMaterial material(const FlatCase& c) {
    LoadedMaterial m;
    m.spec.id = 1;
    m.spec.name = c.name;
    m.spec.method = "exact";
    m.spec.settings.scale = c.scale;
    m.spec.settings.reference_plane = c.reference;
    m.spec.settings.address = c.address;
    m.map = c.map;
    return m;
}

// A floor quad 8 m a side of tiles x tiles tiles (isotropic uv density), seen from `eye` m up at
// the case's pitch: the far rows reach the quad's far edge, low ones past the grazing minimum.
Scene flat_scene(double pitch_deg, double eye = 0.35, float tiles = 16.0f) {
    Scene s;
    s.name = "flat";
    s.meshes.push_back(make_quad("floor", 1, {-4.0f, 0.0f, 1.0f}, {8.0f, 0.0f, 0.0f},
                                 {0.0f, 0.0f, -8.0f}, tiles, tiles));
    const double pitch = pitch_deg * M_PI / 180.0;
    s.camera.eye = {0.1f, static_cast<float>(eye), 0.0f};
    s.camera.target = {0.1f, static_cast<float>(eye - std::sin(pitch)),
                       static_cast<float>(-std::cos(pitch))};
    s.camera.fov_y_deg = 40.0f;
    s.camera.near_plane = 0.01f;
    s.camera.far_plane = 20.0f;
    s.light.kind = LightKind::None;
    return s;
}

// The scene's truth at the default lattice, tessellated for r's w x h view and drawn by its raster.
struct Truth {
    Tessellation tess;
    GeometryFrame frame;
};
Truth draw_truth(FrameRenderer& r, const Scene& scene, const std::vector<LoadedMaterial>& table,
                 int w, int h) {
    TessellationOptions options;
    options.width = w;
    options.height = h;
    Truth t;
    t.tess = displace_scene(scene, table, options);
    t.frame = r.render_geometry(t.tess.scene, 1);
    return t;
}

TEST(Renderer, TruthFlatQuadEqualsExactWithinItsBound) {
    std::vector<FlatCase> cases;
    cases.push_back({"sines, wrap",
                     make_map(32, 32,
                              [](int i, int j) {
                                  return 0.5f + 0.35f * std::sin(0.6f * i) * std::cos(0.4f * j);
                              }),
                     AddressMode::Wrap, 0.05f, 1.0f, 40.0});
    cases.push_back({"noise, clamp, r=0.5",
                     make_map(24, 20,
                              [](int i, int j) {
                                  return 0.5f + 0.4f * std::sin(float(i * 7 + j * 13)) *
                                                    std::cos(float(i * 3 - j * 5));
                              }),
                     AddressMode::Clamp, 0.004f, 0.5f, 25.0, 0.35, 1.0f});
    cases.push_back(
        {"blocks, wrap, to the horizon",
         make_map(16, 16, [](int i, int j) { return (i / 4 + j / 4) % 2 ? 0.9f : 0.2f; }),
         AddressMode::Wrap, 0.03f, 1.0f, 12.0, 0.04});
    for (const FlatCase& c : cases) {
        SCOPED_TRACE(c.name);
        const Scene scene = flat_scene(c.elevation_deg, c.eye_height, c.tiles);
        const std::vector<LoadedMaterial> table = {material(c)};
        const int w = 160, h = 120;
        FrameRenderer r(runtime(), scene, table, {resolve_params(find_method("exact"), {})}, w, h,
                        ShadeSettings{});
        const FrameRun run = r.render(FrameMode::Deferred, false, 1);
        const auto [tess, truth] = draw_truth(r, scene, table, w, h);
        ASSERT_EQ(tess.meshes.size(), 1u);
        EXPECT_GT(tess.meshes[0].triangles, 400u);
        const EngineScene& base = r.gbuffer();
        const std::vector<float> bound =
            truth_bound_texels(r.explicit_gbuffer(), base.material, table, tess);
        // Away from the quad's far edge (the tangent plane goes on, the quad does not) and where
        // the pass traced the view as it is (the grazing rule raises views below its minimum).
        const std::vector<std::uint8_t> band =
            silhouette_band(base.material, base.depth, run.offset.flags, w, h);
        size_t compared = 0, grazing = 0;
        double worst = 0.0, worst_bound = 0.0;
        for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k) {
            if (band[k] || base.depth[k] >= 1.0f || truth.depth[k] >= 1.0f) continue;
            if (run.offset.flags[k] & OM_FLAG_GRAZING) {
                ++grazing;
                continue;
            }
            ASSERT_EQ(truth.material[k], 1.0f) << k;
            ASSERT_TRUE(traced(run.offset.flags[k])) << k;
            ASSERT_TRUE(std::isfinite(bound[k])) << k;
            const double du = (run.offset.uv[k].s[0] - truth.uv[2 * k]) * c.map.width,
                         dv = (run.offset.uv[k].s[1] - truth.uv[2 * k + 1]) * c.map.height;
            const double e = std::hypot(du, dv);
            ASSERT_LE(e, bound[k] + kFloatTexels)
                << "pixel (" << k % w << ", " << k / w << "): truth (" << truth.uv[2 * k] << ", "
                << truth.uv[2 * k + 1] << "), exact (" << run.offset.uv[k].s[0] << ", "
                << run.offset.uv[k].s[1] << ")";
            worst = std::max(worst, e);
            worst_bound = std::max(worst_bound, double(bound[k]));
            ++compared;
        }
        EXPECT_GT(compared, static_cast<size_t>(w) * h / 3);
        std::printf(
            "%s: %zu triangles, %zu pixels compared (%zu grazing skipped), worst |truth - exact| "
            "%.4f texels, largest bound %.4f\n",
            c.name, tess.triangles, compared, grazing, worst, worst_bound);
        const std::string key(c.name, std::strcspn(c.name, ","));
        record_figure("truth.flat." + key + ".worst_texels", worst);
        record_figure("truth.flat." + key + ".bound_texels", worst_bound);
    }
}

// A directional light's view of the flat quad (orthographic, light_camera) through the deferred
// passes is the displaced shadow map: each pixel's exact hit on the truth's uv within its bound,
// and its depth after the offset the truth's own depth along the same ray. Two hits whose
// footprints lie e texels apart are e t_w / cos(elevation) apart along the light's ray (t_w the
// texel's world size), which window depth spreads over the far - near planes.
TEST(Renderer, LightViewOfAFlatQuadIsItsDisplacedShadowMap) {
    const FlatCase c{"sines, wrap",
                     make_map(32, 32,
                              [](int i, int j) {
                                  return 0.5f + 0.35f * std::sin(0.6f * i) * std::cos(0.4f * j);
                              }),
                     AddressMode::Wrap,
                     0.05f,
                     1.0f,
                     0.0,
                     0.35,
                     4.0f};
    Scene scene = flat_scene(40.0, c.eye_height, c.tiles);
    const double elevation = 35.0 * M_PI / 180.0, azimuth = 30.0 * M_PI / 180.0;
    scene.camera = light_camera(
        scene, {float(std::cos(elevation) * std::cos(azimuth)), float(std::sin(elevation)),
                float(std::cos(elevation) * std::sin(azimuth))});
    ASSERT_TRUE(scene.camera.orthographic);
    EXPECT_TRUE(contains(error_of([&] {
                             light_camera(scene, {0.0f, 0.0f, 0.0f});
                         }),
                         "not the zero vector"));
    const std::vector<LoadedMaterial> table = {material(c)};
    const int w = 192, h = 192;
    FrameRenderer r(runtime(), scene, table, {resolve_params(find_method("exact"), {})}, w, h,
                    ShadeSettings{});
    const FrameRun run = r.render(FrameMode::Deferred, false, 1);
    EXPECT_TRUE(r.gbuffer().camera.orthographic);
    const auto [tess, truth] = draw_truth(r, scene, table, w, h);
    const EngineScene& base = r.gbuffer();
    const std::vector<float> bound =
        truth_bound_texels(r.explicit_gbuffer(), base.material, table, tess);
    const std::vector<std::uint8_t> band =
        silhouette_band(base.material, base.depth, run.offset.flags, w, h);
    const double texel_m = 8.0 / c.tiles / c.map.width;  // the quad: 8 m, tiles uv across
    const double depth_range = scene.camera.far_plane - scene.camera.near_plane;
    size_t compared = 0;
    double worst_depth = 0.0;
    for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k) {
        if (band[k] || base.depth[k] >= 1.0f || truth.depth[k] >= 1.0f) continue;
        ASSERT_TRUE(traced(run.offset.flags[k])) << k;
        const double du = (run.offset.uv[k].s[0] - truth.uv[2 * k]) * c.map.width,
                     dv = (run.offset.uv[k].s[1] - truth.uv[2 * k + 1]) * c.map.height;
        const double e = std::hypot(du, dv), allowed = bound[k] + kFloatTexels;
        ASSERT_LE(e, allowed) << "pixel (" << k % w << ", " << k / w << ")";
        // Float depth: the matrices' and the point's rounding, a few 1e-7 of the range.
        const double depth_allowed = allowed * texel_m / std::cos(elevation) / depth_range + 2e-6;
        const double de = std::abs(double(run.depth_after[k]) - truth.depth[k]);
        ASSERT_LE(de, depth_allowed) << "pixel (" << k % w << ", " << k / w << ")";
        EXPECT_GT(std::abs(double(run.depth_after[k]) - base.depth[k]), 0.0) << k;
        worst_depth = std::max(worst_depth, de * depth_range);
        ++compared;
    }
    // The quad fills 28 % of the view (its 64 m^2 at sin 35 degrees in the bounding sphere's
    // square).
    EXPECT_GT(compared, static_cast<size_t>(w) * h / 5);
    std::printf("light view: %zu pixels compared, worst depth against the truth %.2e m\n", compared,
                worst_depth);
    // A single-sided wall the light sees from behind (facing -x, the light from +x) still casts:
    // the light's view keeps back faces.
    Scene walled = scene;
    walled.meshes.push_back(make_quad("wall", 2, {2.0f, 0.0f, -5.0f}, {0.0f, 0.0f, 2.0f},
                                      {0.0f, 2.0f, 0.0f}, 1.0f, 1.0f));
    walled.camera = light_camera(walled, {1.0f, 0.6f, 0.0f});
    std::vector<LoadedMaterial> two = table;
    two.push_back(table[0]);
    two[1].spec.id = 2;
    FrameRenderer lw(
        runtime(), walled, two,
        {resolve_params(find_method("exact"), {}), resolve_params(find_method("exact"), {})}, 64,
        64, ShadeSettings{});
    lw.render(FrameMode::Deferred, false, 1);
    const std::vector<float>& ids = lw.gbuffer().material;
    EXPECT_GT(std::count(ids.begin(), ids.end(), 2.0f), 16)
        << "the wall's back in the light's view";
    Scene forward = scene;
    FrameRenderer f(runtime(), forward, table, {resolve_params(find_method("exact"), {})}, 8, 8,
                    ShadeSettings{});
    EXPECT_TRUE(contains(error_of([&] { f.render(FrameMode::Forward, false, 1); }),
                         "perspective views only"));
}

// A spot light's shadow map (its perspective view, spot_camera): a box of half a metre's side
// over a flat floor under a spot 2 m up. Every floor pixel inside the cone whose segment to the
// light crosses the box shrunk by 3 cm is in shadow, and every one whose segment misses it grown
// by 3 cm is lit (the margin: the map's texels, about 3 mm at the box, and the filter's 3 x 3);
// the box's own box of texels bounds no point behind the light (none here: all lie in front).
TEST(Renderer, ASpotLightsMapShadowsWhatItsOccluderHides) {
    Scene scene;
    scene.name = "spot";
    scene.meshes.push_back(make_quad("floor", 1, {-2.0f, 0.0f, 1.0f}, {4.0f, 0.0f, 0.0f},
                                     {0.0f, 0.0f, -4.0f}, 4.0f, 4.0f));
    const glm::dvec3 centre(0.0, 0.5, -1.0);
    scene.meshes.push_back(make_box("box", 0, {0.0f, 0.5f, -1.0f}, {0.25f, 0.25f, 0.25f}, 1.0f));
    scene.camera.eye = {0.0f, 2.5f, 2.0f};
    scene.camera.target = {0.0f, 0.0f, -1.0f};
    scene.camera.fov_y_deg = 50.0f;
    const glm::dvec3 lamp(0.3, 2.0, -0.8);
    scene.light.kind = LightKind::Spot;
    scene.light.vector = {0.3f, 2.0f, -0.8f};
    scene.light.axis = {-0.1f, -1.0f, 0.0f};
    scene.light.cone_inner = 0.45f;
    scene.light.cone_outer = 0.6f;
    LoadedMaterial floor;
    floor.spec.id = 1;
    floor.spec.name = "flat";
    floor.spec.method = "exact";
    floor.spec.settings.scale = 0.05f;
    floor.map = make_map(8, 8, [](int, int) { return 1.0f; });
    const int w = 160, h = 120;
    FrameRenderer r(runtime(), scene, {floor}, {resolve_params(find_method("exact"), {})}, w, h,
                    ShadeSettings{});
    ShadowMapSettings map;
    map.size = 512;
    r.set_shadow_map(map);
    const FrameRun run = r.render(FrameMode::Deferred, false, 1);
    EXPECT_EQ(run.light_draws, run.frames);
    const std::array<float, 16>& vp = r.view_projection();
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
        for (int k = 0; k < 4; ++k) m[c][k] = vp[4 * c + k];
    const glm::dmat4 inverse = glm::inverse(m);
    // Whether the segment from p to the lamp crosses the box grown by `margin` (slabs).
    auto hidden = [&](const glm::dvec3& p, double margin) {
        const glm::dvec3 d = lamp - p;
        double t0 = 0.0, t1 = 1.0;
        for (int a = 0; a < 3; ++a) {
            const double lo = centre[a] - 0.25 - margin, hi = centre[a] + 0.25 + margin;
            if (std::abs(d[a]) < 1e-12) {
                if (p[a] < lo || p[a] > hi) return false;
                continue;
            }
            double ta = (lo - p[a]) / d[a], tb = (hi - p[a]) / d[a];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta), t1 = std::min(t1, tb);
        }
        return t0 <= t1;
    };
    const glm::dvec3 axis = glm::normalize(glm::dvec3(-0.1, -1.0, 0.0));
    size_t shadowed = 0, lit = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = size_t(y) * w + x;
            if (run.material[k] != 1.0f) continue;
            const glm::dvec4 q = inverse * glm::dvec4((2.0 * x + 1) / w - 1, 1 - (2.0 * y + 1) / h,
                                                      2.0 * run.depth_after[k] - 1.0, 1.0);
            const glm::dvec3 p = glm::dvec3(q) / q.w;
            if (glm::dot(glm::normalize(p - lamp), axis) < std::cos(0.6)) continue;
            if (hidden(p, -0.03)) {
                ++shadowed;
                ASSERT_LT(run.shadow_mask[k], 0.5f) << "hidden from the spot at pixel " << k;
            } else if (!hidden(p, 0.03)) {
                ++lit;
                ASSERT_GT(run.shadow_mask[k], 0.5f) << "in the spot's light at pixel " << k;
            }
        }
    std::printf("spot map: %zu floor pixels in the box's shadow, %zu lit, in its cone\n", shadowed,
                lit);
    EXPECT_GT(shadowed, 100u);
    EXPECT_GT(lit, 2000u);
}

// Relief that shadows itself: a quad of sines under a sun at 20 degrees. The displaced shadow map
// shadows what the displaced quad's own map shadows (renderer::shadow_truth: its tessellation
// drawn from the same light at the same size and tested with the same filter): a pixel counts as
// a mismatch where the two lit fractions differ by half or more. The flat map (the base quad,
// which shadows nothing) misses every self-shadowed pixel; the target is at most a fifth of its
// mismatch. Without a map the frame comes out as before, bit for bit.
TEST(Renderer, ADisplacedShadowMapShadowsWhatTheDisplacedMeshShadows) {
    const FlatCase c{"sines, wrap",
                     make_map(32, 32,
                              [](int i, int j) {
                                  return 0.5f + 0.45f * std::sin(0.6f * i) * std::cos(0.4f * j);
                              }),
                     AddressMode::Wrap,
                     0.08f,
                     1.0f,
                     35.0,
                     0.6,
                     4.0f};
    Scene scene = flat_scene(c.elevation_deg, c.eye_height, c.tiles);
    const double elevation = 20.0 * M_PI / 180.0, azimuth = 60.0 * M_PI / 180.0;
    const std::array<float, 3> toward = {float(std::cos(elevation) * std::cos(azimuth)),
                                         float(std::sin(elevation)),
                                         float(std::cos(elevation) * std::sin(azimuth))};
    const std::vector<LoadedMaterial> table = {material(c)};
    const std::vector<MethodParams> methods = {resolve_params(find_method("exact"), {})};
    const int w = 192, h = 108, size = 512;
    {
        FrameRenderer point(runtime(), scene, table, methods, 8, 8, ShadeSettings{});
        EXPECT_TRUE(
            contains(error_of([&] { point.set_shadow_map(ShadowMapSettings()); }), "directional"));
    }
    scene.light = {LightKind::Directional, toward};
    FrameRenderer r(runtime(), scene, table, methods, w, h, ShadeSettings{});
    const FrameRun plain = r.render(FrameMode::Deferred, false, 1);
    EXPECT_TRUE(plain.shadow_mask.empty());
    ShadowMapSettings map;
    map.size = size;
    EXPECT_TRUE(contains(error_of([&] {
                             ShadowMapSettings bad = map;
                             bad.size = 8;
                             r.set_shadow_map(bad);
                         }),
                         "size"));
    EXPECT_TRUE(contains(error_of([&] { r.light_maps(); }), "no shadow map drawn"));
    r.set_shadow_map(map);
    const FrameRun displaced = r.render(FrameMode::Deferred, false, 1);
    {
        // The map the frame drew: the relief moves the light's depth away from it, never toward.
        const LightMaps maps = r.light_maps();
        ASSERT_EQ(maps.size, size);
        ASSERT_EQ(maps.base.size(), size_t(size) * size);
        ASSERT_EQ(maps.displaced.size(), maps.base.size());
        size_t covered = 0, moved = 0;
        for (size_t k = 0; k < maps.base.size(); ++k) {
            if (maps.base[k] >= 1.0f) continue;
            ++covered;
            moved += maps.displaced[k] > maps.base[k];
            ASSERT_GE(maps.displaced[k], maps.base[k]) << k;
        }
        EXPECT_GT(covered, maps.base.size() / 10);
        EXPECT_GT(moved, covered / 2);
    }
    map.displaced = false;
    r.set_shadow_map(map);
    const FrameRun flat = r.render(FrameMode::Deferred, false, 1);
    // The light's view is drawn once a frame (the warm-up's included), and never without a map.
    EXPECT_EQ(plain.light_draws, 0);
    EXPECT_EQ(displaced.frames, 2);
    EXPECT_EQ(displaced.light_draws, displaced.frames);
    EXPECT_EQ(flat.light_draws, flat.frames);
    r.set_shadow_map(std::nullopt);
    const FrameRun again = r.render(FrameMode::Deferred, false, 1);
    ASSERT_EQ(again.color.size(), plain.color.size());
    EXPECT_EQ(
        std::memcmp(again.color.data(), plain.color.data(), plain.color.size() * sizeof(cl_float4)),
        0)
        << "no map, no change";

    const ShadowTruth t = shadow_truth(runtime(), r, scene, table, methods, w, h, size,
                                       ShadowMapSettings().pcf_radius, 0.5f);
    size_t truth_shadowed = 0, flat_shadowed = 0;
    for (size_t k = 0; k < t.lit.size(); ++k) {
        truth_shadowed += t.lit[k] < 0.5f;
        flat_shadowed += flat.depth_after[k] < 1.0f && flat.light_visibility[k] < 0.5f;
    }
    EXPECT_EQ(flat_shadowed, 0u) << "a flat quad casts nothing on itself";
    const ShadowMismatch mf = shadow_mismatch(t, flat.light_visibility, flat.depth_after, toward);
    const ShadowMismatch md =
        shadow_mismatch(t, displaced.light_visibility, displaced.depth_after, toward);
    std::printf(
        "self-shadows at 20 degrees: %zu of %zu pixels shadowed in the truth; mismatch flat %zu, "
        "displaced %zu\n",
        truth_shadowed, mf.compared, mf.mismatch, md.mismatch);
    EXPECT_GT(truth_shadowed, mf.compared / 20) << "the relief shadows itself";
    EXPECT_EQ(mf.mismatch, truth_shadowed);
    EXPECT_LE(5 * md.mismatch, mf.mismatch);
    // The visibility the shading used is the map's test (no march).
    for (size_t k = 0; k < displaced.shadow_mask.size(); ++k) {
        if (displaced.depth_after[k] < 1.0f) {
            ASSERT_EQ(displaced.light_visibility[k], displaced.shadow_mask[k]) << k;
        }
    }
}

// One relief mesh of a constant height 0.6 with scale 0.05 and reference r, seen by a 160 x 120
// view; `inside` says whether a point is on the part the test judges and gives its distance from
// the axis or centre, which must lie in [lo(r), hi(r)].
struct RadialCase {
    const char* name;
    Scene scene;
    double density;  // of the judged part
    std::function<bool(const glm::dvec3&, double&)> inside;
    std::function<void(double d, double& lo, double& hi)> range;
};

void expect_displaced_radially(const RadialCase& rc) {
    for (const float reference : {1.0f, 0.4f}) {
        SCOPED_TRACE(reference);
        FlatCase c{"constant",        make_map(16, 16, [](int, int) { return 0.6f; }),
                   AddressMode::Wrap, 0.05f,
                   reference,         0.0};
        const std::vector<LoadedMaterial> table = {material(c)};
        const int w = 160, h = 120;
        FrameRenderer r(runtime(), rc.scene, table, {resolve_params(find_method("none"), {})}, w, h,
                        ShadeSettings{});
        r.render(FrameMode::Deferred, false, 1);
        const GeometryFrame truth = draw_truth(r, rc.scene, table, w, h).frame;
        const double d = rc.density * c.scale * (0.6 - reference);
        double lo = 0.0, hi = 0.0;
        rc.range(d, lo, hi);
        size_t judged = 0;
        double seen_lo = INFINITY, seen_hi = -INFINITY;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t k = static_cast<size_t>(y) * w + x;
                if (truth.depth[k] >= 1.0f) continue;
                double radial = 0.0;
                if (!rc.inside(unproject(r.gbuffer(), x, y, truth.depth[k]), radial)) continue;
                ASSERT_GE(radial, lo) << "pixel (" << x << ", " << y << ")";
                ASSERT_LE(radial, hi) << "pixel (" << x << ", " << y << ")";
                seen_lo = std::min(seen_lo, radial);
                seen_hi = std::max(seen_hi, radial);
                ++judged;
            }
        EXPECT_GT(judged, static_cast<size_t>(w) * h / 10);
        std::printf("%s, r=%.1f: d = %.4f m; %zu pixels at [%.5f, %.5f] m, within [%.5f, %.5f]\n",
                    rc.name, reference, d, judged, seen_lo, seen_hi, lo, hi);
    }
}

// A cylinder of N segments with a constant height: the base mesh's side has its points at
// distance |P| in [R cos(pi / N), R] from the axis, and P's interpolated normal points straight
// away from the axis (P and the normal are the same blend of the two vertices' radial
// directions), so the displaced side lies at |P| + d, d = density s (H - r), exactly; a point of a
// sub-triangle lies between its corners' radii, less the chord's sag over its angle.
TEST(Renderer, TruthCylinderOfConstantHeightIsTheDisplacedCylinder) {
    const float R = 0.45f, tall = 1.2f;
    const int N = 64;
    const float tiles_u = 1.0f;
    const double density = 2 * M_PI * R / tiles_u;  // uniform: v tiles at the same world size
    RadialCase rc{"cylinder", {}, density, nullptr, nullptr};
    rc.scene.name = "cylinder";
    rc.scene.meshes.push_back(make_cylinder("cylinder", 1, {0.0f, 0.0f, -2.0f}, R, tall, N, tiles_u,
                                            static_cast<float>(tall / density)));
    rc.scene.camera = looking_at({0.3f, 0.9f, 0.0f}, {0.0f, 0.6f, -2.0f});
    rc.scene.light.kind = LightKind::None;
    rc.inside = [&](const glm::dvec3& p, double& radial) {
        radial = std::hypot(p.x, p.z + 2.0);
        return p.y >= 0.05 && p.y <= tall - 0.1;  // not the caps and their rims
    };
    rc.range = [&](double d, double& lo, double& hi) {
        const double cell_angle = 2 * M_PI / (tiles_u * 16 / 0.5);
        const double sag = (R + std::fabs(d)) * cell_angle * cell_angle / 8;
        lo = R * std::cos(M_PI / N) + d - sag - 1e-4;
        hi = R + d + 1e-4;
    };
    expect_displaced_radially(rc);
}

// A uv sphere given one uv density everywhere (a uv sphere's own density falls toward the poles):
// its vertex normals are P / R, so the interpolated normal is P / |P| and the displaced surface
// lies at |P| + d from the centre, |P| at least R cos(psi) on a base triangle whose corners lie
// within the angle psi of a point (half its cell's diagonal), and a lattice piece of the
// displaced surface sags by at most cos(psi') of its own half-diagonal psi'.
TEST(Renderer, TruthSphereOfConstantHeightAndDensityIsTheDisplacedSphere) {
    const float R = 0.5f;
    const int segments = 48, rings = 24;
    const float tiles_u = 2.0f, tiles_v = 1.0f;
    RadialCase rc{"sphere", {}, M_PI * R / tiles_v, nullptr, nullptr};
    rc.scene.name = "sphere";
    Mesh sphere =
        make_sphere("sphere", 1, {0.0f, 0.0f, -2.0f}, R, segments, rings, tiles_u, tiles_v);
    for (Vertex& v : sphere.vertices) v.uv_density = static_cast<float>(rc.density);
    rc.scene.meshes.push_back(std::move(sphere));
    rc.scene.camera = looking_at({0.4f, 0.7f, -0.3f}, {0.0f, 0.0f, -2.0f});
    rc.scene.light.kind = LightKind::None;
    rc.inside = [&](const glm::dvec3& p, double& radial) {
        radial = glm::length(p - glm::dvec3(0.0, 0.0, -2.0));
        return true;
    };
    rc.range = [&](double d, double& lo, double& hi) {
        const double base_psi = 0.5 * std::hypot(2 * M_PI / segments, M_PI / rings);
        const double piece_psi =
            0.5 * std::hypot(2 * M_PI / (tiles_u * 16 / 0.5), M_PI / (tiles_v * 16 / 0.5));
        lo = (R * std::cos(base_psi) + d) * std::cos(piece_psi) - 1e-4;
        hi = R + d + 1e-4;
    };
    expect_displaced_radially(rc);
}

// Where the uv stretch differs between u and v the truth displaces by the geometric mean of the
// two (the density) and moves along the surface in world units, while the pass moves |V.xy| / V.z
// in uv units of that same density: from the base hit P0 to the displaced plane's hit P1 (D = P1 -
// P0) the truth's uv moves (T.D / su, B.D / sv) and the pass's (T.D, B.D) / sqrt(su sv). A flat
// quad of a constant height, stretched k times along u against v, checks both and says what the
// difference costs in texels.
TEST(Renderer, TruthOfAnUnevenlyStretchedQuadMovesInWorldUnits) {
    const float side = 8.0f, H = 0.6f, scale = 0.05f;
    const int texels = 16;
    for (const float k : {1.0f, 2.0f, 4.0f}) {
        SCOPED_TRACE(k);
        const float tiles_u = 8.0f, tiles_v = 8.0f * k;  // su = k sv
        const double su = side / tiles_u, sv = side / tiles_v, density = std::sqrt(su * sv);
        FlatCase c{"constant",
                   make_map(texels, texels, [&](int, int) { return H; }),
                   AddressMode::Wrap,
                   scale,
                   1.0f,
                   0.0};
        Scene scene;
        scene.name = "stretched";
        scene.meshes.push_back(make_quad("floor", 1, {-4.0f, 0.0f, 1.0f}, {side, 0.0f, 0.0f},
                                         {0.0f, 0.0f, -side}, tiles_u, tiles_v));
        // Looking down 35 degrees and to the side, so the ray leans along u and v.
        scene.camera = looking_at({-1.0f, 1.4f, 0.0f}, {0.4f, 0.0f, -1.6f});
        scene.light.kind = LightKind::None;
        const std::vector<LoadedMaterial> table = {material(c)};
        const int w = 160, h = 120;
        FrameRenderer r(runtime(), scene, table, {resolve_params(find_method("exact"), {})}, w, h,
                        ShadeSettings{});
        const FrameRun run = r.render(FrameMode::Deferred, false, 1);
        const GeometryFrame truth = draw_truth(r, scene, table, w, h).frame;
        const EngineScene& base = r.gbuffer();
        const double d = density * scale * (H - 1.0);
        auto uv_of = [&](const glm::dvec3& p) {
            return glm::dvec2((p.x + 4.0) / su, (1.0 - p.z) / sv);
        };
        std::vector<double> costs;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t i = static_cast<size_t>(y) * w + x;
                if (base.depth[i] >= 1.0f || truth.depth[i] >= 1.0f) continue;
                if (run.offset.flags[i] & OM_FLAG_GRAZING) continue;
                const glm::dvec3 p0 = unproject(base, x, y, base.depth[i]);
                const glm::dvec3 eye(scene.camera.eye[0], scene.camera.eye[1], scene.camera.eye[2]);
                const glm::dvec3 p1 = eye + (p0 - eye) * ((eye.y - d) / (eye.y - p0.y));
                if (std::fabs(p1.x) > 3.5 || p1.z > 0.5 || p1.z < -6.5) continue;  // the edges
                const glm::dvec3 D = p1 - p0;
                const glm::dvec2 want_truth = uv_of(p1);
                const glm::dvec2 want_pass = uv_of(p0) + glm::dvec2(D.x, -D.z) / density;
                const glm::dvec2 got_truth(truth.uv[2 * i], truth.uv[2 * i + 1]);
                const glm::dvec2 got_pass(run.offset.uv[i].s[0], run.offset.uv[i].s[1]);
                ASSERT_LE(glm::length(got_truth - want_truth) * texels, kFloatTexels)
                    << "pixel (" << x << ", " << y << ")";
                ASSERT_LE(glm::length(got_pass - want_pass) * texels, kFloatTexels)
                    << "pixel (" << x << ", " << y << ")";
                costs.push_back(glm::length(got_pass - got_truth) * texels);
            }
        ASSERT_GT(costs.size(), static_cast<size_t>(w) * h / 4);
        std::sort(costs.begin(), costs.end());
        const double p95 = costs[costs.size() * 95 / 100], worst = costs.back();
        if (k == 1.0f) {
            EXPECT_LE(worst, 2 * kFloatTexels);
        }
        std::printf("stretch %.0f:1: pass against truth p95 %.4f, max %.4f texels (%zu pixels)\n",
                    k, p95, worst, costs.size());
        record_figure("truth.stretch" + std::to_string(int(k)) + ".p95_texels", p95);
    }
}

// Bad input: a lattice the tessellation cannot take, and a mesh past the triangle limit, named.
TEST(Renderer, TruthRefusesWhatItCannotTessellate) {
    FlatCase c{"ramp",
               make_map(16, 16, [](int i, int) { return i / 16.0f; }),
               AddressMode::Wrap,
               0.05f,
               1.0f,
               30.0};
    const Scene scene = flat_scene(30.0);
    const std::vector<LoadedMaterial> table = {material(c)};
    TessellationOptions o;
    auto error = [&]() -> std::string {
        try {
            displace_scene(scene, table, o);
        } catch (const Error& e) {
            return e.what();
        }
        return "(no error)";
    };
    o.texels_per_quad = 0.3f;
    EXPECT_NE(error().find("1 / texels per quad must be whole"), std::string::npos) << error();
    o.texels_per_quad = 0.25f;
    o.max_triangles = 1000;
    EXPECT_NE(error().find("mesh 'floor' would need about"), std::string::npos) << error();
    // Unculled, the 2.1 million triangles the estimate gives are all kept: a limit of half that
    // passes the estimate (20 times the limit) and stops the tessellation on the way.
    o.max_triangles = 1'050'000;
    EXPECT_NE(error().find("mesh 'floor' needs more than"), std::string::npos) << error();
}
// The frame with the curvature plane (FrameRenderer::set_curvature) on a cylinder standing on a
// floor, the relief a smooth map: on the floor (K = 0) every pixel is the plane frame's bit for
// bit; on the cylinder's interior the uv error against the displaced mesh falls at least 5x (the
// curved trace is the relief over the cylinder's circle, exact there; the tangent plane's error
// grows with the arc the ray runs over the bending base). Twice: the cylinder's uv with one density
// both ways, and stretched 1.3:1 (the trace's lengths are then the stretch's, not the uv's).
TEST(Renderer, CurvedFrameMeetsTheDisplacedCylinder) {
    for (const double stretch : {1.0, 1.3}) {
        SCOPED_TRACE(stretch);
        const float R = 0.45f, tall = 1.2f, tiles_u = 2.0f;
        const double per_u = 2 * M_PI * R / tiles_u;  // world per u; per v it is per_u / stretch^2
        Scene scene;
        scene.name = "cylinder";
        scene.meshes.push_back(make_cylinder("cylinder", 1, {0.0f, 0.0f, -2.0f}, R, tall, 96,
                                             tiles_u,
                                             static_cast<float>(tall * stretch * stretch / per_u)));
        scene.meshes.push_back(make_quad("floor", 1, {-2.0f, 0.0f, 0.0f}, {4.0f, 0.0f, 0.0f},
                                         {0.0f, 0.0f, -4.0f}, 4.0f, 4.0f));
        scene.camera = looking_at({0.3f, 1.3f, 0.0f}, {0.0f, 0.6f, -2.0f});
        scene.light.kind = LightKind::None;
        FlatCase c{"smooth", smooth_map(64), AddressMode::Wrap, 0.06f, 1.0f, 0.0};
        const std::vector<LoadedMaterial> table = {material(c)};
        const int w = 320, h = 240;
        FrameRenderer r(runtime(), scene, table, {resolve_params(find_method("exact"), {})}, w, h,
                        ShadeSettings{});
        const FrameRun plane = r.render(FrameMode::Deferred, false, 1);
        r.set_curvature(true);
        const FrameRun curved = r.render(FrameMode::Deferred, false, 1);
        ASSERT_TRUE(curved.curved);
        const EngineScene& e = r.gbuffer();
        const GeometryFrame truth = draw_truth(r, scene, table, w, h).frame;
        const std::vector<std::uint8_t> band =
            silhouette_band(e.material, e.depth, plane.offset.flags, w, h);
        std::vector<double> errors[2];
        size_t floor_pixels = 0;
        for (int m = 0; m < 2; ++m) {
            const FrameRun& run = m ? curved : plane;
            const ShownFrame shown{"run", &e.material, &run.offset.uv, &run.depth_after,
                                   &run.offset.flags};
            const TruthComparison cmp =
                compare_to_truth(truth, shown, r.explicit_gbuffer(), e.depth, e.normal, band, table,
                                 e.camera.inverse_view_projection, w, h);
            for (size_t k = 0; k < cmp.uv_error.size(); ++k) {
                if (e.depth[k] >= 1.0f) continue;
                if (std::fabs(e.normal[4 * k + 1]) > 0.99f) {  // floor and cap: no curvature
                    floor_pixels += m;
                    ASSERT_EQ(
                        std::memcmp(&plane.offset.uv[k], &curved.offset.uv[k], sizeof(cl_float2)),
                        0);
                    ASSERT_EQ(plane.offset.flags[k], curved.offset.flags[k]);
                } else if (!band[k] && std::isfinite(cmp.uv_error[k])) {
                    errors[m].push_back(cmp.uv_error[k]);
                }
            }
        }
        ASSERT_GT(floor_pixels, static_cast<size_t>(w) * h / 10);
        ASSERT_GT(errors[0].size(), static_cast<size_t>(w) * h / 20);
        const ErrorStats p = error_stats(errors[0]), q = error_stats(errors[1]);
        std::printf(
            "cylinder interior, uv stretch %.1f, uv p95 vs the displaced mesh: plane %.3f, curved "
            "%.3f texels\n",
            stretch, p.p95, q.p95);
        EXPECT_LE(q.p95, p.p95 / 5.0);
    }
}

// A sphere in bricks over a floor, pom traced over the curved base both ways: the forward peer
// (curvature in its fragment shader, the rays that leave discarded) and the deferred frame show
// the same pixels. With a depth pre-pass forward leaves empty the pixels the one-layer deferred
// frame flags SILHOUETTE; without one it draws what lies behind them, which the two-layer deferred
// frame shows: the same material (the floor) and uv' within 0.05 texel there. Agreement on 98 %
// of those pixels at least (V from the fragment's position against V reconstructed from depth:
// a ray that grazes a crest may be decided either way).
struct SphereOverFloor {
    Scene scene;
    std::vector<LoadedMaterial> table;
    MethodParams pom = resolve_params(find_method("pom"), {});
};

SphereOverFloor sphere_over_floor() {
    SphereOverFloor s;
    s.scene.name = "sphere";
    s.scene.meshes.push_back(
        make_sphere("sphere", 1, {0.0f, 0.55f, -2.0f}, 0.5f, 64, 32, 8.0f, 4.0f));
    s.scene.meshes.push_back(make_quad("floor", 2, {-3.0f, 0.0f, 1.0f}, {6.0f, 0.0f, 0.0f},
                                       {0.0f, 0.0f, -6.0f}, 6.0f, 6.0f));
    s.scene.camera = looking_at({0.2f, 1.4f, 0.0f}, {0.0f, 0.5f, -2.0f});
    s.scene.light.kind = LightKind::None;
    FlatCase c{"smooth", smooth_map(64), AddressMode::Wrap, 0.08f, 1.0f, 0.0};
    LoadedMaterial bricks = material(c), floor = material(c);
    floor.spec.id = 2;
    floor.spec.settings.scale = 0.02f;
    s.table = {bricks, floor};
    return s;
}

TEST(Renderer, TwoLayersShowWhatTheForwardFrameShows) {
    const SphereOverFloor s = sphere_over_floor();
    const MethodParams& pom = s.pom;
    const int w = 240, h = 180;
    FrameRenderer r(runtime(), s.scene, s.table, {pom, pom}, w, h, ShadeSettings{});
    r.set_curvature(true);
    const FrameRun one = r.render(FrameMode::Deferred, false, 1);
    const std::vector<float> base_depth = r.gbuffer().depth;
    const FrameRun pre = r.render(FrameMode::Forward, true, 1);
    const FrameRun fwd = r.render(FrameMode::Forward, false, 1);
    r.set_layers(2);
    const FrameRun two = r.render(FrameMode::Deferred, false, 1);
    ASSERT_EQ(two.layers, 2);
    size_t left = 0, left_agree = 0, behind = 0, behind_agree = 0, near = 0;
    for (size_t k = 0; k < one.offset.flags.size(); ++k) {
        const bool silhouette = one.offset.flags[k] & OM_FLAG_SILHOUETTE;
        const bool dropped = base_depth[k] < 1.0f && (pre.offset.flags[k] & OM_FLAG_EMPTY);
        left += silhouette || dropped;
        left_agree += silhouette && dropped;
        if (!(two.offset.flags[k] & OM_FLAG_BEHIND)) continue;
        ++behind;
        if (two.material[k] != fwd.material[k]) continue;
        ++behind_agree;
        const double du = two.offset.uv[k].s[0] - fwd.offset.uv[k].s[0],
                     dv = two.offset.uv[k].s[1] - fwd.offset.uv[k].s[1];
        near += std::hypot(du, dv) * 64 <= 0.05;
    }
    std::printf(
        "sphere over a floor: %zu of %zu pixels left by the one-layer frame and dropped by "
        "forward with a pre-pass; %zu of %zu behind pixels the forward frame's material, "
        "%zu of them within 0.05 texel; %zu shown by neither\n",
        left_agree, left, behind_agree, behind, near, two.missed_pixels);
    ASSERT_GT(left, 100u);
    EXPECT_GE(left_agree, left * 98 / 100);
    EXPECT_GT(behind, left / 2);
    EXPECT_GE(behind_agree, behind * 98 / 100);
    EXPECT_GE(near, behind_agree * 98 / 100);
}

// The layer behind drawn, read and reconstructed only at the pixels the first layer left (a fresh
// renderer, so no earlier frame's planes stand in for the ones it reads) against the whole layer:
// the same frame bit for bit, its colour, depth, uv', flags and ids. And again in a renderer that
// drew the whole layer, then this one twice (the peel's depth closed after the whole layer, then
// the last frame's pixels closed again before the next).
TEST(Renderer, ALayerBehindDrawnWhereNeededIsTheWholeLayer) {
    const SphereOverFloor s = sphere_over_floor();
    const int w = 240, h = 180;
    std::vector<FrameRun> runs;
    for (bool whole : {false, true}) {
        FrameRenderer r(runtime(), s.scene, s.table, {s.pom, s.pom}, w, h, ShadeSettings{});
        r.set_curvature(true);
        r.set_layers(2, whole);
        runs.push_back(r.render(FrameMode::Deferred, false, 1));
    }
    {
        FrameRenderer r(runtime(), s.scene, s.table, {s.pom, s.pom}, w, h, ShadeSettings{});
        r.set_curvature(true);
        r.set_layers(2, true);
        r.render(FrameMode::Deferred, false, 1);
        r.set_layers(2);
        r.render(FrameMode::Deferred, false, 1);
        runs.push_back(r.render(FrameMode::Deferred, false, 1));
    }
    for (const FrameRun* again : {&runs[0], &runs[2]}) {
        const FrameRun &needed = *again, &whole = runs[1];
        std::printf("sphere over a floor: %zu pixels show the layer behind, %zu neither\n",
                    needed.behind_pixels, needed.missed_pixels);
        ASSERT_GT(needed.behind_pixels, 100u);
        EXPECT_EQ(needed.behind_pixels, whole.behind_pixels);
        EXPECT_EQ(needed.missed_pixels, whole.missed_pixels);
        const size_t n = static_cast<size_t>(w) * h;
        size_t differ = 0;
        for (size_t k = 0; k < n; ++k) {
            const bool same =
                std::memcmp(&needed.color[k], &whole.color[k], sizeof(cl_float4)) == 0 &&
                std::memcmp(&needed.offset.uv[k], &whole.offset.uv[k], sizeof(cl_float2)) == 0 &&
                std::memcmp(&needed.offset.depth[k], &whole.offset.depth[k], sizeof(float)) == 0 &&
                std::memcmp(&needed.depth_after[k], &whole.depth_after[k], sizeof(float)) == 0 &&
                needed.offset.flags[k] == whole.offset.flags[k] &&
                std::memcmp(&needed.material[k], &whole.material[k], sizeof(float)) == 0;
            if (!same && differ++ < 5) ADD_FAILURE() << "pixel " << k % w << ", " << k / w;
        }
        EXPECT_EQ(differ, 0u);
    }
}

// Where the base G-buffer shows another material than the one the truth and the frame both show
// (the frame's layer behind, or what a discarded fragment let through), the base says nothing of
// that surface: the two are the same surface when their points lie within the relief's depth of
// each other along the ray. Three pixels, identity view-projection (world = NDC), a wall seen
// edge-on as the base of the first two, material 1 the base of the third.
TEST(Renderer, CoverageBehindTheBaseComparesTheTwoSurfaces) {
    const int w = 3, h = 1;
    FlatCase c{"smooth", smooth_map(16), AddressMode::Wrap, 0.05f, 1.0f, 0.0};
    LoadedMaterial floor = material(c), wall = material(c);
    wall.spec.id = 2;
    const std::vector<LoadedMaterial> table = {floor, wall};
    GeometryFrame truth;
    truth.uv = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    truth.depth = {0.5f, 0.5f, 0.5f};
    truth.material = {1.0f, 1.0f, 1.0f};
    truth.density = {1.0f, 1.0f, 1.0f};
    truth.normal = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    const std::vector<float> ids = {1.0f, 1.0f, 1.0f};
    const std::vector<cl_float2> uv = {{{0.5f, 0.5f}}, {{0.5f, 0.5f}}, {{0.5f, 0.5f}}};
    // 0.02 apart in world z at the first pixel (within the reach 0.05 x 1.01 + 1e-4), 0.2 at the
    // second; the third as the truth.
    const std::vector<float> depth = {0.51f, 0.6f, 0.5f};
    const std::vector<std::uint32_t> flags = {OM_FLAG_BEHIND, OM_FLAG_BEHIND, 0u};
    const ShownFrame shown{"two layers", &ids, &uv, &depth, &flags};
    GBuffer base;
    base.resize(w, h, false, false);
    base.uv.assign(3, {{0.5f, 0.5f}});
    base.view.assign(3, {{0.0f, 0.0f, 1.0f, 0.0f}});
    base.material = {2.0f, 2.0f, 1.0f};
    const std::vector<float> base_depth = {0.5f, 0.5f, 0.5f};
    const std::vector<float> base_normal = {1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0};
    const std::array<float, 16> identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    const TruthComparison cmp =
        compare_to_truth(truth, shown, base, base_depth, base_normal,
                         std::vector<std::uint8_t>(3, 0), table, identity, w, h);
    EXPECT_EQ(cmp.mismatched, (std::vector<std::uint8_t>{0, 1, 0}));
    EXPECT_EQ(cmp.compared_pixels, 2u);
    EXPECT_FLOAT_EQ(cmp.uv_error[0], 0.0f);
}

// The tangent plane's one-layer frame, the curved two-layer frame without and with the uv metric
// (in that order), the first frame's G-buffer, the truth and the plane's silhouette band.
struct MetricFrames {
    FrameRun runs[3];
    EngineScene e;
    GBuffer base;
    GeometryFrame truth;
    std::vector<std::uint8_t> band;
};

MetricFrames render_metric_frames(FrameRenderer& r, const Scene& scene,
                                  const std::vector<LoadedMaterial>& table, int w, int h) {
    MetricFrames f;
    f.runs[0] = r.render(FrameMode::Deferred, false, 1);
    f.e = r.gbuffer();
    f.base = r.explicit_gbuffer();
    r.set_curvature(true);
    r.set_layers(2);
    f.runs[1] = r.render(FrameMode::Deferred, false, 1);
    r.set_uv_metric(true);
    f.runs[2] = r.render(FrameMode::Deferred, false, 1);
    f.truth = draw_truth(r, scene, table, w, h).frame;
    f.band = silhouette_band(f.e.material, f.e.depth, f.runs[0].offset.flags, w, h);
    return f;
}

// A run of those against the truth.
TruthComparison compare_metric_frame(const MetricFrames& f, const FrameRun& run,
                                     const std::vector<LoadedMaterial>& table, int w, int h) {
    const ShownFrame shown{"run", &run.material, &run.offset.uv, &run.depth_after,
                           &run.offset.flags};
    return compare_to_truth(f.truth, shown, f.base, f.e.depth, f.e.normal, f.band, table,
                            f.e.camera.inverse_view_projection, w, h);
}

// A uv sphere (96 x 48 quads, u twice around, v pole to pole) seen from above its equator up to
// its north pole, relief a quarter of the radius deep: the frame over the curved base with the
// uv metric (FrameRenderer::set_uv_metric) and two layers against the tangent plane's one-layer
// frame, measured on the displaced mesh. Interior uv p95 at least 5x lower and the silhouette
// band's coverage mismatch at least 10x lower, for exact and for pom 16/64 (the curved frame's
// targets); the curved frame without the metric is printed beside them.
TEST(Renderer, UvMetricFrameMeetsTheDisplacedUvSphere) {
    const float R = 0.5f;
    Scene scene;
    scene.name = "uv sphere";
    scene.meshes.push_back(make_sphere("sphere", 1, {0.0f, 0.0f, -2.0f}, R, 96, 48, 2.0f, 1.0f));
    scene.camera = looking_at({0.0f, 0.75f, -0.95f}, {0.0f, 0.0f, -2.0f});
    scene.light.kind = LightKind::None;
    // World depth s x density: a quarter of R at the equator, where the density is pi R.
    const float s = 0.25f * R / (float(M_PI) * R);
    FlatCase c{"smooth", smooth_map(64), AddressMode::Wrap, s, 1.0f, 0.0};
    const std::vector<LoadedMaterial> table = {material(c)};
    const int w = 256, h = 192;
    for (const MethodParams& method :
         {resolve_params(find_method("exact"), {}),
          resolve_params(find_method("pom"), {{"min_samples", "16"}, {"max_samples", "64"}})}) {
        SCOPED_TRACE(method.method->name);
        FrameRenderer r(runtime(), scene, table, {method}, w, h, ShadeSettings{});
        const MetricFrames f = render_metric_frames(r, scene, table, w, h);
        const FrameRun& metric = f.runs[2];
        ErrorStats p95[3];
        size_t band_mismatch[3];
        for (int m = 0; m < 3; ++m) {
            const TruthComparison cmp = compare_metric_frame(f, f.runs[m], table, w, h);
            std::vector<double> errors;
            for (size_t k = 0; k < cmp.uv_error.size(); ++k)
                if (!f.band[k] && std::isfinite(cmp.uv_error[k])) errors.push_back(cmp.uv_error[k]);
            ASSERT_GT(errors.size(), static_cast<size_t>(w) * h / 8);
            p95[m] = error_stats(errors);
            band_mismatch[m] = cmp.mismatch_band;
        }
        std::printf(
            "uv sphere, %s: interior uv p95 plane %.3f, curved %.3f, with the metric %.3f texels; "
            "band mismatch %zu, %zu, %zu pixels\n",
            method.method->name.c_str(), p95[0].p95, p95[1].p95, p95[2].p95, band_mismatch[0],
            band_mismatch[1], band_mismatch[2]);
        EXPECT_LE(p95[2].p95, p95[0].p95 / 5.0);
        EXPECT_LE(10 * band_mismatch[2], band_mismatch[0]);
        if (method.method->name != "pom") continue;
        // The forward peer with the same metric in its fragment shader: the same uv' within 0.05
        // texel on 98 % of the pixels both show on the sphere (V from the fragment's position
        // against V reconstructed from depth).
        const FrameRun fwd = r.render(FrameMode::Forward, false, 1);
        size_t both = 0, near = 0;
        for (size_t k = 0; k < metric.offset.flags.size(); ++k) {
            if (metric.material[k] != 1.0f || fwd.material[k] != 1.0f) continue;
            if (metric.offset.flags[k] & (OM_FLAGS_NOT_SHOWN | OM_FLAG_BEHIND)) continue;
            ++both;
            const double du = metric.offset.uv[k].s[0] - fwd.offset.uv[k].s[0],
                         dv = metric.offset.uv[k].s[1] - fwd.offset.uv[k].s[1];
            near += std::hypot(du, dv) * 64 <= 0.05;
        }
        std::printf("forward peer with the metric: %zu of %zu pixels within 0.05 texel\n", near,
                    both);
        ASSERT_GT(both, static_cast<size_t>(w) * h / 8);
        EXPECT_GE(near, both * 98 / 100);
    }
}

// Other uv layouts against the displaced mesh, exact, two layers: a flat parallelogram
// whose uv is skewed (edges 50 degrees apart) and stretched, a cylinder in 3 by 2 tiles (its
// stretch constant), a torus in 4 by 2 (its metric changing between the rings). Each its own
// material. The patch's uv is affine, so the metric's footprint is exact there: within 0.05 texel
// p95 (the truth's lattice and float), where the plane and the stretch alone take the uv as
// unskewed; the cylinder's stretch is its whole metric (the metric's frame within 10 % + 0.01
// texel of the stretch's); the torus's interior p95 falls below the stretch's.
TEST(Renderer, UvMetricFrameMeetsTheDisplacedSkewCylinderAndTorus) {
    Scene scene;
    scene.name = "layouts";
    const float skew = 50.0f * float(M_PI) / 180.0f;
    scene.meshes.push_back(make_quad("patch", 1, {-1.6f, 0.0f, -1.0f}, {1.2f, 0.0f, 0.0f},
                                     {0.9f * std::cos(skew), 0.0f, -0.9f * std::sin(skew)}, 4.0f,
                                     2.0f));
    scene.meshes.push_back(
        make_cylinder("cylinder", 2, {0.2f, 0.0f, -2.0f}, 0.3f, 0.8f, 96, 3.0f, 2.0f));
    scene.meshes.push_back(
        make_torus("torus", 3, {1.2f, 0.25f, -1.6f}, 0.4f, 0.16f, 96, 48, 4.0f, 2.0f));
    scene.camera = looking_at({0.0f, 1.4f, 0.6f}, {0.0f, 0.2f, -1.6f});
    scene.light.kind = LightKind::None;
    FlatCase c{"smooth", smooth_map(64), AddressMode::Wrap, 0.03f, 1.0f, 0.0};
    std::vector<LoadedMaterial> table;
    for (int id = 1; id <= 3; ++id) {
        table.push_back(material(c));
        table.back().spec.id = id;
        table.back().spec.name = "m" + std::to_string(id);
    }
    const int w = 320, h = 200;
    const MethodParams exact = resolve_params(find_method("exact"), {});
    FrameRenderer r(runtime(), scene, table, {exact, exact, exact}, w, h, ShadeSettings{});
    const MetricFrames frames = render_metric_frames(r, scene, table, w, h);
    const EngineScene& e = frames.e;
    double p95[3][3];  // [mesh][frame]
    for (int f = 0; f < 3; ++f) {
        const TruthComparison cmp = compare_metric_frame(frames, frames.runs[f], table, w, h);
        std::vector<double> errors[3];
        for (size_t k = 0; k < cmp.uv_error.size(); ++k) {
            const int id = static_cast<int>(e.material[k]);
            // The cylinder's caps have planar uv: its side alone.
            if (id == 2 && std::fabs(e.normal[4 * k + 1]) > 0.99f) continue;
            if (id >= 1 && id <= 3 && !frames.band[k] && std::isfinite(cmp.uv_error[k]))
                errors[id - 1].push_back(cmp.uv_error[k]);
        }
        for (int m = 0; m < 3; ++m) {
            ASSERT_GT(errors[m].size(), static_cast<size_t>(w) * h / 50) << m;
            p95[m][f] = error_stats(errors[m]).p95;
        }
    }
    const char* names[3] = {"skewed patch", "cylinder 3x2", "torus 4x2"};
    for (int m = 0; m < 3; ++m)
        std::printf("%-12s interior uv p95: plane %.3f, curved %.3f, with the metric %.3f texels\n",
                    names[m], p95[m][0], p95[m][1], p95[m][2]);
    EXPECT_LE(p95[0][2], 0.05);
    EXPECT_LE(p95[0][2], p95[0][1] / 5.0);
    EXPECT_LE(p95[1][2], 1.1 * p95[1][1] + 0.01);
    EXPECT_LE(p95[2][2], p95[2][1]);
}
#endif

}  // namespace
}  // namespace omtest
