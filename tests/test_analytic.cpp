// Closed-form cases: flat and constant fields, a ramp and a step edge with known hits.
#include "support.hpp"

namespace omtest {
namespace {

// Tolerance for float kernels against closed forms: uv is O(1) with float eps 6e-8, so rounding
// stays below 1e-5 uv; we allow 1e-3 texel of a 64-texel map (1.6e-5 uv), the oracle's tolerance.
constexpr double kTexelTol = 1e-3;

TEST(Analytic, EveryMethodHasATestRow) { EXPECT_EQ(method_names(), methods_with_rows()); }

// On a constant field H = c every method's answer is the plane hit t = s (r - c) / V.z, up to its
// row's lambda quantisation (slab length s / V.z per unit lambda); `none` stays at t = 0 and
// offset limiting uses t = s (r - c) with the same uv footprint rule. With c = r (a flat field,
// the relief is the polygon) that is uv' = uv.
void check_constant_field(float c, float r) {
    HeightMap m = constant_map(c, 32, 32);
    PassSettings s;
    s.scale = 0.1f;
    s.reference_plane = r;
    GBuffer gb = make_scene(RandomScene{64, 4, 9, 5.0, 90.0});
    for (const auto& name : method_names()) {
        OffsetResult res = run(name, m, gb, s);
        for (size_t k = 0; k < gb.pixels(); ++k) {
            const auto& V = gb.view[k].s;
            double tol_lambda = constant_field_lambda_tolerance(name, V[2]);
            double t = s.scale * (r - c) / V[2];
            if (name == "none") t = 0.0;
            if (name == "parallax-limited") t = s.scale * (r - c);
            // Float rounding: 1e-3 texel of this 32-texel map, in t (uv) units per |V.xy|.
            double tol_t = tol_lambda * s.scale / V[2] + 3e-5 * std::max(1.0, t);
            ASSERT_NEAR(res.depth[k], t, tol_t) << name << " c=" << c << " r=" << r << " " << k;
            if (name == "steep") {
                ASSERT_GE(res.depth[k], t - 1e-6) << "steep stops at or below";
            }
            for (int a = 0; a < 2; ++a)
                ASSERT_NEAR(res.uv[k].s[a], gb.uv[k].s[a] - res.depth[k] * V[a], 1e-5)
                    << name << ": uv' must be the ray's footprint at t";
        }
    }
}

TEST(Analytic, FlatFieldLeavesUvUnchanged) {
    check_constant_field(1.0f, 1.0f);
    check_constant_field(0.4f, 0.4f);
}

TEST(Analytic, ConstantFieldGivesThePlaneHit) {
    for (float r : {1.0f, 0.5f})
        for (float c : {0.0f, 0.35f, 0.9f}) check_constant_field(c, r);
}

// One pixel at uv (0.3, 0.6) per view: elevations from straight down to 2 degrees, each azimuth.
std::vector<std::array<float, 5>> views_from_above_to_grazing(
    std::initializer_list<double> azimuths) {
    std::vector<std::array<float, 5>> px;
    for (double elev : {90.0, 70.0, 45.0, 30.0, 15.0, 5.0, 2.0})
        for (double az : azimuths) {
            auto V = view_dir(elev, az);
            px.push_back({0.3f, 0.6f, V[0], V[1], V[2]});
        }
    return px;
}

TEST(Analytic, PomStepCountFollowsTatarchusLerp) {
    // Tatarchuk's dynamic sampling: n = lerp(n_max, n_min, V.z) steps (rounded), more at grazing
    // views. On a floor (H = 0, r = 1) the linear search runs to the bottom plane, sample n, so
    // it reads n + 1 heights; secant's refinement has nothing left to refine there (the last
    // sample is on the floor), so it reads as many.
    HeightMap floor = constant_map(0.0f, 16, 16);
    PassSettings s;
    s.scale = 0.05f;
    const std::vector<std::array<float, 5>> px = views_from_above_to_grazing({0.0, 130.0});
    for (const char* method : {"pom", "secant"}) {
        OffsetResult r =
            run(method, floor, row_gbuffer(px), s, {{"min_samples", "6"}, {"max_samples", "40"}});
        for (size_t k = 0; k < px.size(); ++k) {
            const double n = std::max(1.0, std::floor(40.0 + (6.0 - 40.0) * px[k][4] + 0.5));
            EXPECT_EQ(r.fetches[k], n + 1) << method << " at V.z = " << px[k][4];
        }
    }
}

TEST(Analytic, PomSpacingStepsByTheTexelsTheRayCrosses) {
    // With spacing k the step count is ceil(texels / k) within [n_min, n_max], texels being those
    // the ray crosses through the slab: s |(V.x W, V.y H)| / V.z on a W x H map (r = 1). On a
    // floor the search runs to the bottom, n + 1 reads. A non-square map pins the per-axis sizes.
    HeightMap floor = constant_map(0.0f, 32, 16);
    PassSettings s;
    s.scale = 0.05f;
    const std::vector<std::array<float, 5>> px = views_from_above_to_grazing({0.0, 60.0, 130.0});
    const double k = 1.5, n_min = 2, n_max = 12;
    OffsetResult r = run("pom", floor, row_gbuffer(px), s,
                         {{"min_samples", "2"}, {"max_samples", "12"}, {"spacing", "1.5"}});
    for (size_t i = 0; i < px.size(); ++i) {
        const double vx = px[i][2], vy = px[i][3], vz = px[i][4];
        const double texels = s.scale * std::hypot(vx * 32, vy * 16) / vz;
        const double q = texels / k;
        const double n = std::clamp(std::ceil(q), n_min, n_max);
        if (std::abs(q - std::round(q)) < 1e-4) {  // float rounding may go either way there
            const double lo = std::clamp(std::round(q), n_min, n_max);
            const double hi = std::clamp(std::round(q) + 1, n_min, n_max);
            EXPECT_TRUE(r.fetches[i] == lo + 1 || r.fetches[i] == hi + 1) << i;
        } else {
            EXPECT_EQ(r.fetches[i], n + 1) << "texels " << texels << " at V.z = " << vz;
        }
    }
}

// H = u between the first and last texel centres (texels (i + 0.5) / n), clamped addressing.
TEST(Analytic, RampHit) {
    const int n = 64;
    HeightMap m = make_map(n, 4, [](int i, int) { return (i + 0.5f) / n; });
    PassSettings s;
    s.scale = 0.1f;
    s.address = AddressMode::Clamp;
    // Ray from u0 with V = (Vx, 0, Vz): -t Vz = s (u0 - t Vx - r) => t = s (r - u0) / (Vz - s Vx).
    std::vector<std::array<float, 5>> px;
    std::vector<double> expect_u;
    for (double elev : {80.0, 45.0, 20.0})
        for (double az : {0.0, 180.0}) {
            auto V = view_dir(elev, az);
            const double u0 = 0.5, sc = s.scale;  // the float scale the pass uses
            double t = sc * (1.0 - u0) / (V[2] - sc * V[0]);
            px.push_back({static_cast<float>(u0), 0.5f, V[0], V[1], V[2]});
            expect_u.push_back(u0 - t * V[0]);
        }
    OffsetResult ex = run("exact", m, row_gbuffer(px), s);
    for (size_t k = 0; k < px.size(); ++k) {
        EXPECT_NEAR(ex.uv[k].s[0] * n, expect_u[k] * n, kTexelTol) << k;
        double dv[3] = {px[k][2], px[k][3], px[k][4]};
        ExactHit o = exact_hit(m, px[k][0], px[k][1], dv, s);
        EXPECT_NEAR(o.u * n, expect_u[k] * n, 1e-9) << "oracle " << k;  // double rounding only
    }
}

// A step from 0 to 1 at u = 1/2 is, bilinearly, a one-texel-wide linear face between the centres
// of texels n/2 - 1 and n/2. A ray from the low side toward +u either meets the face or the floor.
TEST(Analytic, StepEdgeHit) {
    const int n = 64;
    HeightMap m = make_map(n, 4, [](int i, int) { return i >= n / 2 ? 1.0f : 0.0f; });
    PassSettings s;
    s.scale = 0.1f;
    s.address = AddressMode::Clamp;
    const double ua = (n / 2 - 0.5) / n;  // face foot (H = 0) ... face top (H = 1) at ua + 1/n
    std::vector<std::array<float, 5>> px;
    std::vector<double> expect_u;
    for (double u0 : {0.40, 0.45, 0.48})
        for (double elev : {30.0, 60.0}) {
            auto V = view_dir(elev, 180.0);  // eye toward -u: the ray runs toward +u
            double vx = V[0], vz = V[2];
            // Floor: z = -s at t = s / Vz. Face: H = (u - ua) n, z = s (H - 1).
            double t_floor = 0.1 / vz;
            double t_face = (0.1 * ((u0 - ua) * n - 1.0)) / (-vz + 0.1 * vx * n);
            double u_face = u0 - t_face * vx;
            bool face = u_face >= ua && u_face <= ua + 1.0 / n && t_face < t_floor;
            double t = face ? t_face : t_floor;
            px.push_back({static_cast<float>(u0), 0.5f, V[0], V[1], V[2]});
            expect_u.push_back(u0 - t * vx);
        }
    OffsetResult ex = run("exact", m, row_gbuffer(px), s);
    OffsetResult pa = run("parallax", m, row_gbuffer(px), s);
    for (size_t k = 0; k < px.size(); ++k) {
        EXPECT_NEAR(ex.uv[k].s[0] * n, expect_u[k] * n, kTexelTol) << k;
        // parallax reads H(u0) = 0 and lands on the floor, through the wall when the face is hit.
        double t_floor = 0.1 / px[k][4];
        EXPECT_NEAR(pa.uv[k].s[0], px[k][0] - t_floor * px[k][2], 1e-6) << k;
    }
}

}  // namespace
}  // namespace omtest
