#include "offsetmap/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "offsetmap/shared.h"

namespace offsetmap {

PreparedRay prepare_ray(double u, double v, const double view[3], const PassSettings& s, int map_w,
                        int map_h) {
    PreparedRay r;
    r.u = u;
    r.v = v;
    if (std::isnan(u) || std::isnan(v)) return r.flags = OM_FLAG_EMPTY, r;
    if (!std::isfinite(u) || !std::isfinite(v) || !std::isfinite(view[0]) ||
        !std::isfinite(view[1]) || !std::isfinite(view[2]))
        return r.flags = OM_FLAG_INVALID, r;
    double len = std::sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    if (!(len > 0.0)) return r.flags = OM_FLAG_INVALID, r;
    if (std::fabs(len - 1.0) > 1e-3) r.flags |= OM_FLAG_RENORMALIZED;
    for (int a = 0; a < 3; ++a) r.V[a] = view[a] / len;
    if (!(r.V[2] > 0.0)) return r.flags |= OM_FLAG_BACKFACING, r;
    const GrazingRule rule = grazing_rule(s, map_w, map_h);
    const double min_vz = rule.min_vz;
    // Flagged under every policy, as the kernels do: below the (cap-raised) minimum.
    if (r.V[2] < min_vz) r.flags |= OM_FLAG_GRAZING;
    if (s.grazing == GrazingPolicy::Limit) {
        double n = std::sqrt(r.V[0] * r.V[0] + r.V[1] * r.V[1] + 1.0);
        r.V[0] /= n;
        r.V[1] /= n;
        r.V[2] = 1.0 / n;
    } else if (r.V[2] < min_vz) {
        double k = std::sqrt(1.0 - min_vz * min_vz) / std::hypot(r.V[0], r.V[1]);
        r.V[0] *= k;
        r.V[1] *= k;
        r.V[2] = min_vz;
    }
    r.traced = true;
    return r;
}

double bilinear_height(const HeightMap& map, double u, double v, AddressMode address) {
    auto texel = [&](long long i, long long j) {
        if (address == AddressMode::Wrap) {
            i = ((i % map.width) + map.width) % map.width;
            j = ((j % map.height) + map.height) % map.height;
        } else {
            i = std::clamp<long long>(i, 0, map.width - 1);
            j = std::clamp<long long>(j, 0, map.height - 1);
        }
        return static_cast<double>(map.at(static_cast<int>(i), static_cast<int>(j)));
    };
    double x = u * map.width - 0.5, y = v * map.height - 0.5;
    double fx = std::floor(x), fy = std::floor(y);
    double a = x - fx, b = y - fy;
    auto i = static_cast<long long>(fx), j = static_cast<long long>(fy);
    return (1 - b) * ((1 - a) * texel(i, j) + a * texel(i + 1, j)) +
           b * ((1 - a) * texel(i, j + 1) + a * texel(i + 1, j + 1));
}

ExactHit exact_hit(const HeightMap& map, double u, double v, const double V[3],
                   const PassSettings& s) {
    return exact_hit(map, u, v, V, s, CellLift{});
}

ExactHit exact_hit(const HeightMap& map, double u, double v, const double V[3],
                   const PassSettings& s, const CellLift& lift) {
    const double scale = s.scale, ref = s.reference_plane;
    const double top = 1.0 + std::max(lift.highest, 0.0), bottom = std::min(lift.lowest, 0.0);
    const double t0 = -scale * (top - ref) / V[2], t1 = scale * (ref - bottom) / V[2];
    // Ray height above the relief; the first t where it is <= 0 is the hit. Each segment lies in
    // one bilinear cell, whose lift it takes.
    double moved = 0.0;
    auto gap = [&](double t) {
        return -t * V[2] -
               scale * (bilinear_height(map, u - t * V[0], v - t * V[1], s.address) + moved - ref);
    };
    // Every t where the footprint crosses a line through texel centres: between two consecutive
    // ones the ray stays inside one bilinear patch, where gap(t) is exactly quadratic.
    std::vector<double> ts = {t0, t1};
    auto crossings = [&](double c0, double dc) {  // cell coordinate c(t) = c0 - t dc
        if (dc == 0.0) return;
        double ca = c0 - t0 * dc, cb = c0 - t1 * dc;
        for (double k = std::ceil(std::min(ca, cb)); k <= std::max(ca, cb); k += 1.0)
            ts.push_back((c0 - k) / dc);
    };
    crossings(u * map.width - 0.5, V[0] * map.width);
    crossings(v * map.height - 0.5, V[1] * map.height);
    std::sort(ts.begin(), ts.end());
    auto at = [&](double t) { return ExactHit{u - t * V[0], v - t * V[1], t}; };
    for (size_t k = 0; k + 1 < ts.size(); ++k) {
        double a = std::clamp(ts[k], t0, t1), b = std::clamp(ts[k + 1], t0, t1);
        if (b <= a) continue;
        if (lift.at) {
            const double mid = 0.5 * (a + b);
            moved =
                lift.at(static_cast<long long>(std::floor((u - mid * V[0]) * map.width - 0.5)),
                        static_cast<long long>(std::floor((v - mid * V[1]) * map.height - 0.5)));
        }
        double ga = gap(a);
        if (ga <= 0.0) return at(a);
        double m = 0.5 * (a + b), gm = gap(m), gb = gap(b);
        // Quadratic through (0, ga), (h, gm), (2h, gb) in tau = t - a.
        double h = 0.5 * (b - a);
        double c2 = (gb - 2.0 * gm + ga) / (2.0 * h * h);
        double c1 = (4.0 * gm - gb - 3.0 * ga) / (2.0 * h);
        double best = -1.0;
        if (std::fabs(c2) * (b - a) <= 1e-14 * (std::fabs(c1) + std::fabs(ga) / (b - a))) {
            if (c1 < 0.0) best = -ga / c1;
        } else {
            double disc = c1 * c1 - 4.0 * c2 * ga;
            if (disc >= 0.0) {
                double q = -0.5 * (c1 + std::copysign(std::sqrt(disc), c1));
                double r1 = ga / q, r2 = q / c2;
                for (double r : {std::min(r1, r2), std::max(r1, r2)})
                    if (r >= 0.0 && r <= b - a) {
                        best = r;
                        break;
                    }
            }
        }
        if (best >= 0.0 && best <= b - a) return at(a + best);
        if (gb <= 0.0) return at(b);
    }
    return at(t1);
}

}  // namespace offsetmap
