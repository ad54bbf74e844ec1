// The uv metric (docs/design.md, "The uv metric"): the footprint to second order in its arc
// length on a uv sphere (the model's own derivation, in double precision); the kernels' curved
// trace with the metric plane against the curved oracle with the same metric; a metric that is
// the stretch gives the stretch's frame; degenerate metrics fall back to the stretch, finite and
// the same from run to run.
#include <cmath>
#include <cstring>
#include <random>

#include "curved_rays.hpp"
#include "offsetmap/mesh_uv_metric.hpp"
#include "offsetmap/oracle.hpp"
#include "support.hpp"

namespace omtest {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A uv sphere of radius R (world units): u = U lon / (2 pi) around, v = W lat / pi + 1/2 pole to
// pole; tangent frame T = east, B = north, N outward. Its base at latitude `lat` in the pass's
// lengths (one uv density rho = sqrt(|dP/du| |dP/dv|)): K = rho / R each way, J = diag(a, 1 / a)
// and the Christoffel symbols Gamma^u_uv = -tan(lat) pi / W, Gamma^v_uu = (2 pi / U)^2 sin cos W
// / pi.
struct UvSphere {
    double R = 1.0, U = 2.0, W = 1.0;
    double su(double lat) const { return R * std::cos(lat) * 2.0 * kPi / U; }
    double sv() const { return R * kPi / W; }
    double rho(double lat) const { return std::sqrt(su(lat) * sv()); }
    Curvature base(double lat, bool metric) const {
        Curvature K;
        K.uu = K.vv = rho(lat) / R;
        const double a = std::sqrt(su(lat) / sv());
        K.stretch = a;
        if (!metric) return K;
        K.metric = true;
        K.j[0] = a;
        K.j[3] = 1.0 / a;
        K.gamma_u[1] = -std::tan(lat) * kPi / W;
        K.gamma_v[0] = std::pow(2.0 * kPi / U, 2) * std::sin(lat) * std::cos(lat) * W / kPi;
        return K;
    }
    // The uv offset of the point at geodesic distance l (pass lengths) from (0, lat) in the
    // direction at angle b from east: the great circle, exactly.
    std::array<double, 2> geodesic(double lat, double b, double l) const {
        const double s = l * rho(lat) / R;  // the arc's angle
        const double p0[3] = {std::cos(lat), 0.0, std::sin(lat)};
        const double east[3] = {0.0, 1.0, 0.0}, north[3] = {-std::sin(lat), 0.0, std::cos(lat)};
        double p[3];
        for (int i = 0; i < 3; ++i)
            p[i] = std::cos(s) * p0[i] +
                   std::sin(s) * (std::cos(b) * east[i] + std::sin(b) * north[i]);
        const double lon = std::atan2(p[1], p[0]), la = std::asin(p[2]);
        return {U * lon / (2.0 * kPi), W * (la - lat) / kPi};
    }
};

// The model's footprint at arc length l along direction b on the base, from curved_point: with
// the curvature set aside (the arc is then the ray's horizontal run, exactly) the offset is the
// metric's alone; a ray 1e-3 rad above the plane runs toward b.
std::array<double, 2> model_offset(Curvature K, double b, double l) {
    K.uu = K.uv = K.vv = 0.0;
    const double e = 1e-3;
    const double V[3] = {-std::cos(e) * std::cos(b), -std::cos(e) * std::sin(b), std::sin(e)};
    const CurvedPoint p = curved_point(V, K, l / std::cos(e));
    return {p.dx, p.dy};
}

// The footprint of the metric is the sphere's uv to third order in the arc length (halving l cuts
// its error 8x), where the stretch alone is it to second order (4x): at 30, 60 and 80 degrees of
// latitude, eight directions, l from 0.02 to 0.0025 of the pass's length.
TEST(UvMetric, TheFootprintIsTheSpheresUvToThirdOrder) {
    const UvSphere sphere;
    for (double lat_deg : {30.0, 60.0, 80.0}) {
        const double lat = lat_deg * kPi / 180.0;
        double worst_metric_ratio = 1e9, worst_stretch_ratio = 1e9, err_small = 0.0;
        for (int d = 0; d < 8; ++d) {
            const double b = d * kPi / 4.0 + 0.3;
            auto err = [&](bool metric, double l) {
                const std::array<double, 2> want = sphere.geodesic(lat, b, l);
                const std::array<double, 2> got = model_offset(sphere.base(lat, metric), b, l);
                return std::hypot(got[0] - want[0], got[1] - want[1]);
            };
            for (double l = 0.02; l > 0.004; l *= 0.5) {
                worst_metric_ratio =
                    std::min(worst_metric_ratio, err(true, l) / err(true, 0.5 * l));
                worst_stretch_ratio =
                    std::min(worst_stretch_ratio, err(false, l) / err(false, 0.5 * l));
            }
            err_small = std::max(err_small, err(true, 0.01));
        }
        std::printf(
            "latitude %2.0f: halving the arc cuts the metric's error %.2fx, the stretch's "
            "%.2fx; metric error at l = 0.01: %.2e uv\n",
            lat_deg, worst_metric_ratio, worst_stretch_ratio, err_small);
        EXPECT_GT(worst_metric_ratio, 6.5) << lat_deg;
        EXPECT_LT(worst_stretch_ratio, 5.0) << lat_deg;
    }
}

// The curvature plane (stretch 1 where the metric is given) and the uv metric's three planes.
GBuffer metric_gbuffer(const std::vector<CurvedRay>& rays, bool with_metric = true) {
    std::vector<std::array<float, 5>> px;
    for (const CurvedRay& r : rays) px.push_back({r.u, r.v, r.V[0], r.V[1], r.V[2]});
    GBuffer gb = row_gbuffer(px);
    const size_t n = rays.size();
    gb.curvature.resize(n);
    if (with_metric) gb.uv_metric.assign(3 * n, {{0.0f, 0.0f, 0.0f, 0.0f}});
    auto f = [](double x) { return static_cast<float>(x); };
    for (size_t k = 0; k < n; ++k) {
        const Curvature& K = rays[k].K;
        gb.curvature[k] = {{f(K.uu), f(K.uv), f(K.vv), f(K.stretch)}};
        if (!with_metric || !K.metric) continue;
        gb.uv_metric[k] = {{f(K.j[0]), f(K.j[1]), f(K.j[2]), f(K.j[3])}};
        gb.uv_metric[n + k] = {{f(K.gamma_u[0]), f(K.gamma_u[1]), f(K.gamma_u[2]), 0.0f}};
        gb.uv_metric[2 * n + k] = {{f(K.gamma_v[0]), f(K.gamma_v[1]), f(K.gamma_v[2]), 0.0f}};
    }
    return gb;
}

// A skewed, stretched flat patch; a uv sphere at 30, 60 and 80 degrees of latitude; a base with
// every term (curvature, skew, rates) at once. The oracle takes the planes' float values.
std::vector<Curvature> metric_bases() {
    const UvSphere sphere;
    std::vector<Curvature> bases;
    Curvature skew;
    skew.metric = true;
    const double j_skew[4] = {1.1, 0.0, 0.45, 0.85};
    std::copy(j_skew, j_skew + 4, skew.j);
    bases.push_back(skew);
    for (double lat : {30.0, 60.0, 80.0}) bases.push_back(sphere.base(lat * kPi / 180.0, true));
    Curvature all{1.2, 0.3, -0.5};
    all.metric = true;
    const double j_all[4] = {0.9, 0.1, 0.3, 1.2}, gu[3] = {0.8, -1.1, 0.4},
                 gv[3] = {-0.6, 0.5, 0.9};
    std::copy(j_all, j_all + 4, all.j);
    std::copy(gu, gu + 3, all.gamma_u);
    std::copy(gv, gv + 3, all.gamma_v);
    bases.push_back(all);
    for (Curvature& K : bases) {
        auto f = [](double& x) { x = static_cast<float>(x); };
        f(K.uu), f(K.uv), f(K.vv), f(K.stretch);
        for (double& x : K.j) f(x);
        for (int i = 0; i < 3; ++i) f(K.gamma_u[i]), f(K.gamma_v[i]);
    }
    return bases;
}

struct MetricCase {
    HeightMap map;
    PassSettings s = wrap_settings(0.04f, 0.8f);
    std::vector<CurvedRay> rays;
    GBuffer gb;
    std::vector<CurvedHit> want;
    MetricCase(HeightMap m, int n, unsigned seed) : map(std::move(m)) {
        rays = random_rays(n, metric_bases(), seed, 15.0, 70.0);
        gb = metric_gbuffer(rays);
        for (const CurvedRay& r : rays) {
            const double V[3] = {r.V[0], r.V[1], r.V[2]};
            want.push_back(curved_hit(map, r.u, r.v, V, s, r.K));
        }
    }
    double gap(size_t k, double t) const {
        const CurvedRay& r = rays[k];
        const double V[3] = {r.V[0], r.V[1], r.V[2]};
        const CurvedPoint p = curved_point(V, r.K, t);
        return p.he - s.scale * (bilinear_height(map, r.u + p.dx, r.v + p.dy, s.address) -
                                 s.reference_plane);
    }
};

// The cell walks over a base with the uv metric are the curved oracle's hit with the same metric
// (1/32 texel, the oracle's step; a crest the oracle stepped over is checked on the relief, the
// model's gap within 4e-6 uv), and leave the relief where it does.
TEST(UvMetric, CellWalksMeetTheOracleWithTheMetric) {
    const MetricCase c(noisy_map(64), 600, 3);
    for (const char* method : {"exact", "cone", "maxmip", "sphere"}) {
        const OffsetResult got = run(method, c.map, c.gb, c.s);
        double worst = 0.0;
        int left = 0;
        for (size_t k = 0; k < c.rays.size(); ++k) {
            SCOPED_TRACE(std::string(method) + ", ray " + std::to_string(k));
            const bool miss = got.flags[k] & OM_FLAG_SILHOUETTE;
            ASSERT_EQ(miss, c.want[k].miss);
            left += miss;
            if (miss) continue;
            const double e = texels(c.want[k], got.uv[k], 64);
            if (got.depth[k] < c.want[k].t && e > 1.0 / 32.0) {
                ASSERT_LE(std::fabs(c.gap(k, got.depth[k])), 4e-6);
                continue;
            }
            ASSERT_LE(e, 1.0 / 32.0);
            worst = std::max(worst, e);
        }
        std::printf("%-7s %zu rays: %d left the relief, worst |uv - oracle| %.2e texel\n", method,
                    c.rays.size(), left, worst);
    }
}

// The marching methods follow the same footprint: their p95 against the oracle with the metric
// stays within 2.5x their p95 against the plane's oracle on the plane, plus 0.002 texel.
TEST(UvMetric, MarchesFollowTheMetric) {
    const MetricCase c(smooth_map(64), 420, 5);
    GBuffer plane = c.gb;
    plane.curvature.clear();
    plane.uv_metric.clear();
    for (const char* method : {"parallax-slope", "relief", "pom", "secant"}) {
        const OffsetResult got = run(method, c.map, c.gb, c.s);
        const OffsetResult flat = run(method, c.map, plane, c.s);
        std::vector<double> e, ep;
        for (size_t k = 0; k < c.rays.size(); ++k) {
            const CurvedRay& r = c.rays[k];
            const double V[3] = {r.V[0], r.V[1], r.V[2]};
            ep.push_back(texels(curved_hit(c.map, r.u, r.v, V, c.s, Curvature{}), flat.uv[k], 64));
            if (!(got.flags[k] & OM_FLAG_SILHOUETTE) && !c.want[k].miss)
                e.push_back(texels(c.want[k], got.uv[k], 64));
        }
        std::sort(e.begin(), e.end());
        std::sort(ep.begin(), ep.end());
        const double p95 = e[e.size() * 95 / 100], p95_plane = ep[ep.size() * 95 / 100];
        std::printf("%-15s p95 %.4f texel with the metric, %.4f on the plane\n", method, p95,
                    p95_plane);
        EXPECT_LE(p95, 2.5 * p95_plane + 0.002) << method;
    }
}

// A small frame of every kind of base (the Oclgrind sweep's case, at 1 and 16 lanes): the walk
// within the oracle's step of its hit, the march and the slope step finite.
TEST(UvMetric, ASmallFrameMeetsTheOracle) {
    const MetricCase c(noisy_map(32), 40, 21);
    const OffsetResult exact = run("exact", c.map, c.gb, c.s);
    for (size_t k = 0; k < c.rays.size(); ++k) {
        SCOPED_TRACE(k);
        ASSERT_EQ(bool(exact.flags[k] & OM_FLAG_SILHOUETTE), c.want[k].miss);
        if (c.want[k].miss) continue;
        if (exact.depth[k] < c.want[k].t && texels(c.want[k], exact.uv[k], 32) > 1.0 / 32.0)
            ASSERT_LE(std::fabs(c.gap(k, exact.depth[k])), 4e-6);
        else
            ASSERT_LE(texels(c.want[k], exact.uv[k], 32), 1.0 / 32.0);
    }
    for (const char* method : {"pom", "parallax-slope"}) {
        const OffsetResult got = run(method, c.map, c.gb, c.s);
        for (size_t k = 0; k < c.rays.size(); ++k)
            ASSERT_TRUE(std::isfinite(got.uv[k].s[0]) && std::isfinite(got.uv[k].s[1])) << k;
    }
}

// A metric that says what the stretch says (J = diag(a, 1 / a), no rates) gives the stretch's
// frame within float rounding; one the trace cannot use (zeros, a collapsed row, a mirrored
// frame, a NaN or an infinity anywhere) gives the stretch's too, finite, and the same bits from
// run to run.
TEST(UvMetric, TheStretchAndUnusableMetricsGiveTheStretchsFrame) {
    const HeightMap map = noisy_map(64);
    const PassSettings s = wrap_settings(0.04f, 0.8f);
    const UvSphere sphere;
    std::vector<CurvedRay> rays = random_rays(240, {sphere.base(0.7, false)}, 8, 15.0, 70.0);
    const GBuffer stretch = metric_gbuffer(rays, false);
    GBuffer same = metric_gbuffer(rays), bad = same;
    const size_t n = rays.size();
    const float a = static_cast<float>(rays[0].K.stretch);
    const float rows[6][4] = {{0, 0, 0, 0},       {a, 0, 0, 0},        {a, 0, 0, -1 / a},
                              {NAN, 0, 0, 1 / a}, {a, 0, 0, INFINITY}, {a, 0, 0, 1 / a}};
    for (size_t k = 0; k < n; ++k) {
        same.uv_metric[k] = {{a, 0.0f, 0.0f, 1.0f / a}};
        const float* r = rows[k % 6];
        bad.uv_metric[k] = {{r[0], r[1], r[2], r[3]}};
        // The last row is usable but for a NaN rate.
        if (k % 6 == 5) bad.uv_metric[n + k].s[1] = NAN;
    }
    for (const std::string& method : method_names()) {
        const OffsetResult want = run(method, map, stretch, s);
        const OffsetResult got = run(method, map, same, s);
        const OffsetResult b1 = run(method, map, bad, s), b2 = run(method, map, bad, s);
        for (size_t k = 0; k < n; ++k) {
            SCOPED_TRACE(method + ", pixel " + std::to_string(k));
            for (const OffsetResult* r : {&got, &b1}) {
                ASSERT_TRUE(std::isfinite(r->uv[k].s[0]) && std::isfinite(r->uv[k].s[1]));
                ASSERT_LE(
                    texels(CurvedHit{want.uv[k].s[0], want.uv[k].s[1], 0.0, false}, r->uv[k], 64),
                    2e-3);
                ASSERT_EQ(r->flags[k] & OM_FLAG_SILHOUETTE, want.flags[k] & OM_FLAG_SILHOUETTE);
            }
            ASSERT_EQ(std::memcmp(&b1.uv[k], &b2.uv[k], sizeof(cl_float2)), 0);
        }
    }
}

// A mesh over packed arrays (3 floats a position, 2 a uv), the arrays the caller's.
UvMetricMesh packed_mesh(const std::vector<float>& pos, const std::vector<float>& uv,
                         const std::vector<std::uint32_t>& idx) {
    UvMetricMesh m;
    m.positions = pos.data();
    m.uvs = uv.data();
    m.vertex_count = pos.size() / 3;
    m.indices = idx.data();
    m.index_count = idx.size();
    return m;
}

// A uv sphere mesh of radius 1 in packed arrays: `seg` x `rings` quads, u = lon / pi + shear v
// (twice around, sheared), v = lat / pi + 1/2; the poles' rows are `seg` + 1 vertices at one
// point (their quads' degenerate triangles have no area).
struct SphereArrays {
    int seg, rings;
    double shear;
    std::vector<float> pos, uv;
    std::vector<std::uint32_t> idx;
    SphereArrays(int s, int r, double sh) : seg(s), rings(r), shear(sh) {
        for (int j = 0; j <= rings; ++j)
            for (int i = 0; i <= seg; ++i) {
                const double v = double(j) / rings, u = 2.0 * i / seg + shear * v;
                const std::array<double, 3> x = at(u, v);
                pos.insert(pos.end(), {float(x[0]), float(x[1]), float(x[2])});
                uv.insert(uv.end(), {float(u), float(v)});
            }
        for (int j = 0; j < rings; ++j)
            for (int i = 0; i < seg; ++i) {
                const std::uint32_t k = j * (seg + 1) + i, up = k + seg + 1;
                idx.insert(idx.end(), {k, k + 1, up + 1, k, up + 1, up});
            }
    }
    std::array<double, 3> at(double u, double v) const {
        const double lat = kPi * (v - 0.5), lon = kPi * (u - shear * v);
        return {std::cos(lat) * std::cos(lon), std::cos(lat) * std::sin(lon), std::sin(lat)};
    }
    UvMetricMesh mesh() const { return packed_mesh(pos, uv, idx); }
    // The analytic symbols at (u, v), from central differences of the surface (step 1e-4: their
    // own error about 1e-8).
    std::array<double, 6> gamma(double u, double v) const {
        const double e = 1e-4;
        auto d = [&](int i, int j) {  // second derivative d2P / du_i du_j
            std::array<double, 3> r{};
            const double du[2] = {e, 0}, dv[2] = {0, e};
            const double a[2] = {i == 0 ? du[0] : dv[0], i == 0 ? du[1] : dv[1]};
            const double b[2] = {j == 0 ? du[0] : dv[0], j == 0 ? du[1] : dv[1]};
            const auto pp = at(u + a[0] + b[0], v + a[1] + b[1]),
                       pm = at(u + a[0] - b[0], v + a[1] - b[1]);
            const auto mp = at(u - a[0] + b[0], v - a[1] + b[1]),
                       mm = at(u - a[0] - b[0], v - a[1] - b[1]);
            for (int q = 0; q < 3; ++q) r[q] = (pp[q] - pm[q] - mp[q] + mm[q]) / (4 * e * e);
            return r;
        };
        auto first = [&](int i) {
            std::array<double, 3> r{};
            const auto p = at(u + (i == 0) * e, v + (i == 1) * e),
                       m = at(u - (i == 0) * e, v - (i == 1) * e);
            for (int q = 0; q < 3; ++q) r[q] = (p[q] - m[q]) / (2 * e);
            return r;
        };
        auto dot3 = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
            return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        };
        const auto su = first(0), sv = first(1);
        const double E = dot3(su, su), F = dot3(su, sv), G = dot3(sv, sv), det = E * G - F * F;
        std::array<double, 6> g{};
        const int ij[3][2] = {{0, 0}, {0, 1}, {1, 1}};
        for (int k = 0; k < 3; ++k) {
            const auto s2 = d(ij[k][0], ij[k][1]);
            const double xu = dot3(s2, su), xv = dot3(s2, sv);
            g[k] = (G * xu - F * xv) / det;
            g[3 + k] = (E * xv - F * xu) / det;
        }
        return g;
    }
};

// derive_uv_metric's symbols on a sheared uv sphere (every symbol non-zero, skew included)
// against the surface's own, at the vertices within 60 degrees of the equator, the seam's
// included (its two sides' triangles both count): their error falls with the mesh's spacing (at
// least 3x when it halves: second order), and the poles' degenerate triangles give finite values
// or none.
TEST(UvMetric, TheMeshsSymbolsAreTheSurfacesToSecondOrder) {
    double worst_prev = 0.0;
    for (int seg : {48, 96}) {
        const SphereArrays s(seg, seg / 2, 0.3);
        const std::vector<UvMetricVertex> m = derive_uv_metric(s.mesh());
        double worst = 0.0, scale = 0.0;
        for (size_t k = 0; k < m.size(); ++k) {
            for (int q = 0; q < 3; ++q)
                ASSERT_TRUE(std::isfinite(m[k].gamma_u[q]) && std::isfinite(m[k].gamma_v[q]));
            const double u = s.uv[2 * k], v = s.uv[2 * k + 1];
            if (std::fabs(v - 0.5) > 1.0 / 3.0) continue;
            const std::array<double, 6> want = s.gamma(u, v);
            for (int q = 0; q < 3; ++q) {
                worst = std::max(worst, std::fabs(m[k].gamma_u[q] - want[q]));
                worst = std::max(worst, std::fabs(m[k].gamma_v[q] - want[3 + q]));
                scale = std::max({scale, std::fabs(want[q]), std::fabs(want[3 + q])});
            }
        }
        std::printf("sheared uv sphere %d x %d: worst symbol error %.2e (largest symbol %.2f)\n",
                    seg, seg / 2, worst, scale);
        if (worst_prev > 0.0) {
            EXPECT_GT(worst_prev / worst, 3.0);
        }
        worst_prev = worst;
    }
}

// Degenerate uv: a triangle whose uv has no area, one whose corners are one point, and a vertex
// only they touch: nothing from them (zeros: the pass reads no metric there), the rest finite.
TEST(UvMetric, DegenerateUvGivesNothingAndNoNaN) {
    const std::vector<float> pos = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 2, 2, 0, 3, 3, 0, 3, 3, 0};
    const std::vector<float> uv = {0, 0, 1, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 0.5f, 0.7f, 0.1f};
    // A good pair; a triangle with collinear uv (4, 5, 6: two uv equal); a zero-area one (5, 6
    // at one point).
    const std::vector<std::uint32_t> idx = {0, 1, 3, 0, 3, 2, 4, 5, 6, 5, 6, 4};
    UvMetricMesh mesh = packed_mesh(pos, uv, idx);
    const std::vector<UvMetricVertex> m = derive_uv_metric(mesh);
    for (int k = 0; k < 4; ++k) {
        EXPECT_FLOAT_EQ(m[k].dpdu[0], 1.0f);
        EXPECT_FLOAT_EQ(m[k].dpdv[1], 1.0f);
    }
    for (int k = 4; k < 7; ++k)
        for (int q = 0; q < 3; ++q) {
            EXPECT_EQ(m[k].dpdu[q], 0.0f);
            EXPECT_EQ(m[k].gamma_u[q], 0.0f);
            EXPECT_EQ(m[k].gamma_v[q], 0.0f);
        }
    mesh.index_count = 4;
    EXPECT_THROW(derive_uv_metric(mesh), Error);
}

// A mirrored uv seam (u = |x| across x = 0, the seam's vertices one on each side): its sides are
// not welded, so each seam vertex keeps its own side's dP/du (unit length, opposite signs), where
// welding them would average it to nothing; a translated seam (u = x and x + 2 across it) is.
TEST(UvMetric, AMirroredSeamKeepsEachSidesMetric) {
    // Two quads, x in [-1, 0] and [0, 1], y in [0, 1]; the seam's column at x = 0 twice.
    auto strip = [](bool mirrored) {
        std::vector<float> pos, uv;
        for (int side = 0; side < 2; ++side)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    const float x = side == 0 ? float(i) - 1.0f : float(i);
                    pos.insert(pos.end(), {x, float(j), 0.0f});
                    const float u = mirrored ? std::fabs(x) : (side == 0 ? x + 2.0f : x);
                    uv.insert(uv.end(), {u, float(j)});
                }
        return std::make_pair(pos, uv);
    };
    std::vector<std::uint32_t> idx;
    for (std::uint32_t b : {0u, 4u}) idx.insert(idx.end(), {b, b + 1, b + 3, b, b + 3, b + 2});
    for (bool mirrored : {true, false}) {
        SCOPED_TRACE(mirrored ? "mirrored" : "translated");
        const auto [pos, uv] = strip(mirrored);
        const std::vector<UvMetricVertex> m = derive_uv_metric(packed_mesh(pos, uv, idx));
        // Vertex 1 is the left side's seam vertex (x = 0), vertex 4 the right side's.
        const float left = mirrored ? -1.0f : 1.0f;
        EXPECT_FLOAT_EQ(m[1].dpdu[0], left);
        EXPECT_FLOAT_EQ(m[4].dpdu[0], 1.0f);
        for (const UvMetricVertex& v : m)
            for (int q = 0; q < 3; ++q)
                EXPECT_TRUE(std::isfinite(v.gamma_u[q]) && std::isfinite(v.gamma_v[q]));
    }
}

// A pixel on the tangent plane (no curvature, no stretch, J the identity) traces the plane
// whatever its symbols say (their term is second order in a footprint whose first order is the
// plane's): every method's frame is the one without the metric plane, bit for bit.
TEST(UvMetric, APixelOnTheTangentPlaneKeepsThePlanesBits) {
    const HeightMap map = noisy_map(64);
    const PassSettings s = wrap_settings(0.04f, 0.8f);
    std::vector<CurvedRay> rays = random_rays(128, {Curvature{}}, 12, 15.0, 70.0);
    const GBuffer none = metric_gbuffer(rays, false);
    GBuffer flat = metric_gbuffer(rays);
    const size_t n = rays.size();
    for (size_t k = 0; k < n; ++k) {
        flat.uv_metric[k] = {{1.0f, 0.0f, 0.0f, 1.0f}};
        flat.uv_metric[n + k] = {{0.3f, -1.5f, 0.8f, 0.0f}};
        flat.uv_metric[2 * n + k] = {{-0.7f, 0.2f, 2.5f, 0.0f}};
    }
    for (const std::string& method : method_names()) {
        const OffsetResult a = run(method, map, none, s), b = run(method, map, flat, s);
        for (size_t k = 0; k < n; ++k) {
            SCOPED_TRACE(method + ", pixel " + std::to_string(k));
            ASSERT_EQ(std::memcmp(&a.uv[k], &b.uv[k], sizeof(cl_float2)), 0);
            ASSERT_EQ(std::memcmp(&a.depth[k], &b.depth[k], sizeof(float)), 0);
            ASSERT_EQ(a.flags[k], b.flags[k]);
        }
    }
}

}  // namespace
}  // namespace omtest
