// The exact kernel (float) against the independent double-precision host oracle.
//
// Tolerance 1e-3 texel: the kernel traces in a local frame where uv is O(1), so positions carry
// float rounding of ~1e-7 uv, and hits are found from quadratics whose coefficients carry
// relative rounding ~1e-7; for rays that cross the surface at the slopes these maps have, that
// moves a hit by 1e-5 texel or less. 1e-3 texel leaves two orders of margin for rays that cross
// at a shallow angle, and is still far below anything visible (1/1000 of a texel).
#include "support.hpp"

namespace omtest {
namespace {

struct Case {
    const char* name;
    HeightMap map;
};

void compare_with_oracle(const HeightMap& map, const char* name, float scale, float ref,
                         double min_elev, AddressMode address,
                         const std::string& method = "exact") {
    PassSettings s;
    s.scale = scale;
    s.reference_plane = ref;
    s.address = address;
    GBuffer gb = make_scene(RandomScene{64, 32, 2024, min_elev, 90.0});
    OffsetResult res = run(method, map, gb, s);
    double worst = 0.0;
    size_t worst_k = 0;
    for (size_t k = 0; k < gb.pixels(); ++k) {
        ASSERT_EQ(res.flags[k] & ~OM_FLAG_GRAZING, 0u) << k;
        double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
        PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s);
        ExactHit o = exact_hit(map, pr.u, pr.v, pr.V, s);
        double e =
            std::hypot((res.uv[k].s[0] - o.u) * map.width, (res.uv[k].s[1] - o.v) * map.height);
        if (e > worst) worst = e, worst_k = k;
        ASSERT_NEAR(res.depth[k], o.t, 1e-4 * std::max(1.0, std::fabs(o.t))) << name << " " << k;
    }
    std::printf("%s vs oracle, %s s=%.2f r=%.1f: worst %.2e texel over %zu rays\n", method.c_str(),
                name, scale, ref, worst, gb.pixels());
    EXPECT_LE(worst, 1e-3) << name << " s=" << scale << " r=" << ref << " worst pixel " << worst_k;
}

// 48 x 20: non-square, not a power of two, 20 not a multiple of 8.
HeightMap nonsquare_map() {
    return make_map(48, 20, [](int i, int j) {
        return static_cast<float>(0.5 + 0.45 * std::sin(0.7 * i) * std::cos(0.9 * j));
    });
}

// A method that ends in exact's patch solve (maxmip, cone), held to exact's bound: smooth, noisy
// and cliff maps at both scales and reference planes, plus `extra` maps, wrapped; the non-square
// map wrapped and clamped.
void agrees_like_exact(const std::string& method, std::vector<Case> extra = {}) {
    std::vector<Case> cases = {{"smooth", smooth_map(64)},
                               {"noisy", noisy_map(64)},
                               {"cliffs", cliff_map(64)},
                               {"noisy-256", noisy_map(256, 9)}};
    for (auto& c : extra) cases.push_back(std::move(c));
    for (const auto& c : cases)
        for (float scale : {0.05f, 0.2f})
            for (float ref : {1.0f, 0.6f})
                compare_with_oracle(c.map, c.name, scale, ref, 5.0, AddressMode::Wrap, method);
    HeightMap m = nonsquare_map();
    compare_with_oracle(m, "nonsquare-wrap", 0.1f, 0.8f, 5.0, AddressMode::Wrap, method);
    compare_with_oracle(m, "nonsquare-clamp", 0.1f, 1.0f, 5.0, AddressMode::Clamp, method);
}

TEST(ExactOracle, AgreesOnRandomRaysDownTo5Degrees) {
    std::vector<Case> cases = {
        {"smooth", smooth_map(64)}, {"noisy", noisy_map(64)}, {"cliffs", cliff_map(64)}};
    for (const auto& c : cases)
        for (float scale : {0.05f, 0.2f})
            for (float ref : {1.0f, 0.6f})
                compare_with_oracle(c.map, c.name, scale, ref, 5.0, AddressMode::Wrap);
}

TEST(ExactOracle, AgreesWithClampAddressingAndNonSquareMaps) {
    HeightMap m = nonsquare_map();
    compare_with_oracle(m, "nonsquare-clamp", 0.1f, 1.0f, 5.0, AddressMode::Clamp);
    compare_with_oracle(m, "nonsquare-wrap", 0.1f, 0.8f, 5.0, AddressMode::Wrap);
}

TEST(MaxMip, AgreesWithTheOracleLikeExact) {
    // The same bound as exact: maxmip ends in the same patch solve; its skips are exact decisions.
    // 48 x 20 has two levels; clamp addressing has no hierarchy.
    agrees_like_exact("maxmip");
}

TEST(MaxMip, LevelZeroIsExactAndTheHierarchySavesFetchesOnLongRays) {
    // Long traversals (smooth relief, grazing views, large s) are where a max pyramid pays: blocks
    // above the ray are skipped whole. On noise every block's maximum is near 1 and rays hit
    // within a few cells, so the walk costs a little more than exact's DDA (reported, not
    // asserted).
    PassSettings s;
    s.scale = 0.1f;
    GBuffer grazing = make_scene(RandomScene{64, 64, 31, 5.0, 30.0});
    auto fetches = [&](const HeightMap& m, const std::string& method,
                       const std::map<std::string, std::string>& p = {}) {
        OffsetResult r = run(method, m, grazing, s, p);
        double sum = 0;
        for (auto f : r.fetches) sum += f;
        return std::make_pair(r, sum / grazing.pixels());
    };
    HeightMap smooth = smooth_map(256), noise = noisy_map(256, 4);
    auto [ex, fe] = fetches(smooth, "exact");
    auto [flat, ff] = fetches(smooth, "maxmip", {{"max_level", "0"}});
    auto [mm, fm] = fetches(smooth, "maxmip");
    for (size_t k = 0; k < grazing.pixels(); ++k)
        ASSERT_EQ(std::memcmp(&flat.uv[k], &ex.uv[k], sizeof(cl_float2)), 0)
            << "level 0 is exact, pixel " << k;
    EXPECT_EQ(ff, fe);
    std::printf("fetches per pixel, 256^2 smooth map, 5-30 deg, s = 0.1: exact %.1f, maxmip %.1f\n",
                fe, fm);
    EXPECT_LT(fm, 0.5 * fe);
    auto [nex, nfe] = fetches(noise, "exact");
    auto [nmm, nfm] = fetches(noise, "maxmip");
    std::printf("fetches per pixel, 256^2 noise (worst case): exact %.1f, maxmip %.1f\n", nfe, nfm);
}

TEST(Cone, AgreesWithTheOracleLikeExact) {
    // The same bound as exact: cone ends in the same patch solve, and its cone steps never cross
    // relief, so a skipped thin feature would show up here as a wrong hit. On 48 x 20 (wrap) block
    // maxima do not tile (20 % 8), so the build visits every cell in reach.
    agrees_like_exact("cone", {{"spikes", make_map(64, 64, [](int i, int j) {
                                    return (i % 7 == 3 && j % 5 == 1) ? 1.0f : 0.05f;
                                })}});
}

// The bilinear relief of `map` at texel-space point (x, y) (integer = texel centre), wrapped.
double bilinear_wrap(const HeightMap& map, double x, double y) {
    double fx = std::floor(x), fy = std::floor(y), a = x - fx, b = y - fy;
    auto at = [&](long i, long j) {
        i = ((i % map.width) + map.width) % map.width;
        j = ((j % map.height) + map.height) % map.height;
        return static_cast<double>(map.h[j * map.width + i]);
    };
    long i = static_cast<long>(fx), j = static_cast<long>(fy);
    return (1 - b) * ((1 - a) * at(i, j) + a * at(i + 1, j)) +
           b * ((1 - a) * at(i, j + 1) + a * at(i + 1, j + 1));
}

TEST(Cone, MapHoldsNoReliefInsideAnyCellConeAndIsNotLooser) {
    // Straight from the definition: for every cell C and relief points q sampled 5 x 5 per cell
    // (corners and edges included) around it, dist(q, C) >= c (H(q) - Hc), and Hc bounds C's patch.
    // max_ratio 12 bounds the cones, so points beyond 12 + sqrt 2 texels cannot matter.
    // And not looser than the cell discretisation: a cone below max_ratio is set by a cell D at
    // gap delta whose highest corner (sampled) lies within delta + sqrt 2 of C (for touching
    // cells: 1 for delta = 1, sqrt 2 for delta = 1/sqrt 2), so the samples' bound is <= 2.42 c.
    const int n = 32, reach = 15;
    HeightMap map = noisy_map(n, 21);
    PassSettings s;
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, map, s);
    OffsetPass pass(rt, "cone", {{"max_ratio", "12"}});
    pass.prepare(f, s);
    EXPECT_EQ(pass.precomputed().bytes, 2u * n * n * sizeof(float));
    std::vector<float> cone(2 * n * n);
    rt->queue().enqueueReadBuffer(pass.precomputed_buffer(), CL_TRUE, 0,
                                  cone.size() * sizeof(float), cone.data());
    double loosest = 0.0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const double hc = cone[2 * (j * n + i)], c = cone[2 * (j * n + i) + 1];
            ASSERT_GT(c, 0.0);
            ASSERT_LE(c, 12.0);
            double worst = 1e9;
            for (int sy = 4 * (j - reach); sy <= 4 * (j + reach + 1); ++sy) {
                for (int sx = 4 * (i - reach); sx <= 4 * (i + reach + 1); ++sx) {
                    const double x = sx / 4.0, y = sy / 4.0, h = bilinear_wrap(map, x, y);
                    const double gx = std::max({i - x, x - (i + 1), 0.0}),
                                 gy = std::max({j - y, y - (j + 1), 0.0});
                    if (gx == 0.0 && gy == 0.0) {
                        ASSERT_LE(h, hc + 1e-6) << "cell " << i << "," << j;
                        continue;
                    }
                    if (h > hc) worst = std::min(worst, std::hypot(gx, gy) / (h - hc));
                }
            }
            ASSERT_GE(worst, c * (1 - 1e-5)) << "cell " << i << "," << j << " cone " << c;
            if (c < 12.0) {
                EXPECT_LE(worst, 2.42 * c) << "cell " << i << "," << j << " cone " << c;
                loosest = std::max(loosest, worst / c);
            }
        }
    }
    std::printf("cone map 32^2 noise: sampled bound / stored cone at most %.2f\n", loosest);
}

TEST(Cone, SavesFetchesOverExactOnLongRays) {
    PassSettings s;
    s.scale = 0.1f;
    GBuffer grazing = make_scene(RandomScene{64, 64, 31, 5.0, 30.0});
    auto fetches = [&](const HeightMap& m, const std::string& method) {
        OffsetResult r = run(method, m, grazing, s);
        double sum = 0;
        for (auto f : r.fetches) sum += f;
        return sum / grazing.pixels();
    };
    HeightMap smooth = smooth_map(256), noise = noisy_map(256, 4);
    const double fe = fetches(smooth, "exact"), fm = fetches(smooth, "maxmip"),
                 fc = fetches(smooth, "cone");
    std::printf(
        "fetches per pixel, 256^2 smooth map, 5-30 deg, s = 0.1: exact %.1f, maxmip %.1f, cone "
        "%.1f\n",
        fe, fm, fc);
    EXPECT_LT(fc, 0.5 * fe);
    std::printf("fetches per pixel, 256^2 noise: exact %.1f, maxmip %.1f, cone %.1f\n",
                fetches(noise, "exact"), fetches(noise, "maxmip"), fetches(noise, "cone"));
}

TEST(ExactOracle, OracleMatchesBruteForceMarch) {
    // The oracle itself against a fine march with bisection (independent of its segment logic).
    HeightMap m = noisy_map(32, 3);
    PassSettings s;
    s.scale = 0.15f;
    GBuffer gb = make_scene(RandomScene{32, 8, 77, 10.0, 90.0});
    for (size_t k = 0; k < gb.pixels(); ++k) {
        double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
        PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s);
        ExactHit o = exact_hit(m, pr.u, pr.v, pr.V, s);
        auto gap = [&](double t) {
            return -t * pr.V[2] - s.scale * (bilinear_height(m, pr.u - t * pr.V[0],
                                                             pr.v - t * pr.V[1], s.address) -
                                             1.0);
        };
        double t1 = s.scale / pr.V[2], dt = t1 / 20000, t = 0;
        while (t < t1 && gap(t + dt) > 0) t += dt;
        double lo = t, hi = std::min(t + dt, t1);
        for (int it = 0; it < 60; ++it) {
            double mid = 0.5 * (lo + hi);
            (gap(mid) > 0 ? lo : hi) = mid;
        }
        // A march of 20000 steps can only miss a dip shallower than its step; none here is.
        EXPECT_NEAR(o.t, hi, 1e-9 + 1e-6 * t1) << k;
    }
}

}  // namespace
}  // namespace omtest
