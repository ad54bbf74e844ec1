// Tatarchuk's LOD system: the mip pyramid, per-pixel levels from the G-buffer or the uv footprint,
// more samples near the viewer, and the fade to normal mapping past the threshold.
#include "support.hpp"

namespace omtest {
namespace {

TEST(Lod, MipPyramidIsBoxAveragedDownToOneTexel) {
    HeightMap m = make_map(5, 3, [](int i, int j) { return 0.05f * (i + 5 * j); });
    ASSERT_EQ(mip_level_count(5, 3), 3);  // 5x3, 2x1, 1x1
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, m, PassSettings{});
    ASSERT_EQ(f.mip_levels, 3);
    std::vector<float> all(mip_pyramid_floats(5, 3, 3));
    ASSERT_EQ(all.size(), 15u + 2 + 1);
    rt->queue().enqueueReadBuffer(f.heights, CL_TRUE, 0, all.size() * sizeof(float), all.data());
    auto avg = [&](int x0, int x1, int y0, int y1) {  // over level 0, [x0, x1) x [y0, y1)
        double s = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) s += m.at(x, y);
        return s / ((x1 - x0) * (y1 - y0));
    };
    // Level 1 (2x1): texel 0 covers columns 0-1 (5 * 0 / 2 .. 5 * 1 / 2), texel 1 columns 2-4,
    // both over rows 0-2; level 2 averages level 1.
    EXPECT_NEAR(all[15], avg(0, 2, 0, 3), 1e-6);
    EXPECT_NEAR(all[16], avg(2, 5, 0, 3), 1e-6);
    EXPECT_NEAR(all[17], 0.5 * (all[15] + all[16]), 1e-6);
}

GBuffer with_lod(const std::vector<float>& levels, const std::array<float, 3>& V) {
    std::vector<std::array<float, 5>> px;
    for (size_t k = 0; k < levels.size(); ++k) px.push_back({0.3f + 0.01f * k, 0.6f, V[0], V[1], V[2]});
    GBuffer gb = row_gbuffer(px);
    gb.lod = levels;
    return gb;
}

PassSettings lod_settings(float threshold, float fade) {
    PassSettings s;
    s.scale = 0.1f;
    s.lod.enabled = true;
    s.lod.threshold = threshold;
    s.lod.fade = fade;
    return s;
}

TEST(Lod, OffsetFadesLinearlyToNormalMappingPastTheThreshold) {
    // Constant H = 0.3: every level of the pyramid is 0.3 and pom meets the plane exactly, so the
    // full-effect uv' is known at any level: uv - t V.xy with t = s (1 - 0.3) / V.z.
    auto V = view_dir(40, 70);
    GBuffer gb = with_lod({0.0f, 2.5f, 3.5f, 3.75f, 4.0f, 7.0f}, V);
    OffsetResult r = run("pom", constant_map(0.3f), gb, lod_settings(4.0f, 1.0f));
    const double t = 0.1 * 0.7 / V[2];
    const double w[] = {1, 1, 0.5, 0.25, 0, 0};  // clamp((4 - m) / 1, 0, 1)
    for (size_t k = 0; k < gb.pixels(); ++k) {
        for (int a = 0; a < 2; ++a)
            EXPECT_NEAR(r.uv[k].s[a], gb.uv[k].s[a] - w[k] * t * V[a], 1e-5) << k;
        EXPECT_NEAR(r.depth[k], w[k] * t, 1e-5) << k;
        EXPECT_EQ((r.flags[k] & OM_FLAG_LOD_FADED) != 0, w[k] == 0) << k;
        if (w[k] == 0) {
            EXPECT_EQ(r.fetches[k], 0u) << "faded pixels cost nothing";
        }
    }
    // LOD off: the lod channel is ignored.
    PassSettings off = lod_settings(4.0f, 1.0f);
    off.lod.enabled = false;
    OffsetResult o = run("pom", constant_map(0.3f), gb, off);
    EXPECT_NEAR(o.depth[5], t, 1e-5);
}

TEST(Lod, MoreSamplesNearTheViewer) {
    // On H = 0 the linear search runs to the bottom: n + 1 fetches with n = round(32 * detail),
    // detail = mix(1, 0.25, m / 8): m = 0 -> 33, m = 4 -> 21 (n = 20), m = 7 -> 12 (n = 11).
    auto V = view_dir(60, 10);
    GBuffer gb = with_lod({0.0f, 4.0f, 7.0f}, V);
    std::map<std::string, std::string> p = {{"min_samples", "32"}, {"max_samples", "32"}};
    OffsetResult r = run("pom", constant_map(0.0f), gb, lod_settings(8.0f, 1.0f), p);
    EXPECT_EQ(r.fetches[0], 33u);
    EXPECT_EQ(r.fetches[1], 21u);
    EXPECT_EQ(r.fetches[2], 12u);
}

TEST(Lod, LevelFromTheUvFootprintWhenTheGBufferHasNone) {
    // uv steps of 1/16 per pixel along x (4 texels of a 64 map) and 1/64 along y (1 texel):
    // level log2(4) = 2; with threshold 2.5 and fade 1 the offset is blended at w = 0.5.
    GBuffer gb;
    gb.resize(8, 6, false, false);
    auto V = view_dir(45, 0);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 8; ++x) {
            gb.uv[y * 8 + x] = {{x / 16.0f, y / 64.0f}};
            gb.view[y * 8 + x] = {{V[0], V[1], V[2], 0.0f}};
        }
    OffsetResult r = run("pom", constant_map(0.5f, 64, 64), gb, lod_settings(2.5f, 1.0f));
    const double t = 0.1 * 0.5 / V[2];
    for (size_t k = 0; k < gb.pixels(); ++k)
        EXPECT_NEAR(r.uv[k].s[0], gb.uv[k].s[0] - 0.5 * t * V[0], 1e-5) << k;
}

TEST(Lod, HeightsAreReadAtThePixelsLevel) {
    // A one-texel checker averages to 0.5 at level 1: parallax straight down reads H there.
    HeightMap checker = make_map(16, 16, [](int i, int j) { return ((i + j) % 2) ? 1.0f : 0.0f; });
    GBuffer gb = with_lod({0.0f, 1.5f}, {0.0f, 0.0f, 1.0f});
    gb.uv[0] = {{0.5f / 16, 0.5f / 16}};  // centre of texel (0, 0), height 0 at level 0
    gb.uv[1] = gb.uv[0];
    OffsetResult r = run("parallax", checker, gb, lod_settings(8.0f, 1.0f));
    EXPECT_NEAR(r.depth[0], 0.1 * (1.0 - 0.0), 1e-6);
    EXPECT_NEAR(r.depth[1], 0.1 * (1.0 - 0.5), 1e-6);
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

TEST(Lod, FootprintModeCapsStepsAtTheTexelsCrossedAndFadesByThem) {
    // s = 0.1 on a 64 map: a ray at elevation e crosses 6.4 cot(e) texels of level 0 through the
    // slab, half that at level 1. pom with 32 samples on H = 0 searches to the bottom, so its
    // fetches are (steps + 1) with steps = min(32, ceil(texels) + 1).
    PassSettings s;
    s.scale = 0.1f;
    s.lod.enabled = true;
    s.lod.footprint = true;
    s.lod.fade_texels_lo = 0.5f;
    s.lod.fade_texels_hi = 2.0f;
    std::map<std::string, std::string> p = {{"min_samples", "32"}, {"max_samples", "32"}};
    auto V45 = view_dir(45, 0);
    GBuffer gb = with_lod({0.0f, 1.0f, 4.0f}, V45);
    OffsetResult r = run("pom", constant_map(0.0f, 64, 64), gb, s, p);
    EXPECT_EQ(r.fetches[0], 9u);  // 6.4 texels: 7 + 1 = 8 steps
    EXPECT_EQ(r.fetches[1], 6u);  // 3.2 texels: 4 + 1 = 5 steps
    EXPECT_EQ(r.fetches[2], 0u);  // 0.4 texels at level 4: below the fade range, no trace
    EXPECT_TRUE(r.flags[2] & OM_FLAG_LOD_FADED);
    // Fade: at level 2 the ray crosses 1.6 texels: w = (1.6 - 0.5) / 1.5; on H = 0.3 pom meets the
    // plane exactly, so uv' = uv - w t V.xy with t = s (1 - 0.3) / V.z.
    GBuffer g2 = with_lod({2.0f}, V45);
    OffsetResult f = run("pom", constant_map(0.3f, 64, 64), g2, s, p);
    const double w = (6.4 / 4 - 0.5) / 1.5, t = 0.1 * 0.7 / V45[2];
    EXPECT_NEAR(f.uv[0].s[0], g2.uv[0].s[0] - w * t * V45[0], 1e-5);
}

}  // namespace
}  // namespace omtest
