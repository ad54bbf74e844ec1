// The offset pass over a curved base (the G-buffer's curvature plane): zero curvature is today's
// pass bit for bit, pixel by pixel even beside curved ones; the cell walk is the curved oracle's
// hit within its chords' bound; every method leaves a sphere where the analytic ray does, and
// flags it SILHOUETTE; a concave base is never left.
#include <cmath>
#include <random>

#include "curved_rays.hpp"
#include "offsetmap/oracle.hpp"
#include "support.hpp"

namespace omtest {
namespace {

GBuffer curved_gbuffer(const std::vector<CurvedRay>& rays) {
    std::vector<std::array<float, 5>> px;
    for (const CurvedRay& r : rays) px.push_back({r.u, r.v, r.V[0], r.V[1], r.V[2]});
    GBuffer gb = row_gbuffer(px);
    gb.curvature.resize(rays.size());
    for (size_t k = 0; k < rays.size(); ++k)
        gb.curvature[k] = {{static_cast<float>(rays[k].K.uu), static_cast<float>(rays[k].K.uv),
                            static_cast<float>(rays[k].K.vv),
                            static_cast<float>(rays[k].K.stretch)}};
    return gb;
}

// Every method with a curvature plane of zeros gives the pass without one, bit for bit; with half
// the pixels curved (each block mixed), the flat half still does.
TEST(CurvedTrace, ZeroCurvatureIsTodaysPassBitForBit) {
    const HeightMap map = noisy_map(64);
    const PassSettings s = wrap_settings(0.06f, 0.8f);
    std::vector<CurvedRay> rays = random_rays(256, {Curvature{}}, 7);
    GBuffer none = curved_gbuffer(rays);
    none.curvature.clear();
    GBuffer zero = curved_gbuffer(rays);
    // A stretch of 1, or one not a finite value above 0, is none.
    const float no_stretch[] = {1.0f, 0.0f, -2.0f, NAN, INFINITY, -INFINITY};
    for (size_t k = 0; k < rays.size(); ++k) zero.curvature[k].s[3] = no_stretch[k % 6];
    for (size_t k = 1; k < rays.size(); k += 2) rays[k].K = Curvature{1.5, 0.4, -0.7};
    const GBuffer mixed = curved_gbuffer(rays);
    for (const std::string& method : method_names()) {
        const OffsetResult a = run(method, map, none, s);
        const OffsetResult b = run(method, map, zero, s);
        const OffsetResult c = run(method, map, mixed, s);
        for (size_t k = 0; k < rays.size(); ++k) {
            SCOPED_TRACE(method + ", pixel " + std::to_string(k));
            ASSERT_EQ(std::memcmp(&a.uv[k], &b.uv[k], sizeof(cl_float2)), 0);
            ASSERT_EQ(std::memcmp(&a.depth[k], &b.depth[k], sizeof(float)), 0);
            ASSERT_EQ(a.fetches[k], b.fetches[k]);
            ASSERT_EQ(a.flags[k], b.flags[k]);
            if (k % 2 == 1) continue;
            ASSERT_EQ(std::memcmp(&a.uv[k], &c.uv[k], sizeof(cl_float2)), 0);
            ASSERT_EQ(std::memcmp(&a.depth[k], &c.depth[k], sizeof(float)), 0);
            ASSERT_EQ(a.fetches[k], c.fetches[k]);
            ASSERT_EQ(a.flags[k], c.flags[k]);
        }
    }
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

// Rays over a sphere, a cylinder, a saddle, a bowl, a gentle sphere, a sphere whose uv is stretched
// and a plane whose uv is, 12 to 85 degrees, and the
// curved oracle's answers for them and for the same rays over the plane.
struct Curved {
    HeightMap map;
    PassSettings s;
    std::vector<CurvedRay> rays;
    GBuffer gb, plane;
    std::vector<CurvedHit> want, want_plane;

    Curved(HeightMap m, unsigned seed) : map(std::move(m)), s(wrap_settings(0.06f, 0.8f)) {
        rays = random_rays(1500,
                           {{1.5, 0.0, 1.5},
                            {2.0, 0.0, 0.0},
                            {1.0, 0.5, -0.8},
                            {-1.2, 0.0, -1.2},
                            {0.3, 0.0, 0.3},
                            {1.5, 0.0, 1.5, 1.25},
                            {0.0, 0.0, 0.0, 0.7}},
                           seed);
        gb = curved_gbuffer(rays);
        plane = gb;
        plane.curvature.clear();
        for (const CurvedRay& r : rays) {
            const double V[3] = {r.V[0], r.V[1], r.V[2]};
            want.push_back(curved_hit(map, r.u, r.v, V, s, r.K));
            want_plane.push_back(curved_hit(map, r.u, r.v, V, s, Curvature{}));
        }
    }
};

// The model's gap (ray height minus relief, uv units) for ray k at t, in double precision.
double model_gap(const Curved& c, size_t k, double t) {
    const CurvedRay& r = c.rays[k];
    const double V[3] = {r.V[0], r.V[1], r.V[2]};
    const CurvedPoint p = curved_point(V, r.K, t);
    return p.h - c.s.scale * (bilinear_height(c.map, r.u + p.dx, r.v + p.dy, c.s.address) -
                              c.s.reference_plane);
}

// The cell walks (exact, cone, maxmip, sphere) over a curved base: every chord's root refined by
// Newton on the curve is the curved oracle's hit, and a ray leaves exactly where the oracle's
// does. Tolerance 1/32 texel: the oracle's own step. A crest the ray grazes within one of the
// oracle's steps may be stepped over by it: where the kernel's hit comes first, its point must lie
// on the relief (the model's gap there within float rounding, 2e-6 uv).
TEST(CurvedTrace, CellWalksAreTheCurvedOracle) {
    for (const HeightMap& map : {smooth_map(64), noisy_map(64)}) {
        const Curved c(map, 9);
        for (const char* method : {"exact", "cone", "maxmip", "sphere"}) {
            const OffsetResult got = run(method, c.map, c.gb, c.s);
            double worst = 0.0;
            int left = 0, crests = 0;
            for (size_t k = 0; k < c.rays.size(); ++k) {
                SCOPED_TRACE(std::string(method) + ", ray " + std::to_string(k));
                const bool miss = got.flags[k] & OM_FLAG_SILHOUETTE;
                ASSERT_EQ(miss, c.want[k].miss);
                left += miss;
                if (miss) continue;
                const double e = texels(c.want[k], got.uv[k], 64);
                if (got.depth[k] < c.want[k].t && e > 1.0 / 32.0) {
                    // A crest the oracle stepped over: the kernel's point is on the relief.
                    ASSERT_LE(std::fabs(model_gap(c, k, got.depth[k])), 2e-6);
                    ++crests;
                    continue;
                }
                ASSERT_LE(e, 1.0 / 32.0);
                worst = std::max(worst, e);
            }
            std::printf(
                "%-7s %4zu rays: %d left the relief, %d crests the oracle missed, worst |uv - "
                "oracle| %.2e texel\n",
                method, c.rays.size(), left, crests, worst);
        }
    }
}

// The marching and slope methods over a curved base: the same march along the bent ray, so its
// error against the curved oracle is its error on the plane against the plane's: p95 within 2.5x
// (a convex base's rays that leave through the top run up to twice as far at the same sample
// count) plus 0.002 texel.
TEST(CurvedTrace, MarchesErrAsOnThePlane) {
    const Curved c(smooth_map(64), 5);
    for (const char* method :
         {"parallax", "parallax-slope", "parallax-iterative", "steep", "relief", "pom", "secant"}) {
        const OffsetResult got = run(method, c.map, c.gb, c.s);
        const OffsetResult plane = run(method, c.map, c.plane, c.s);
        std::vector<double> e, ep;
        for (size_t k = 0; k < c.rays.size(); ++k) {
            ep.push_back(texels(c.want_plane[k], plane.uv[k], 64));
            if (!(got.flags[k] & OM_FLAG_SILHOUETTE) && !c.want[k].miss)
                e.push_back(texels(c.want[k], got.uv[k], 64));
        }
        std::sort(e.begin(), e.end());
        std::sort(ep.begin(), ep.end());
        const double p95 = e[e.size() * 95 / 100], p95_plane = ep[ep.size() * 95 / 100];
        std::printf("%-19s p95 %.4f texel over the curved bases, %.4f on the plane\n", method, p95,
                    p95_plane);
        EXPECT_LE(p95, 2.5 * p95_plane + 0.002) << method;
    }
}

// A constant height over a sphere of radius rho: the relief is the sphere of rho + s (H - r), the
// slab's top that of rho + s (1 - r). Every method that traces says SILHOUETTE exactly where the
// ray misses the first; its t is the analytic one: to float rounding for parallax (the level's
// circle) and the cell walks, within one step of the march for the marching methods (the search
// brackets the hit and every refinement stays inside). parallax-slope's one step from the polygon
// cannot tell, and none and parallax-limited do not trace.
TEST(CurvedTrace, SphereIsLeftWhereTheAnalyticRayLeaves) {
    const double rho = 0.64, H = double(0.6f);
    const HeightMap map = constant_map(0.6f);
    const Curvature K{1.0 / rho, 0.0, 1.0 / rho};
    struct Row {
        const char* method;
        double steps;  // the march's fewest samples; 0: exact
    };
    std::map<std::string, int> left;
    for (const float ref : {1.0f, 0.5f}) {
        const PassSettings s = wrap_settings(0.04f, ref);
        std::vector<CurvedRay> rays;
        for (double deg = 1.0; deg <= 90.0; deg += 0.5)
            rays.push_back({0.25f, 0.5f, view_dir(deg, 40.0), K});
        const GBuffer gb = curved_gbuffer(rays);
        for (const Row& row :
             {Row{"parallax", 0}, Row{"exact", 0}, Row{"cone", 0}, Row{"maxmip", 0},
              Row{"sphere", 0}, Row{"parallax-iterative", -1}, Row{"steep", 16}, Row{"relief", 8},
              Row{"pom", 8}, Row{"secant", 8}}) {
            const OffsetResult got = run(row.method, map, gb, s);
            for (size_t k = 0; k < rays.size(); ++k) {
                SCOPED_TRACE(std::string(row.method) + ", r " + std::to_string(ref) + ", " +
                             std::to_string(1.0 + 0.5 * k) + " degrees");
                const double vz = rays[k].V[2];
                // |p(t) - centre|^2 = R^2, p(t) = -t V, centre (0, 0, -rho).
                auto disc = [&](double R) { return rho * rho * vz * vz - (rho * rho - R * R); };
                auto root = [&](double R, double sign) {
                    return rho * vz + sign * std::sqrt(std::max(disc(R), 0.0));
                };
                const double relief = rho + s.scale * (H - ref), top = rho + s.scale * (1.0 - ref),
                             bottom = rho - s.scale * ref;
                if (std::fabs(disc(relief)) < 1e-6) continue;  // grazes the relief's sphere
                const bool hit = disc(relief) > 0.0;
                const bool miss = got.flags[k] & OM_FLAG_SILHOUETTE;
                ASSERT_EQ(miss, !hit);
                left[row.method] += miss;
                if (row.steps < 0) continue;
                const double t = hit ? root(relief, -1.0) : root(top, 1.0);
                const double t_in = root(top, -1.0),
                             t_out = disc(bottom) > 0.0 ? root(bottom, -1.0) : root(top, 1.0);
                const double tol = row.steps > 0 ? (t_out - t_in) / row.steps : 2e-5;
                ASSERT_NEAR(got.depth[k], t, tol);
            }
        }
    }
    for (const auto& [method, n] : left) EXPECT_GT(n, 5) << method;  // at r = 1, below 13 degrees
}

// A bowl (the inside of a sphere) is never left: its rays all reach the bottom.
TEST(CurvedTrace, ConcaveBaseIsNeverLeft) {
    const HeightMap map = noisy_map(64);
    const PassSettings s = wrap_settings(0.06f, 0.5f);
    std::vector<CurvedRay> rays = random_rays(400, {{-1.5, 0.0, -1.5}, {-2.0, 0.0, 0.0}}, 4);
    for (size_t k = 0; k < rays.size(); k += 4) rays[k].V = view_dir(2.0, 37.0 * k);
    const GBuffer gb = curved_gbuffer(rays);
    for (const std::string& method : method_names()) {
        const OffsetResult got = run(method, map, gb, s);
        for (size_t k = 0; k < rays.size(); ++k)
            ASSERT_FALSE(got.flags[k] & OM_FLAG_SILHOUETTE) << method << ", ray " << k;
    }
}

}  // namespace
}  // namespace omtest
