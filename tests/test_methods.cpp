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

TEST(Convergence, SteepStopsAtItsFirstLayerBelowTheRelief) {
    // steep's answer is the first of its n + 1 layer samples t_i = t_enter + i (t_exit - t_enter)
    // / n at or below the relief; checked per ray against the relief in double precision. So the
    // exact hit lies within one layer before it (a uv error of at most s cot(elevation) / n),
    // unless the ray crossed a crest between two samples above the relief: then the exact hit
    // lies before the last sample above. Every ray is one or the other (no tolerance on the
    // count); samples within 1e-5 of the relief (float rounding of H and of the sample position)
    // may fall either way.
    // On the smooth map the error halves with each doubling of layers; on noise (texels
    // independent) rays do cross crests between samples.
    for (bool noisy : {false, true}) {
        Bench st;
        if (noisy) {
            st.map = noisy_map(64, 3);
            st.exact = run("exact", st.map, st.gb, st.s);
        }
        const double eps = 1e-5;
        double prev_mean = 1e9;
        for (int n : {8, 32, 128}) {
            OffsetResult r = run("steep", st.map, st.gb, st.s, {{"layers", std::to_string(n)}});
            Errors e = errors(r, st.exact, st.map);
            size_t within = 0, crest = 0;
            for (size_t k = 0; k < st.gb.pixels(); ++k) {
                double V[3] = {st.gb.view[k].s[0], st.gb.view[k].s[1], st.gb.view[k].s[2]};
                PreparedRay pr = prepare_ray(st.gb.uv[k].s[0], st.gb.uv[k].s[1], V, st.s);
                const double t1 = st.s.scale / pr.V[2];  // r = 1: t_enter = 0
                // The ray's height over the relief at layer i, in units of H: lambda_i = i / n.
                auto above = [&](int i) {
                    const double t = t1 * i / n;
                    return bilinear_height(st.map, pr.u - t * pr.V[0], pr.v - t * pr.V[1],
                                           st.s.address) -
                           (1.0 - static_cast<double>(i) / n);
                };
                const double li = r.depth[k] / t1 * n;
                const int i = static_cast<int>(std::lround(li));
                ASSERT_NEAR(li, i, 1e-3) << "steep stops on a layer, pixel " << k;
                ASSERT_GE(above(i), -eps)
                    << "layer " << i << " is at or below the relief, pixel " << k;
                for (int j = 0; j < i; ++j)
                    ASSERT_LT(above(j), eps) << "layer " << j << " is above, pixel " << k;
                const double t_exact = st.exact.depth[k];
                ASSERT_LE(t_exact, r.depth[k] + 1e-6) << "the exact hit comes first, pixel " << k;
                if (t_exact >= t1 * (i - 1) / n - 1e-6) {
                    ++within;
                    const double vxy = std::sqrt(1 - pr.V[2] * pr.V[2]);
                    EXPECT_LE(e.per_pixel[k], st.s.scale * vxy / pr.V[2] / n * st.map.width + 1e-3)
                        << "one layer, pixel " << k;
                } else {
                    ++crest;  // below the relief at t_exact, above it again at layer i - 1
                }
            }
            std::printf(
                "steep layers=%d on %s: mean %.4f p99 %.4f texels; %zu rays within one "
                "layer, %zu crossed a crest between samples\n",
                n, noisy ? "noise" : "smooth", e.mean, e.p99, within, crest);
            const std::string key = std::string("steep.") + (noisy ? "noise" : "smooth") +
                                    ".layers" + std::to_string(n);
            record_figure(key + ".mean", e.mean);
            record_figure(key + ".crest_rays", static_cast<double>(crest));
            if (!noisy) {
                EXPECT_LT(e.mean, 0.5 * prev_mean) << n;  // layers x4: the one-layer bound / 4
            } else if (n == 8) {
                EXPECT_GT(crest, 0u) << "the crest case is exercised";
            }
            prev_mean = e.mean;
        }
    }
}

TEST(Convergence, ReliefAndPomFallTowardZero) {
    // relief: the binary search halves a one-layer bracket m times: error <= layer / 2^m.
    // pom: the secant through the last two samples has error O(layer^2 * curvature).
    Bench st;
    double prev = 1e9;
    for (auto [n, m] : std::vector<std::pair<int, int>>{{8, 2}, {16, 6}, {64, 12}}) {
        Errors e = st.of("relief", {{"linear", std::to_string(n)}, {"binary", std::to_string(m)}});
        std::printf("relief linear=%d binary=%d: mean %.5f p99 %.5f\n", n, m, e.mean, e.p99);
        record_figure("relief.linear" + std::to_string(n) + ".binary" + std::to_string(m) + ".mean",
                      e.mean);
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
        record_figure("pom.samples" + std::to_string(n) + ".mean", e.mean);
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
    std::printf("mean error: parallax %.4f, slope %.4f, slope (safe) %.4f\n", par.mean, slope.mean,
                safe.mean);
    record_figure("premecz.parallax.mean", par.mean);
    record_figure("premecz.slope.mean", slope.mean);
    record_figure("premecz.slope_safe.mean", safe.mean);
    EXPECT_LT(slope.mean, par.mean);
    // Premecz's safe form drops the 1 / (N.V) factor, which is 1 / V.z on a flat patch: every
    // off-vertical step falls short by V.z of its length, so it is worse than plain parallax.
    EXPECT_GT(safe.mean, par.mean);
}

TEST(SeedClaims, IterationsBeatOneSlopeStep) {
    // Premecz: repeating the slope step 3-4 times converges toward the hit on smooth relief.
    Bench st(30.0, 0.05f);
    Errors one = st.of("parallax-slope");
    Errors four = st.of("parallax-iterative", {{"iterations", "4"}});
    Errors k1 = st.of("parallax-iterative", {{"iterations", "1"}});
    std::printf("mean error: slope %.4f, iterative k=4 %.4f\n", one.mean, four.mean);
    record_figure("premecz.iterative4.mean", four.mean);
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
        record_figure("tatarchuk.layers" + std::to_string(n) + ".steep", steep.mean);
        record_figure("tatarchuk.layers" + std::to_string(n) + ".pom", pom.mean);
        EXPECT_LT(pom.mean, 0.5 * steep.mean) << n;
    }
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

// The largest height of the bilinear relief over the uv square [x0, x1] x [y0, y1]: a bilinear
// patch peaks at a corner of any rectangle inside it, so the maximum is on the grid of the square's
// edges and the patch lines (texel centres) between them.
double square_max(const HeightMap& m, double x0, double x1, double y0, double y1,
                  AddressMode address = AddressMode::Wrap) {
    auto lines = [](double a, double b, int n) {
        std::vector<double> l = {a, b};
        for (double c = std::ceil(a * n - 0.5); (c + 0.5) / n < b; c += 1.0)
            l.push_back((c + 0.5) / n);
        return l;
    };
    double best = 0.0;
    for (double u : lines(x0, x1, m.width))
        for (double v : lines(y0, y1, m.height))
            best = std::max(best, bilinear_height(m, u, v, address));
    return best;
}

TEST(Convergence, SphereStopsWithinAVoxelOfItsProxyAndNeverPassesTheHit) {
    // sphere's contract without cells (kernels/methods/sphere.cl, Donnelly's): it steps by the
    // distance from its voxel's box to a column proxy (per uv square of the res^2 grid, a box up to
    // the exact maximum of the relief over that square), so it never passes the exact hit, and it
    // stops where that distance is 0: its voxel touches a column box of its own or a neighbouring
    // square, so the stop point is at most one layer (s / layers) above that column's top. Checked
    // per ray against the columns computed here in double precision (1e-4 of a voxel of slack for
    // points on voxel faces). The error this leaves is set by the voxel size and shrinks as res and
    // layers grow together (reported).
    Bench st(15.0, 0.08f);
    double prev = 1e9;
    for (auto [res, layers] : std::vector<std::pair<int, int>>{{32, 8}, {64, 16}, {256, 64}}) {
        const int steps = 256;
        OffsetResult r = run("sphere", st.map, st.gb, st.s,
                             {{"res", std::to_string(res)},
                              {"layers", std::to_string(layers)},
                              {"steps", std::to_string(steps)},
                              {"cells", "0"}});
        Errors e = errors(r, st.exact, st.map);
        std::vector<double> colmax(static_cast<size_t>(res) * res);
        for (int j = 0; j < res; ++j)
            for (int i = 0; i < res; ++i)
                colmax[j * res + i] = square_max(st.map, double(i) / res, double(i + 1) / res,
                                                 double(j) / res, double(j + 1) / res);
        size_t stopped = 0;
        for (size_t k = 0; k < st.gb.pixels(); ++k) {
            ASSERT_LE(r.depth[k], st.exact.depth[k] + 1e-6) << "passed the hit, pixel " << k;
            if (r.fetches[k] >= static_cast<unsigned>(steps)) continue;  // ran out of steps
            ++stopped;
            const double V[3] = {st.gb.view[k].s[0], st.gb.view[k].s[1], st.gb.view[k].s[2]};
            PreparedRay pr = prepare_ray(st.gb.uv[k].s[0], st.gb.uv[k].s[1], V, st.s);
            const double t = r.depth[k];
            const double u = pr.u - t * pr.V[0], v = pr.v - t * pr.V[1];
            const double w = st.s.scale - t * pr.V[2];  // s H of the ray (r = 1)
            const double slack = 1e-4 / res;
            double top = 0.0;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    // Squares that the voxel (found with slack on either side of a face) touches.
                    for (double ou : {-slack, slack})
                        for (double ov : {-slack, slack}) {
                            long ci = static_cast<long>(std::floor((u + ou) * res)) + di;
                            long cj = static_cast<long>(std::floor((v + ov) * res)) + dj;
                            ci = ((ci % res) + res) % res;
                            cj = ((cj % res) + res) % res;
                            top = std::max(top, colmax[cj * res + ci]);
                        }
                }
            ASSERT_LE(w, st.s.scale * (top + (1.0 + 1e-4) / layers))
                << "stopped more than a layer above every column it touches, pixel " << k;
        }
        std::printf(
            "sphere res=%d layers=%d: mean %.4f p99 %.4f texels, %zu of %zu rays stopped "
            "at the proxy\n",
            res, layers, e.mean, e.p99, stopped, st.gb.pixels());
        record_figure("sphere.res" + std::to_string(res) + ".mean", e.mean);
        EXPECT_GT(stopped, st.gb.pixels() * 9 / 10);
        EXPECT_LT(e.mean, prev);
        prev = e.mean;
    }
}

TEST(Sphere, DistanceMapIsTheBoxDistanceToTheColumnProxy) {
    // The stored distance of voxel (i, j, k), straight from its definition in double precision:
    // the distance from the voxel's box (uv square (i, j) of the res^2 grid, heights w in
    // [k, k + 1] s / layers) to the nearest column box (uv square (ci, cj), w from 0 up to s times
    // the relief's maximum over that square). Wrap: columns tile; clamp: columns past the edge
    // repeat the edge column (the extruded relief). Float rounding of the sums: 1e-6 uv.
    const int n = 16, res = 16, layers = 4;
    HeightMap map = noisy_map(n, 13);
    for (AddressMode address : {AddressMode::Wrap, AddressMode::Clamp}) {
        PassSettings s;
        s.scale = 0.2f;
        s.address = address;
        auto rt = runtime();
        DeviceHeightField f = upload(*rt, map, s);
        OffsetPass pass(rt, "sphere",
                        {{"res", std::to_string(res)}, {"layers", std::to_string(layers)}});
        pass.prepare(f, s);
        std::vector<float> dist(static_cast<size_t>(res) * res * layers);
        ASSERT_EQ(pass.precomputed().bytes, dist.size() * sizeof(float));
        rt->queue().enqueueReadBuffer(pass.precomputed_buffer(), CL_TRUE, 0,
                                      dist.size() * sizeof(float), dist.data());
        std::vector<double> colmax(static_cast<size_t>(res) * res);
        for (int j = 0; j < res; ++j)
            for (int i = 0; i < res; ++i)
                colmax[j * res + i] = square_max(map, double(i) / res, double(i + 1) / res,
                                                 double(j) / res, double(j + 1) / res, address);
        const bool wrap = address == AddressMode::Wrap;
        double worst = 0.0;
        for (int k = 0; k < layers; ++k)
            for (int j = 0; j < res; ++j)
                for (int i = 0; i < res; ++i) {
                    const double w_low = s.scale * k / layers;
                    double best = w_low;  // the floor w = 0
                    for (int cj = j - res; cj < j + res; ++cj)
                        for (int ci = i - res; ci < i + res; ++ci) {
                            const int mi =
                                wrap ? ((ci % res) + res) % res : std::clamp(ci, 0, res - 1);
                            const int mj =
                                wrap ? ((cj % res) + res) % res : std::clamp(cj, 0, res - 1);
                            const double gx = std::max(std::abs(ci - i) - 1, 0) / double(res);
                            const double gy = std::max(std::abs(cj - j) - 1, 0) / double(res);
                            const double gz =
                                std::max(w_low - s.scale * colmax[mj * res + mi], 0.0);
                            best = std::min(best, std::sqrt(gx * gx + gy * gy + gz * gz));
                        }
                    const double stored = dist[(static_cast<size_t>(k) * res + j) * res + i];
                    worst = std::max(worst, std::fabs(stored - best));
                    ASSERT_NEAR(stored, best, 1e-6)
                        << "voxel " << i << "," << j << "," << k << (wrap ? " wrap" : " clamp");
                }
        std::printf("distance map %d^2 x %d (%s): worst %.1e uv from the definition\n", res, layers,
                    wrap ? "wrap" : "clamp", worst);
    }
}

TEST(SeedClaims, SphereNeverOvershootsAThinSpikeSteepSkips) {
    // One-texel spikes of height 1 on a floor of 0 (fur-like). Rays that pass the spike's bilinear
    // tent between two of steep's layers come out behind it; sphere tracing may stop short of the
    // hit but never passes it: its t never exceeds the exact t.
    const int n = 64;
    HeightMap m =
        make_map(n, n, [](int i, int j) { return (i % 16 == 8 && j % 16 == 8) ? 1.0f : 0.0f; });
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
    std::printf("%zu rays hit a spike: steep (8 layers) passed %zu of them, sphere %zu\n",
                spike_hits, steep_skips, sphere_over);
    record_figure("spikes.hits", static_cast<double>(spike_hits));
    record_figure("spikes.steep8_passed", static_cast<double>(steep_skips));
    record_figure("spikes.sphere_passed", static_cast<double>(sphere_over));
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
        return st.of(
            "secant",
            {{"min_samples", "16"}, {"max_samples", "16"}, {"refine", refine}, {"tol", "0"}});
    };
    Errors sec2 = sec("2"), sec4 = sec("4");
    Errors rel2 = st.of("relief", {{"linear", "16"}, {"binary", "2"}});
    Errors rel6 = st.of("relief", {{"linear", "16"}, {"binary", "6"}});
    Errors pom = st.of("pom", {{"min_samples", "16"}, {"max_samples", "16"}});
    std::printf(
        "16 linear steps + 2 refinements: secant %.6f, relief %.5f; secant 4 %.7f vs relief 6 "
        "%.5f\n",
        sec2.mean, rel2.mean, sec4.mean, rel6.mean);
    record_figure("secant.refine2.mean", sec2.mean);
    record_figure("relief.binary2.mean", rel2.mean);
    record_figure("secant.refine4.mean", sec4.mean);
    record_figure("relief.binary6.mean", rel6.mean);
    EXPECT_LT(sec2.mean, 0.25 * rel2.mean);
    EXPECT_LT(sec4.mean, rel6.mean);  // fewer fetches, lower error
    // refine = 0 is pom bit for bit: uv', depth, fetches and flags (at its default tol too).
    for (const char* tol : {"0", "1e-4"}) {
        auto params = std::map<std::string, std::string>{
            {"min_samples", "16"}, {"max_samples", "16"}, {"refine", "0"}, {"tol", tol}};
        OffsetResult s0 = run("secant", st.map, st.gb, st.s, params);
        OffsetResult p0 =
            run("pom", st.map, st.gb, st.s, {{"min_samples", "16"}, {"max_samples", "16"}});
        ASSERT_EQ(std::memcmp(s0.uv.data(), p0.uv.data(), s0.uv.size() * sizeof(cl_float2)), 0)
            << tol;
        ASSERT_EQ(s0.depth, p0.depth) << tol;
        ASSERT_EQ(s0.fetches, p0.fetches) << tol;
        ASSERT_EQ(s0.flags, p0.flags) << tol;
    }
    // And it converges: 64 linear steps and 8 refinements on a smooth map are exact to 1e-3 texel.
    Errors fine = st.of(
        "secant", {{"min_samples", "64"}, {"max_samples", "64"}, {"refine", "8"}, {"tol", "0"}});
    EXPECT_LT(fine.p99, 1e-3);
}

}  // namespace
}  // namespace omtest
