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
    GBuffer gb = row_gbuffer({{0.3f, 0.3f, 0, 0, 1},
                              {0.3f, 0.3f, 0, 0, 1},
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
    for (int c = 0; c < 3; ++c)
        px[c] = static_cast<unsigned char>(std::lround((0.5f + 0.5f * nrm[c]) * 255));
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

// A box of height `top` (texels 56..71 of a 128 map) on a floor of 0, s = 0.1, lit from +u at
// elevation alpha: the box's top edge at u_top = 56.5 / 128 (bilinear: the wall rises between the
// centres of texels 55 and 56) casts a shadow on the floor behind it (toward -u).
struct BoxScene {
    static constexpr int n = 128;
    static constexpr double s = 0.1;
    float top = 1.0f;
    HeightMap map;
    PassSettings pass;  // scale s; the grazing rule the light's march obeys
    double u_top = 56.5 / n, u_foot = 55.5 / n;
    std::vector<double> us;

    explicit BoxScene(float top_height = 1.0f) : top(top_height) {
        pass.scale = static_cast<float>(s);
        map = make_map(n, n, [this](int i, int j) {
            return (i >= 56 && i < 72 && j >= 56 && j < 72) ? top : 0.0f;
        });
    }

    // With `mask` (one value a floor pixel): a shadow map's test beside the march; `visibility`
    // takes what the diffuse term was scaled by.
    std::vector<cl_float4> shade_floor(double alpha_deg, ShadowMode mode, float size_deg = 8.0f,
                                       int steps = 64, const std::vector<float>* mask = nullptr,
                                       std::vector<float>* visibility = nullptr,
                                       float specular = 0.0f) {
        std::vector<std::array<float, 5>> px;
        us.clear();
        for (double u = 0.05; u < u_foot - 1.0 / n; u += 0.25 / n) {
            us.push_back(u);
            px.push_back({static_cast<float>(u), 0.5f, 0, 0, 1});
        }
        ShadeSettings ss;
        ss.specular = specular;
        auto L = view_dir(alpha_deg, 0);
        std::copy(L.begin(), L.end(), ss.light);
        ss.shadow = mode;
        ss.shadow_steps = steps;
        ss.light_size_deg = size_deg;
        Image4 white{1, 1, {{{1, 1, 1, 1}}}};
        auto rt = runtime();
        const PassSettings& ps = pass;
        DeviceHeightField f = upload(*rt, map, ps);
        GBuffer gb = row_gbuffer(px);
        DeviceGBuffer g = upload(*rt, gb);
        OffsetPass pass(rt, "none");
        OffsetResult r = run_offset(*rt, pass, g, f, ps, 1);
        ShadePass sp(rt);
        DeviceImage da = upload(*rt, white);
        if (!mask && !visibility) return run_shade(*rt, sp, r, g, f, &da, ps, ss);
        const size_t count = px.size();
        auto floats = [&](const std::vector<float>* v, cl_mem_flags flags) {
            return v ? cl::Buffer(rt->context(), flags | CL_MEM_COPY_HOST_PTR,
                                  count * sizeof(float), const_cast<float*>(v->data()))
                     : cl::Buffer();
        };
        ShadeInputs in;
        in.albedo = &da;
        in.uv = cl::Buffer(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                           count * sizeof(cl_float2), r.uv.data());
        in.flags = cl::Buffer(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                              count * sizeof(std::uint32_t), r.flags.data());
        in.shadow_mask = floats(mask, CL_MEM_READ_ONLY);
        ShadeTargets out{cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, count * sizeof(cl_float4))};
        if (visibility) {
            visibility->assign(count, -1.0f);
            out.visibility = floats(visibility, CL_MEM_READ_WRITE);
        }
        sp.enqueue(g, f, in, ps, ss, out).wait();
        std::vector<cl_float4> rgba(count);
        rt->queue().enqueueReadBuffer(out.rgba, CL_TRUE, 0, count * sizeof(cl_float4), rgba.data());
        if (visibility)
            rt->queue().enqueueReadBuffer(out.visibility, CL_TRUE, 0, count * sizeof(float),
                                          visibility->data());
        return rgba;
    }

    // The light's visible share on the floor, from the shaded colour (white albedo, flat floor:
    // N . L = sin alpha).
    std::vector<double> visibility(double alpha_deg, float size_deg, int steps = 64) {
        ShadeSettings ss;
        auto c = shade_floor(alpha_deg, ShadowMode::Soft, size_deg, steps);
        std::vector<double> vis;
        const double full = ss.diffuse * std::sin(alpha_deg * M_PI / 180);
        for (const auto& px : c) vis.push_back((px.s[0] - ss.ambient) / full);
        return vis;
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
                EXPECT_NEAR(c[k].s[0], ss.ambient, 1e-4)
                    << "shadow at u=" << u << " alpha " << alpha;
            }
            checked += std::fabs(u - edge) > tol;
        }
        EXPECT_GT(checked, 100u);
        auto none = box.shade_floor(alpha, ShadowMode::None);
        for (size_t k = 0; k < box.us.size(); ++k) EXPECT_NEAR(none[k].s[0], lit, 1e-4);
    }
}

bool same_bits(const std::vector<cl_float4>& a, const std::vector<cl_float4>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof a[0]) == 0;
}

// The shadow map's test and the march combine by the smaller visibility: a pixel both shadow is
// darkened once, as the stricter says, never by their product. A mask of ones gives the march's
// frame bit for bit; a mask of zeros leaves the ambient term alone, the glint gone with the
// diffuse.
TEST(Shadows, AShadowMapAndTheMarchDarkenAPixelOnceByTheStricter) {
    BoxScene box;
    const double alpha = 40.0;
    const float size = 8.0f;
    ShadeSettings ss;
    std::vector<float> march;
    const std::vector<cl_float4> plain =
        box.shade_floor(alpha, ShadowMode::Soft, size, 64, nullptr, &march, ss.specular);
    ASSERT_TRUE(same_bits(
        plain, box.shade_floor(alpha, ShadowMode::Soft, size, 64, nullptr, nullptr, ss.specular)))
        << "writing the visibility changes no bit";
    const size_t n = box.us.size();
    size_t lit = 0, dark = 0, penumbra = 0;
    for (float v : march) {
        lit += v == 1.0f;
        dark += v == 0.0f;
        penumbra += v > 0.0f && v < 1.0f;
    }
    ASSERT_GT(lit, 10u);
    ASSERT_GT(dark, 10u);
    ASSERT_GT(penumbra, 3u) << "the march's penumbra";

    const std::vector<float> ones(n, 1.0f);
    std::vector<float> vis;
    EXPECT_TRUE(same_bits(
        box.shade_floor(alpha, ShadowMode::Soft, size, 64, &ones, &vis, ss.specular), plain))
        << "a mask of ones changes no bit";
    EXPECT_EQ(vis, march);

    // A mask that steps through 0, 0.3, 0.6 and 1 along the floor, across the march's lit,
    // penumbra and shadowed pixels.
    std::vector<float> mask(n);
    for (size_t k = 0; k < n; ++k) mask[k] = std::array<float, 4>{0.0f, 0.3f, 0.6f, 1.0f}[k % 4];
    const std::vector<cl_float4> both =
        box.shade_floor(alpha, ShadowMode::Soft, size, 64, &mask, &vis, ss.specular);
    const double ndl = std::sin(alpha * M_PI / 180);
    for (size_t k = 0; k < n; ++k) {
        const float expected = std::min(march[k], mask[k]);
        EXPECT_EQ(vis[k], expected) << "u " << box.us[k];
        // White albedo, flat floor: ambient + diffuse N.L v (+ the glint, scaled by the mask).
        const double diffuse = ss.ambient + ss.diffuse * ndl * expected;
        EXPECT_GE(both[k].s[0], diffuse - 1e-5) << "u " << box.us[k];
        if (mask[k] == 0.0f) {
            EXPECT_NEAR(both[k].s[0], ss.ambient, 1e-6) << "u " << box.us[k];
        }
        const double glint = plain[k].s[0] - (ss.ambient + ss.diffuse * ndl * march[k]);
        if (march[k] > 0.0f && mask[k] > 0.0f) {
            EXPECT_NEAR(both[k].s[0], diffuse + glint * mask[k], 1e-5) << "u " << box.us[k];
        }
    }
    // Without the march (ShadowMode::None) the mask alone is the visibility.
    box.shade_floor(alpha, ShadowMode::None, size, 64, &mask, &vis, ss.specular);
    EXPECT_EQ(vis, mask);
}

TEST(Shadows, TheLightsMarchObeysTheViewsGrazingRule) {
    // Light at 25 degrees over the box (s = 0.1, 128^2 map). The shadow's length on the floor is
    // s / tan of the elevation the march uses: 25 degrees under clamp; under cap (16 texels) the
    // light is raised like a view, to atan(s 128 / 16) = 38.7 degrees, a shadow of exactly the cap,
    // 16 texels; under limit the march runs along normalize(L.xy, 1), a shadow of s |L.xy| =
    // s cos 25. Tolerance: one texel, as for the hard shadow above.
    const double alpha = 25.0, n = BoxScene::n;
    ShadeSettings ss;
    const double lit = ss.ambient + ss.diffuse * std::sin(alpha * M_PI / 180);
    struct Case {
        GrazingPolicy policy;
        double length;  // uv
    };
    for (const Case& c : {Case{GrazingPolicy::Clamp, 0.1 / std::tan(alpha * M_PI / 180)},
                          Case{GrazingPolicy::Cap, 16.0 / n},
                          Case{GrazingPolicy::Limit, 0.1 * std::cos(alpha * M_PI / 180)}}) {
        BoxScene box;
        box.pass.grazing = c.policy;
        box.pass.max_offset_texels = 16.0f;
        auto col = box.shade_floor(alpha, ShadowMode::Hard);
        const double edge = box.u_top - c.length, tol = 1.0 / n;
        size_t checked = 0;
        for (size_t k = 0; k < box.us.size(); ++k) {
            const double u = box.us[k];
            if (u < edge - tol) {
                EXPECT_NEAR(col[k].s[0], lit, 1e-4) << "lit at " << u;
            }
            if (u > edge + tol) {
                EXPECT_NEAR(col[k].s[0], ss.ambient, 1e-4) << "shadow at " << u;
            }
            checked += std::fabs(u - edge) > tol;
        }
        EXPECT_GT(checked, 100u) << static_cast<int>(c.policy);
    }
}

// The soft shadow's geometric prediction. A light of angular diameter sigma at elevation alpha,
// seen from a floor point at distance d in front of the box's top edge (height difference
// b = s * top), is cut by the blocker's edge at angle w = atan(b / d): the visible share of the
// light (uniform across its elevation) is v(d) = clamp(1/2 - (w - alpha) / sigma, 0, 1). The edge
// bounds every other blocker angle: on the wall (height (x - u_foot) n top, x < u_top) and on the
// top (x > u_top) the angle is below atan(b / d). So the penumbra spans the d where w is within
// sigma / 2 of alpha, and its width on the floor is b (cot(alpha - sigma/2) - cot(alpha +
// sigma/2)): proportional to the blocker's height, i.e. to its distance along the light. The march
// samples the light ray every delta (its length over the step count) and so sees the edge itself
// only up to delta past it: the worst angle it finds lies in [atan(b / (d + delta)), w], and v is
// at most (w - atan(b / (d + delta))) / sigma above the prediction, never below it.
double predicted_visibility(double d, double b, double alpha, double sigma) {
    return std::clamp(0.5 - (std::atan(b / d) - alpha) / sigma, 0.0, 1.0);
}

TEST(Shadows, SoftShadowFollowsTheGeometricPenumbraAndWidensWithDistance) {
    const double alpha_deg = 40.0, sigma_deg = 8.0;
    const double alpha = alpha_deg * M_PI / 180, sigma = sigma_deg * M_PI / 180;
    const int steps = 256;
    double width[2] = {0, 0}, predicted[2] = {0, 0}, tol[2] = {0, 0};
    const float tops[2] = {1.0f, 0.5f};
    for (int b_i = 0; b_i < 2; ++b_i) {
        BoxScene box(tops[b_i]);
        const double b = BoxScene::s * box.top;
        std::vector<double> vis = box.visibility(alpha_deg, static_cast<float>(sigma_deg), steps);
        // The march reaches as far as a ray toward the light's lowest point needs to climb to the
        // top plane (H = 1): s / tan(alpha - sigma / 2) from the floor.
        const double delta = BoxScene::s / std::tan(alpha - sigma / 2) / steps;
        size_t in_penumbra = 0;
        for (size_t k = 0; k < box.us.size(); ++k) {
            const double d = box.u_top - box.us[k];
            const double lo = predicted_visibility(d, b, alpha, sigma);
            const double hi = predicted_visibility(d + delta, b, alpha, sigma);
            EXPECT_GE(vis[k], lo - 1e-4) << "top " << box.top << " at u=" << box.us[k];
            EXPECT_LE(vis[k], hi + 1e-4) << "top " << box.top << " at u=" << box.us[k];
            in_penumbra += lo > 0.0 && lo < 1.0;
        }
        EXPECT_GT(in_penumbra, 5u) << "the penumbra spans several pixels";
        // Its measured width, between visibility 0.1 and 0.9 (linear between samples).
        auto crossing = [&](double level) {
            for (size_t k = 1; k < vis.size(); ++k)
                if (vis[k - 1] >= level && vis[k] < level)
                    return box.us[k - 1] + (box.us[k] - box.us[k - 1]) * (vis[k - 1] - level) /
                                               (vis[k - 1] - vis[k]);
            ADD_FAILURE() << "visibility never crosses " << level;
            return 0.0;
        };
        width[b_i] = crossing(0.1) - crossing(0.9);
        predicted[b_i] =
            b * (1 / std::tan(alpha - 0.4 * sigma) - 1 / std::tan(alpha + 0.4 * sigma));
        // The measured curve lies between the prediction at d and at d + delta, so each crossing
        // sits within delta of the predicted one, on the same side: the width is off by at most
        // delta. Linear interpolation between pixels h apart adds h^2 |v''| / (8 |v'|) =
        // h^2 d / (4 (d^2 + b^2)) < 1e-5 uv here.
        tol[b_i] = delta + 1e-5;
        std::printf(
            "soft shadow, blocker %.2f: penumbra (10-90 %%) %.5f uv, predicted %.5f +- %.5f\n", b,
            width[b_i], predicted[b_i], tol[b_i]);
        EXPECT_NEAR(width[b_i], predicted[b_i], tol[b_i]);
        const std::string key = "penumbra.top" + std::to_string(static_cast<int>(box.top * 100));
        record_figure(key + ".width_texels", width[b_i] * BoxScene::n);
        record_figure(key + ".predicted_texels", predicted[b_i] * BoxScene::n);
    }
    // Twice the blocker height (twice its distance from the floor along the light): twice the
    // width, within what the two widths' tolerances allow.
    EXPECT_GT(width[0] / width[1], (predicted[0] - tol[0]) / (predicted[1] + tol[1]));
    EXPECT_LT(width[0] / width[1], (predicted[0] + tol[0]) / (predicted[1] - tol[1]));
    EXPECT_GT((predicted[0] - tol[0]) / (predicted[1] + tol[1]), 1.8);  // the bound is informative
}

}  // namespace
}  // namespace omtest
