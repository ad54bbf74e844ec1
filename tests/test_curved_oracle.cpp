// The oracle of the relief over a curved base (curved_hit): zero curvature is the flat oracle,
// a sphere of known radius is hit, or left, at the analytic point (its model is exact there), and
// a cylinder traced along its axis is flat.
#include <cmath>
#include <random>

#include "offsetmap/oracle.hpp"
#include "support.hpp"

namespace omtest {
namespace {

// A unit view at elevation `deg` and azimuth `az` (radians).
void view(double deg, double az, double V[3]) {
    const double e = deg * M_PI / 180.0;
    V[0] = std::cos(e) * std::cos(az);
    V[1] = std::cos(e) * std::sin(az);
    V[2] = std::sin(e);
}

TEST(CurvedOracle, ZeroCurvatureIsTheFlatOracle) {
    const HeightMap map = smooth_map(64);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worst = 0.0;
    for (const float ref : {1.0f, 0.6f}) {
        const PassSettings s = wrap_settings(0.05f, ref);
        for (int i = 0; i < 400; ++i) {
            double V[3];
            view(10.0 + 80.0 * unit(rng), 2.0 * M_PI * unit(rng), V);
            const double u = unit(rng), v = unit(rng);
            const ExactHit flat = exact_hit(map, u, v, V, s);
            const CurvedHit curved = curved_hit(map, u, v, V, s, Curvature{});
            ASSERT_FALSE(curved.miss);
            // The march brackets each sign change and bisects it to double precision; a ray
            // that grazes a crest between two of its samples would be a whole step apart.
            const double e = std::hypot(curved.u - flat.u, curved.v - flat.v) * 64.0;
            ASSERT_LE(e, 1e-6) << "ray " << i;
            worst = std::max(worst, e);
        }
    }
    std::printf("zero curvature: worst |curved - flat| %.1e texels over 800 rays\n", worst);
}

// A sphere of radius rho (uv units) under the pixel, the relief a constant H: the relief is the
// sphere of radius rho + s (H - r) and the slab's top the one of rho + s (1 - r), both about
// (0, 0, -rho). The ray meets the first (the nearer root) or leaves through the second (the
// farther root); the texture coordinate is the hit's geodesic polar coordinates about the pixel.
TEST(CurvedOracle, SphereIsHitOrLeftAtTheAnalyticPoint) {
    const double rho = 0.64, H = double(0.6f);  // the map holds floats
    const HeightMap map = constant_map(0.6f);
    const Curvature K{1.0 / rho, 0.0, 1.0 / rho};
    int hits = 0, misses = 0;
    for (const float ref : {1.0f, 0.5f}) {
        const PassSettings s = wrap_settings(0.04f, ref);
        for (double deg = 1.0; deg <= 90.0; deg += 1.0) {
            double V[3];
            view(deg, 0.7, V);
            const CurvedHit c = curved_hit(map, 0.25, 0.5, V, s, K);
            // |p(t) - centre|^2 = R^2 with p(t) = -t V, centre (0, 0, -rho):
            // t^2 - 2 t rho V.z + rho^2 - R^2 = 0.
            auto roots = [&](double R, double& t1, double& t2) {
                const double b = rho * V[2], disc = b * b - (rho * rho - R * R);
                if (disc < 0.0) return false;
                t1 = b - std::sqrt(disc);
                t2 = b + std::sqrt(disc);
                return true;
            };
            double t1 = 0, t2 = 0;
            const bool hit = roots(rho + s.scale * (H - ref), t1, t2);
            double t = t1;
            if (!hit) {
                ASSERT_TRUE(roots(rho + s.scale * (1.0 - ref), t1, t2));
                t = t2;
            }
            const double q[3] = {-t * V[0], -t * V[1], -t * V[2] + rho};  // from the centre
            const double horizontal = std::hypot(q[0], q[1]);
            const double arc = rho * std::atan2(horizontal, q[2]);
            const double want_u = 0.25 + arc * q[0] / horizontal,
                         want_v = 0.5 + arc * q[1] / horizontal;
            ASSERT_EQ(c.miss, !hit) << deg << " degrees, r = " << ref;
            ASSERT_NEAR(c.u, want_u, 1e-9) << deg << " degrees, r = " << ref;
            ASSERT_NEAR(c.v, want_v, 1e-9) << deg << " degrees, r = " << ref;
            ASSERT_NEAR(c.t, t, 1e-9);
            (hit ? hits : misses) += 1;
        }
    }
    EXPECT_GT(hits, 20);
    EXPECT_GT(misses, 4);
    std::printf("sphere: %d hits and %d rays leaving, each at the analytic point\n", hits, misses);
}

// A cylinder bends along u only: a ray whose footprint runs along v sees a flat base.
TEST(CurvedOracle, CylinderAlongItsAxisIsFlat) {
    const HeightMap map = smooth_map(64);
    const PassSettings s = wrap_settings(0.05f, 1.0f);
    for (double deg = 10.0; deg <= 80.0; deg += 10.0) {
        double V[3];
        view(deg, M_PI / 2, V);
        V[0] = 0.0;
        const ExactHit flat = exact_hit(map, 0.3, 0.7, V, s);
        const CurvedHit curved = curved_hit(map, 0.3, 0.7, V, s, Curvature{2.0, 0.0, 0.0});
        ASSERT_FALSE(curved.miss);
        ASSERT_NEAR(curved.u, flat.u, 1e-8);
        ASSERT_NEAR(curved.v, flat.v, 1e-8);
    }
}

}  // namespace
}  // namespace omtest
