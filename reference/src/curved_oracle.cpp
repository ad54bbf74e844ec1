// The relief over a curved base, in double precision: the oracle the curved trace is held to.
#include <algorithm>
#include <cmath>

#include "offsetmap/oracle.hpp"

namespace offsetmap {

namespace {

// A point of the ray's vertical plane, a along the surface direction e and z along the normal,
// in coordinates of the base circle of curvature k through the pixel (centre at (0, -1 / k)):
// h its height above the circle along the circle's normal, arc the arc length to the foot of
// that normal. Written so that k -> 0 gives h = z and arc = a without cancellation.
struct CircleCoords {
    double h, arc;
};
CircleCoords circle_coords(double k, double a, double z) {
    const double c = 1.0 + k * z, ka = k * a;
    const double r = std::sqrt(c * c + ka * ka);  // distance to the centre, times k
    CircleCoords p;
    p.h = (2.0 * z + k * (z * z + a * a)) / (r + 1.0);
    p.arc = ka == 0.0 ? (c > 0.0 ? a : 0.0) : a * (std::atan2(ka, c) / ka);
    return p;
}

}  // namespace

CurvedPoint curved_point(const double V[3], const Curvature& K, double t) {
    const double lxy = std::hypot(V[0], V[1]);
    // The direction the footprint runs (p(t) = -t V) and the one across it.
    const double ex = lxy > 0.0 ? -V[0] / lxy : 1.0, ey = lxy > 0.0 ? -V[1] / lxy : 0.0;
    const double px = -ey, py = ex;
    const double kn = ex * (K.uu * ex + K.uv * ey) + ey * (K.uv * ex + K.vv * ey);
    const double kc = px * (K.uu * ex + K.uv * ey) + py * (K.uv * ex + K.vv * ey);
    const CircleCoords c = circle_coords(kn, t * lxy, -t * V[2]);
    const double side = -c.h * kc * c.arc;
    if (!K.metric)
        return CurvedPoint{(c.arc * ex + side * px) / K.stretch,
                           (c.arc * ey + side * py) * K.stretch, c.h, c.h};
    const double* J = K.j;
    const double det = J[0] * J[3] - J[2] * J[1];
    const double a00 = J[3] / det, a01 = -J[2] / det, a10 = -J[1] / det, a11 = J[0] / det;
    const double mu = a00 * ex + a01 * ey, mv = a10 * ex + a11 * ey;
    const double nu = a00 * px + a01 * py, nv = a10 * px + a11 * py;
    auto form = [&](const double* g) {
        return g[0] * mu * mu + 2.0 * g[1] * mu * mv + g[2] * mv * mv;
    };
    const double l2 = c.arc * c.arc;
    const double dx = c.arc * mu + side * nu - 0.5 * l2 * form(K.gamma_u);
    const double dy = c.arc * mv + side * nv - 0.5 * l2 * form(K.gamma_v);
    const double du = 0.5 * (K.gamma_u[0] + K.gamma_v[1]), dv = 0.5 * (K.gamma_u[1] + K.gamma_v[2]);
    // The relief's depth factor's reciprocal, linear in the offset (no division).
    const double g = std::clamp(1.0 - (du * dx + dv * dy), 0.25, 4.0);
    return CurvedPoint{dx, dy, c.h, c.h * g};
}

CurvedHit curved_hit(const HeightMap& map, double u, double v, const double V[3],
                     const PassSettings& s, const Curvature& K) {
    const double scale = s.scale, ref = s.reference_plane;
    const double top = scale * (1.0 - ref), bottom = -scale * ref;
    const double lxy = std::hypot(V[0], V[1]);
    struct Sample {
        double h, x, y, he;
    };
    auto at = [&](double t) {
        const CurvedPoint p = curved_point(V, K, t);
        return Sample{p.h, p.dx, p.dy, p.he};
    };
    auto gap = [&](double t) {
        const Sample p = at(t);
        return p.he - scale * (bilinear_height(map, u + p.x, v + p.y, s.address) - ref);
    };
    auto result = [&](double t, bool miss) {
        const Sample p = at(t);
        return CurvedHit{u + p.x, v + p.y, t, miss};
    };
    // Where the ray enters the slab on the eye's side: h falls as t grows through 0.
    double t_in = -top / V[2];
    for (int i = 0; i < 60 && at(t_in).h < top; ++i) t_in *= 2.0;
    if (t_in < 0.0) {
        double lo = t_in, hi = 0.0;  // h(lo) >= top > ... >= h(hi)
        for (int i = 0; i < 200; ++i) {
            const double mid = 0.5 * (lo + hi);
            (at(mid).h >= top ? lo : hi) = mid;
        }
        t_in = lo;
    }
    const double texel = 1.0 / std::max(map.width, map.height);
    // In uv per unit of t: the stretch's, or A's norm and the rates' growth over the slab's
    // reach (a bound: its 1/32 texel steps only need to be small enough).
    double speed = lxy * std::max(K.stretch, 1.0 / K.stretch);
    if (K.metric) {
        const double* J = K.j;
        const double det = std::fabs(J[0] * J[3] - J[2] * J[1]);
        const double a = std::sqrt(J[0] * J[0] + J[1] * J[1] + J[2] * J[2] + J[3] * J[3]) / det;
        double g = 0.0;
        for (int i = 0; i < 3; ++i) g += std::fabs(K.gamma_u[i]) + std::fabs(K.gamma_v[i]);
        const double reach = 4.0 * scale / V[2] * a;
        speed = lxy * a * (1.0 + 2.0 * g * a * reach);
    }
    const double dt = std::min(texel / 32.0 / std::max(speed, 1e-12), scale / 256.0 / V[2]);
    double t = t_in, g = gap(t), h = at(t).h;
    if (g <= 0.0) return result(t, false);
    // A convex base turns the ray back up: past its lowest point, above the top, it has left.
    for (long long i = 0; i < 100000000LL; ++i) {
        const double tn = t + dt;
        const double gn = gap(tn), hn = at(tn).h;
        if (gn <= 0.0) {
            double lo = t, hi = tn;
            for (int b = 0; b < 100; ++b) {
                const double mid = 0.5 * (lo + hi);
                (gap(mid) > 0.0 ? lo : hi) = mid;
            }
            return result(hi, false);
        }
        if (hn > top && hn > h) {
            double lo = t, hi = tn;  // h(lo) <= top < h(hi)
            for (int b = 0; b < 100; ++b) {
                const double mid = 0.5 * (lo + hi);
                (at(mid).h <= top ? lo : hi) = mid;
            }
            return result(hi, true);
        }
        if (hn < bottom) return result(tn, false);  // unreachable: H >= 0 meets it first
        t = tn;
        h = hn;
    }
    return result(t, true);
}

}  // namespace offsetmap
