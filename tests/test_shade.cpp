// The shading pass: Blinn-Phong against its closed form, light sources, albedo and normal maps.
#include <filesystem>
#include <limits>

#include "support.hpp"

namespace omtest {
namespace {

std::vector<cl_float4> shade(const HeightMap& map, const GBuffer& gb, const Image4* albedo,
                             const ShadeSettings& ss, const Image4* normal_map = nullptr) {
    auto rt = runtime();
    PassSettings s;
    s.scale = 0.1f;
    DeviceHeightField f = upload(*rt, map, s, normal_map);
    DeviceGBuffer g = upload(*rt, gb);
    OffsetPass pass(rt, "none");
    OffsetResult r = run_offset(*rt, pass, g, f, s, 1);
    ShadePass sp(rt);
    DeviceImage da;
    if (albedo) da = upload(*rt, *albedo);
    return run_shade(*rt, sp, r, g, f, albedo ? &da : nullptr, s, ss);
}

float blinn_phong(float albedo, const float n[3], const float l[3], const float v[3],
                  const ShadeSettings& ss) {
    float ndl = std::max(0.0f, n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
    float h[3] = {l[0] + v[0], l[1] + v[1], l[2] + v[2]};
    float hl = std::sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    float ndh = (n[0] * h[0] + n[1] * h[1] + n[2] * h[2]) / hl;
    float spec = ndl > 0 ? std::pow(std::max(ndh, 0.0f), ss.shininess) : 0.0f;
    return albedo * (ss.ambient + ss.diffuse * ndl) + ss.specular * spec;
}

TEST(Shade, BlinnPhongMatchesClosedForm) {
    Image4 albedo{2, 2, std::vector<cl_float4>(4, {{0.5f, 0.25f, 1.0f, 1.0f}})};
    ShadeSettings ss;
    ss.light[0] = 0.6f, ss.light[1] = 0.0f, ss.light[2] = 0.8f;
    const float up[3] = {0, 0, 1}, l[3] = {0.6f, 0, 0.8f};
    auto V = view_dir(50, 120);
    const float v[3] = {V[0], V[1], V[2]};
    GBuffer gb = row_gbuffer({{0.3f, 0.3f, V[0], V[1], V[2]}});
    auto c = shade(constant_map(0.5f), gb, &albedo, ss);
    for (int ch = 0; ch < 3; ++ch)
        EXPECT_NEAR(c[0].s[ch], blinn_phong(albedo.texels[0].s[ch], up, l, v, ss), 1e-5f) << ch;

    // A tilted ramp H = u: normal normalize(-s, 0, 1) with s = 0.1 (the pass's scale).
    const int n = 32;
    HeightMap ramp = make_map(n, 4, [](int i, int) { return 0.25f + 0.5f * (i + 0.5f) / n; });
    float len = std::sqrt(1.0f + 0.05f * 0.05f);
    const float tilt[3] = {-0.05f / len, 0, 1 / len};  // dH/du = 0.5, s dH/du = 0.05
    auto c2 = shade(ramp, gb, &albedo, ss);
    EXPECT_NEAR(c2[0].s[0], blinn_phong(0.5f, tilt, l, v, ss), 1e-4f);
}

TEST(Shade, LightSourcesBackgroundAndChecker) {
    ShadeSettings ss;
    ss.specular = 0.0f;
    // Per-pixel L from the G-buffer wins over the global light; L below the polygon: ambient only.
    GBuffer gb = row_gbuffer({{0.3f, 0.3f, 0, 0, 1}, {0.3f, 0.3f, 0, 0, 1},
                              {std::numeric_limits<float>::quiet_NaN(), 0.3f, 0, 0, 1}});
    gb.light = {{{0, 0, 1, 0}}, {{0.6f, 0, -0.8f, 0}}, {{0, 0, 1, 0}}};
    Image4 white{1, 1, {{{1, 1, 1, 1}}}};
    auto c = shade(constant_map(1.0f), gb, &white, ss);
    EXPECT_NEAR(c[0].s[0], ss.ambient + ss.diffuse, 1e-5f);
    EXPECT_NEAR(c[1].s[0], ss.ambient, 1e-5f);
    EXPECT_EQ(c[2].s[3], 0.0f);  // empty pixel: background, alpha 0
    // Without albedo: the neutral checker, 8 x 8 squares per tile, two different greys.
    GBuffer two = row_gbuffer({{0.01f, 0.01f, 0, 0, 1}, {0.14f, 0.01f, 0, 0, 1}});
    auto k = shade(constant_map(1.0f), two, nullptr, ss);
    EXPECT_GT(std::fabs(k[0].s[0] - k[1].s[0]), 0.1f);
}

TEST(Shade, NormalMapFileWithGreenFlip) {
    // One texel storing n = (0.6, -0.48, 0.64) as rgb = 0.5 + 0.5 n (8-bit).
    auto path = (std::filesystem::temp_directory_path() / "om_normal.png").string();
    const float nrm[3] = {0.6f, -0.48f, 0.64f};
    std::vector<unsigned char> px(3);
    for (int c = 0; c < 3; ++c) px[c] = static_cast<unsigned char>(std::lround((0.5f + 0.5f * nrm[c]) * 255));
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(1, 1, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    Image4 gl = load_normal_map(path, false), dx = load_normal_map(path, true);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(gl.texels[0].s[c], nrm[c], 2.0f / 255) << c;
    EXPECT_NEAR(dx.texels[0].s[1], -nrm[1], 2.0f / 255);
    // The shade pass uses the file's normal instead of the derived one.
    ShadeSettings ss;
    ss.specular = 0.0f;
    ss.light[0] = nrm[0], ss.light[1] = nrm[1], ss.light[2] = nrm[2];
    Image4 white{1, 1, {{{1, 1, 1, 1}}}};
    auto c = shade(constant_map(0.5f, 1, 1), row_gbuffer({{0.5f, 0.5f, 0, 0, 1}}), &white, ss, &gl);
    EXPECT_NEAR(c[0].s[0], ss.ambient + ss.diffuse, 1e-2f);  // N . L = 1 up to 8-bit rounding
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

// A box of height 1 (texels 56..71 of a 128 map) on a floor of 0, s = 0.1, lit from +u at elevation
// alpha: the box's top edge at u_top = 56.5 / 128 (bilinear: the wall rises between the centres of
// texels 55 and 56) casts a shadow on the floor behind it (toward -u) of length s / tan(alpha).
struct BoxScene {
    static constexpr int n = 128;
    HeightMap map = make_map(n, n, [](int i, int j) {
        return (i >= 56 && i < 72 && j >= 56 && j < 72) ? 1.0f : 0.0f;
    });
    double u_top = 56.5 / n, u_foot = 55.5 / n;
    std::vector<double> us;

    std::vector<cl_float4> shade_floor(double alpha_deg, ShadowMode mode, float size_deg = 8.0f) {
        std::vector<std::array<float, 5>> px;
        us.clear();
        for (double u = 0.10; u < u_foot - 1.0 / n; u += 0.25 / n) {
            us.push_back(u);
            px.push_back({static_cast<float>(u), 0.5f, 0, 0, 1});
        }
        ShadeSettings ss;
        ss.specular = 0.0f;
        auto L = view_dir(alpha_deg, 0);
        std::copy(L.begin(), L.end(), ss.light);
        ss.shadow = mode;
        ss.shadow_steps = 64;
        ss.light_size_deg = size_deg;
        Image4 white{1, 1, {{{1, 1, 1, 1}}}};
        auto rt = runtime();
        PassSettings s;
        s.scale = 0.1f;
        DeviceHeightField f = upload(*rt, map, s);
        GBuffer gb = row_gbuffer(px);
        DeviceGBuffer g = upload(*rt, gb);
        OffsetPass pass(rt, "none");
        OffsetResult r = run_offset(*rt, pass, g, f, s, 1);
        ShadePass sp(rt);
        DeviceImage da = upload(*rt, white);
        return run_shade(*rt, sp, r, g, f, &da, s, ss);
    }
};

TEST(Shadows, HardShadowOfABoxHasTheAnalyticLength) {
    BoxScene box;
    ShadeSettings ss;
    for (double alpha : {30.0, 50.0, 70.0}) {
        auto c = box.shade_floor(alpha, ShadowMode::Hard);
        const double lit = ss.ambient + ss.diffuse * std::sin(alpha * M_PI / 180);
        const double edge = box.u_top - 0.1 / std::tan(alpha * M_PI / 180);
        // Tolerance: one texel (the march samples the light ray 64 times over at most 22 texels,
        // and the bilinear wall is one texel wide).
        const double tol = 1.0 / BoxScene::n;
        size_t checked = 0;
        for (size_t k = 0; k < box.us.size(); ++k) {
            double u = box.us[k];
            if (u < edge - tol) {
                EXPECT_NEAR(c[k].s[0], lit, 1e-4) << "lit at u=" << u << " alpha " << alpha;
            }
            if (u > edge + tol) {
                EXPECT_NEAR(c[k].s[0], ss.ambient, 1e-4) << "shadow at u=" << u << " alpha " << alpha;
            }
            checked += std::fabs(u - edge) > tol;
        }
        EXPECT_GT(checked, 100u);
        auto none = box.shade_floor(alpha, ShadowMode::None);
        for (size_t k = 0; k < box.us.size(); ++k) EXPECT_NEAR(none[k].s[0], lit, 1e-4);
    }
}

TEST(Shadows, SoftShadowIsHalfLitAtTheGeometricEdgeAndWidensWithDistance) {
    BoxScene box;
    ShadeSettings ss;
    const double alpha = 40.0;
    auto c = box.shade_floor(alpha, ShadowMode::Soft, 8.0f);
    const double full = ss.diffuse * std::sin(alpha * M_PI / 180);
    const double edge = box.u_top - 0.1 / std::tan(alpha * M_PI / 180);
    std::vector<double> vis;
    for (size_t k = 0; k < box.us.size(); ++k) vis.push_back((c[k].s[0] - ss.ambient) / full);
    // Visibility falls monotonically from lit to dark toward the box ...
    for (size_t k = 1; k < vis.size(); ++k) EXPECT_LE(vis[k], vis[k - 1] + 1e-5) << box.us[k];
    // ... is one half where the top edge sits exactly on the light direction ...
    size_t ke = 0;
    while (ke + 1 < box.us.size() && box.us[ke] < edge) ++ke;
    EXPECT_NEAR(vis[ke], 0.5, 0.15) << "at u=" << box.us[ke] << ", edge " << edge;
    // ... and the penumbra's width is the light's angular size seen over the blocker distance:
    // d alpha = 8 deg at distance s / sin(alpha) from the edge gives about d / sin(alpha) on the
    // floor: (0.1 / sin 40) * (8 deg in rad) / sin 40 ~ 0.034 uv. Visibility is 0 and 1 outside.
    double half = 0.5 * 0.1 / std::sin(alpha * M_PI / 180) * (8.0 * M_PI / 180) / std::sin(alpha * M_PI / 180);
    for (size_t k = 0; k < box.us.size(); ++k) {
        if (box.us[k] < edge - 1.5 * half) {
            EXPECT_NEAR(vis[k], 1.0, 1e-4) << box.us[k];
        }
        if (box.us[k] > edge + 1.5 * half) {
            EXPECT_NEAR(vis[k], 0.0, 1e-4) << box.us[k];
        }
    }
}

}  // namespace
}  // namespace omtest
