// Seed methods against `exact`: convergence as their budgets grow and the seeds' claims that hold
// robustly, measured on documented settings. Errors are uv distances in texels.
#include <algorithm>

#include "support.hpp"

namespace omtest {
namespace {

struct Errors {
    double mean = 0, p99 = 0;
    std::vector<double> per_pixel;
};

Errors errors(const OffsetResult& r, const OffsetResult& ref, const HeightMap& m) {
    Errors e;
    for (size_t k = 0; k < r.uv.size(); ++k)
        e.per_pixel.push_back(std::hypot((r.uv[k].s[0] - ref.uv[k].s[0]) * m.width,
                                         (r.uv[k].s[1] - ref.uv[k].s[1]) * m.height));
    std::vector<double> sorted = e.per_pixel;
    std::sort(sorted.begin(), sorted.end());
    for (double x : sorted) e.mean += x / sorted.size();
    e.p99 = sorted[static_cast<size_t>(0.99 * (sorted.size() - 1))];
    return e;
}

struct Bench {
    HeightMap map = smooth_map(64);
    PassSettings s;
    GBuffer gb;
    OffsetResult exact;
    explicit Bench(double min_elev = 15.0, float scale = 0.08f) {
        s.scale = scale;
        gb = make_scene(RandomScene{64, 64, 99, min_elev, 90.0});
        exact = run("exact", map, gb, s);
    }
    Errors of(const std::string& method, const std::map<std::string, std::string>& params = {}) {
        return errors(run(method, map, gb, s, params), exact, map);
    }
};

TEST(Convergence, SteepErrorIsBoundedByOneLayer) {
    // The first layer at or below the surface lies within one layer of the hit along the ray:
    // a uv error of at most s cot(elevation) / n, unless the march stepped over a crest thinner
    // than a layer. On this smooth map that happens to well under 1% of rays.
    Bench st;
    double prev_mean = 1e9;
    for (int n : {8, 32, 128}) {
        Errors e = st.of("steep", {{"layers", std::to_string(n)}});
        size_t over = 0;
        for (size_t k = 0; k < st.gb.pixels(); ++k) {
            double vz = st.gb.view[k].s[2];
            double vxy = std::sqrt(1 - vz * vz);
            double bound = st.s.scale * vxy / vz / n * st.map.width + 1e-3;
            over += e.per_pixel[k] > bound;
        }
        std::printf("steep layers=%d: mean %.4f p99 %.4f texels, %zu over the layer bound\n", n, e.mean, e.p99, over);
        EXPECT_LT(over, st.gb.pixels() / 100) << n;
        EXPECT_LT(e.mean, 0.5 * prev_mean) << n;
        prev_mean = e.mean;
    }
    EXPECT_LT(prev_mean, 0.05);
}

TEST(Convergence, ReliefAndPomFallTowardZero) {
    // relief: the binary search halves a one-layer bracket m times: error <= layer / 2^m.
    // pom: the secant through the last two samples has error O(layer^2 * curvature).
    Bench st;
    double prev = 1e9;
    for (auto [n, m] : std::vector<std::pair<int, int>>{{8, 2}, {16, 6}, {64, 12}}) {
        Errors e = st.of("relief", {{"linear", std::to_string(n)}, {"binary", std::to_string(m)}});
        std::printf("relief linear=%d binary=%d: mean %.5f p99 %.5f\n", n, m, e.mean, e.p99);
        EXPECT_LT(e.mean, prev);
        prev = e.mean;
        if (n == 64) {
            EXPECT_LT(e.p99, 1e-2);
        }
    }
    prev = 1e9;
    for (int n : {8, 32, 128}) {
        auto ns = std::to_string(n);
        Errors e = st.of("pom", {{"min_samples", ns}, {"max_samples", ns}});
        std::printf("pom samples=%d: mean %.5f p99 %.5f\n", n, e.mean, e.p99);
        EXPECT_LT(e.mean, 0.5 * prev);
        prev = e.mean;
        if (n == 128) {
            EXPECT_LT(e.p99, 1e-2);
        }
    }
}

TEST(SeedClaims, SlopeBeatsParallaxOnSmoothSlopes) {
    // Premecz: the tangent plane follows a sloped surface where parallax assumes it flat.
    // Documented setting: smooth map, s = 0.05, elevations 30-90 degrees.
    Bench st(30.0, 0.05f);
    Errors par = st.of("parallax");
    Errors slope = st.of("parallax-slope");
    Errors safe = st.of("parallax-slope", {{"safe", "1"}});
    std::printf("mean error: parallax %.4f, slope %.4f, slope (safe) %.4f\n", par.mean, slope.mean, safe.mean);
    EXPECT_LT(slope.mean, 0.7 * par.mean);
}

TEST(SeedClaims, IterationsBeatOneSlopeStep) {
    // Premecz: repeating the slope step 3-4 times converges toward the hit on smooth relief.
    Bench st(30.0, 0.05f);
    Errors one = st.of("parallax-slope");
    Errors four = st.of("parallax-iterative", {{"iterations", "4"}});
    Errors k1 = st.of("parallax-iterative", {{"iterations", "1"}});
    std::printf("mean error: slope %.4f, iterative k=4 %.4f\n", one.mean, four.mean);
    EXPECT_LT(four.mean, 0.5 * one.mean);
    EXPECT_NEAR(k1.mean, one.mean, 1e-6);  // k = 1 is parallax-slope
}

TEST(SeedClaims, PomBeatsSteepAtEqualLayers) {
    // Tatarchuk: intersecting the segment between the last two samples recovers most of the
    // layer quantisation steep parallax keeps.
    Bench st;
    for (int n : {8, 16, 32}) {
        auto ns = std::to_string(n);
        Errors steep = st.of("steep", {{"layers", ns}});
        Errors pom = st.of("pom", {{"min_samples", ns}, {"max_samples", ns}});
        std::printf("layers %d: steep %.4f, pom %.4f\n", n, steep.mean, pom.mean);
        EXPECT_LT(pom.mean, 0.5 * steep.mean) << n;
    }
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

TEST(Convergence, SphereFallsTowardZeroAsItsMapAndStepsGrow) {
    // Bound: the march stops when its voxel touches the column proxy, so the stop point is within
    // one voxel (1/res across, s/layers in height) of the surface, the proxy's excess over it
    // being at most slope x 1/res (the proxy is the exact maximum per column); the error along the
    // ray is that distance over the sine of the ray-surface angle, unless the steps run out
    // first. So the error falls linearly with the voxel size: x4 finer, about 4x smaller.
    Bench st(15.0, 0.08f);
    double prev = 1e9;
    for (auto [res, layers, steps] : std::vector<std::tuple<int, int, int>>{{32, 8, 16}, {64, 16, 48}, {256, 64, 192}}) {
        Errors e = st.of("sphere", {{"res", std::to_string(res)}, {"layers", std::to_string(layers)},
                                    {"steps", std::to_string(steps)}});
        std::printf("sphere res=%d layers=%d steps=%d: mean %.4f p99 %.4f\n", res, layers, steps, e.mean, e.p99);
        EXPECT_LT(e.mean, 0.6 * prev);
        prev = e.mean;
    }
    EXPECT_LT(prev, 0.3);  // res 256: a quarter texel of this 64-texel map
}

TEST(SeedClaims, SphereNeverOvershootsAThinSpikeSteepSkips) {
    // One-texel spikes of height 1 on a floor of 0 (fur-like). Rays that pass the spike's bilinear
    // tent between two of steep's layers come out behind it; sphere tracing may stop short of the
    // hit but never passes it: its t never exceeds the exact t.
    const int n = 64;
    HeightMap m = make_map(n, n, [](int i, int j) { return (i % 16 == 8 && j % 16 == 8) ? 1.0f : 0.0f; });
    PassSettings s;
    s.scale = 0.1f;
    GBuffer gb = make_scene(RandomScene{128, 128, 17, 10.0, 60.0});
    OffsetResult ex = run("exact", m, gb, s);
    OffsetResult sp = run("sphere", m, gb, s, {{"res", "64"}, {"layers", "16"}, {"steps", "64"}});
    OffsetResult st = run("steep", m, gb, s, {{"layers", "8"}});
    size_t spike_hits = 0, steep_skips = 0, sphere_over = 0;
    for (size_t k = 0; k < gb.pixels(); ++k) {
        double t_floor = s.scale / gb.view[k].s[2];
        if (ex.depth[k] > t_floor - 1e-6) continue;  // the ray met the floor: no spike on its way
        ++spike_hits;
        steep_skips += st.depth[k] > ex.depth[k] + 0.05 * t_floor;
        sphere_over += sp.depth[k] > ex.depth[k] + 1e-5;
    }
    std::printf("%zu rays hit a spike: steep (8 layers) passed %zu of them, sphere %zu\n", spike_hits,
                steep_skips, sphere_over);
    ASSERT_GT(spike_hits, 100u);
    EXPECT_GT(steep_skips, spike_hits / 10);
    EXPECT_EQ(sphere_over, 0u);
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

TEST(Secant, RefinesFasterThanBinarySearchAndIsPomWithoutRefinement) {
    // Risser et al.: secant refinement reaches a given accuracy in fewer fetches than binary
    // search. Same 16-step linear search (min = max = 16 samples) for both.
    Bench st(15.0, 0.08f);
    auto sec = [&](const char* refine) {
        return st.of("secant", {{"min_samples", "16"}, {"max_samples", "16"}, {"refine", refine}, {"tol", "0"}});
    };
    Errors sec2 = sec("2"), sec4 = sec("4"), sec0 = sec("0");
    Errors rel2 = st.of("relief", {{"linear", "16"}, {"binary", "2"}});
    Errors rel6 = st.of("relief", {{"linear", "16"}, {"binary", "6"}});
    Errors pom = st.of("pom", {{"min_samples", "16"}, {"max_samples", "16"}});
    std::printf("16 linear steps + 2 refinements: secant %.6f, relief %.5f; secant 4 %.7f vs relief 6 %.5f\n",
                sec2.mean, rel2.mean, sec4.mean, rel6.mean);
    EXPECT_LT(sec2.mean, 0.25 * rel2.mean);
    EXPECT_LT(sec4.mean, rel6.mean);  // fewer fetches, lower error
    for (size_t k = 0; k < sec0.per_pixel.size(); ++k)
        ASSERT_EQ(sec0.per_pixel[k], pom.per_pixel[k]) << "refine = 0 must be pom, pixel " << k;
    // And it converges: 64 linear steps and 8 refinements on a smooth map are exact to 1e-3 texel.
    Errors fine = st.of("secant", {{"min_samples", "64"}, {"max_samples", "64"}, {"refine", "8"}, {"tol", "0"}});
    EXPECT_LT(fine.p99, 1e-3);
}

}  // namespace
}  // namespace omtest
