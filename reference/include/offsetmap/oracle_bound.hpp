// The per-ray bound an exact method's float answer is held to against the double oracle
// (offsetmap/oracle.hpp), shared by the oracle tests, the randomized property test and the device
// check (tools/check).
//
// Tolerance, per ray, from float rounding: the kernel finds the hit as the first root of the gap
// q(t) = z(t) - s (H(p(t)) - r) (ray height minus relief height) on one bilinear patch. Its
// inputs carry rounding: the cell position c - t d (cells, magnitude P = W (|u| + |t V.x|) +
// H (|v| + |t V.y|), u and v where the kernels start: wrapped into [0, 1) under wrap), the corner
// heights combined into h (an error of at most P in cells times the patch's height change per cell,
// <= 1, plus a few roundings of H <= 1) and the ray height t V.z. About ten roundings lie between
// the inputs and q; we allow K = 16 units of float rounding (eps = 2^-24) on each term:
//     dq = K eps (|t| V.z + s (1 + P)).
// A root moves by dq / |q'(t)| where q' = dq/dt is the gap's rate along the ray at the hit (from
// the oracle, double precision; the smaller one-sided rate at a cell edge). A ray that meets the
// relief tangentially (q' -> 0) has the quadratic's bound 2 sqrt(dq / |q''|) instead, with
// |q''| <= 2 s |e3| W H |V.x V.y| <= 4 s W H |V.x V.y| (e3 the patch's twist, |e3| <= 2).
// So: |t - t_oracle| <= dt, and the uv' error in texels is at most (dt |V.xy| + K eps P / W) W,
// with P there the larger of the kernels' frame and the input's (uv' is returned in the latter).
// This tolerance grows with the map's size (P) and at grazing views (|q'| ~ V.z), as the
// rounding does; a fixed number of texels cannot be right for both 64^2 and 256^2 maps.
// A ray that grazes the relief (the gap dips to within dq of zero and rises again) has two
// answers to the inputs' precision: the graze or the next hit. The root bound cannot cover that
// jump, so a kernel's hit is also right when it is the other answer: between the two hits the
// ray never goes more than dq below the relief, and at the kernel's hit the gap is within dq.
#pragma once
#include <algorithm>
#include <cmath>

#include "offsetmap/oracle.hpp"

namespace offsetmap {

struct RayTolerance {
    double dt;      // in t (uv units along the ray)
    double texels;  // uv' distance, texels of the map
    double dq;      // in the gap q (uv units of height)
};

// The ray's height above the relief at t (q in the header), in double.
inline double ray_gap(const HeightMap& map, const PreparedRay& pr, const PassSettings& s,
                      double t) {
    return -t * pr.V[2] -
           s.scale * (bilinear_height(map, pr.u - t * pr.V[0], pr.v - t * pr.V[1], s.address) -
                      s.reference_plane);
}

constexpr double kBoundEps = 0x1.0p-24, kBoundRoundings = 16.0;  // eps and K in the header

// The magnitude P of the ray's cell position at t (cells; the header's P), in the frame the
// kernels trace in: wrap starts from the fractional uv (a uv of -0.005 starts near the far edge,
// its position as large as the map), clamp from the uv itself.
inline double cell_magnitude(const HeightMap& map, const PreparedRay& pr, const PassSettings& s,
                             double t) {
    const bool wrap = s.address == AddressMode::Wrap;
    const double u = wrap ? pr.u - std::floor(pr.u) : std::fabs(pr.u),
                 v = wrap ? pr.v - std::floor(pr.v) : std::fabs(pr.v);
    return map.width * (u + std::fabs(t * pr.V[0])) + map.height * (v + std::fabs(t * pr.V[1]));
}

// The gap's rounding dq at t (the header's dq).
inline double gap_rounding(const HeightMap& map, const PreparedRay& pr, const PassSettings& s,
                           double t) {
    return kBoundRoundings * kBoundEps *
           (std::fabs(t) * pr.V[2] + s.scale * (1.0 + cell_magnitude(map, pr, s, t)));
}

inline RayTolerance ray_tolerance(const HeightMap& map, const PreparedRay& pr,
                                  const PassSettings& s, double t) {
    const double eps = kBoundEps, K = kBoundRoundings;
    const double* V = pr.V;
    // uv' comes back in the input's frame (the start's wrap added back): rounded at that size too.
    const double P = std::max(cell_magnitude(map, pr, s, t),
                              map.width * (std::fabs(pr.u) + std::fabs(t * V[0])) +
                                  map.height * (std::fabs(pr.v) + std::fabs(t * V[1])));
    const double dq = gap_rounding(map, pr, s, t);
    auto gap = [&](double x) { return ray_gap(map, pr, s, x); };
    const double h = 1e-7 * s.scale / V[2];
    const double rate =
        std::min(std::fabs(gap(t + h) - gap(t)), std::fabs(gap(t) - gap(t - h))) / h;
    const double curvature = 4.0 * s.scale * map.width * map.height * std::fabs(V[0] * V[1]);
    double dt = rate > 0.0 ? dq / rate : INFINITY;
    if (curvature > 0.0) dt = std::min(dt, 2.0 * std::sqrt(dq / curvature));
    const double vxy = std::hypot(V[0], V[1]);
    return {dt,
            (dt * vxy + K * eps * P / std::max(map.width, map.height)) *
                std::max(map.width, map.height),
            dq};
}

// Whether the kernel's hit (uv', t) is the other answer of a graze (see the header): its uv' on
// the ray at t, the gap there within dq, and never below -dq between it and the oracle's hit
// (sampled every 1/16 cell the ray crosses).
inline bool other_answer_of_a_graze(const HeightMap& map, const PreparedRay& pr,
                                    const PassSettings& s, double t_oracle, double t, double u,
                                    double v) {
    const RayTolerance tol = ray_tolerance(map, pr, s, t);
    const double on_ray =
        std::hypot((u - (pr.u - t * pr.V[0])) * map.width, (v - (pr.v - t * pr.V[1])) * map.height);
    if (on_ray > tol.texels || std::fabs(ray_gap(map, pr, s, t)) > tol.dq) return false;
    const double a = std::min(t, t_oracle), b = std::max(t, t_oracle);
    const double cells = (b - a) * std::hypot(pr.V[0] * map.width, pr.V[1] * map.height);
    const int n = 16 * static_cast<int>(std::ceil(cells)) + 1;
    for (int i = 0; i <= n; ++i) {
        const double x = a + (b - a) * i / n;
        if (ray_gap(map, pr, s, x) < -gap_rounding(map, pr, s, x)) return false;
    }
    return true;
}

// A kernel's hit (uv', t) judged against the oracle's: its uv' distance in texels, the larger of
// that and its t error as a share of the ray's bound, and whether it is right (within the bound,
// or the other answer of a graze).
struct HitVerdict {
    double texels = 0.0;
    double share_of_bound = 0.0;
    bool graze = false;  // outside the bound but the graze's other answer
    bool ok = true;
};

inline HitVerdict judge_hit(const HeightMap& map, const PreparedRay& pr, const PassSettings& s,
                            const ExactHit& oracle, double u, double v, double t) {
    HitVerdict h;
    const RayTolerance tol = ray_tolerance(map, pr, s, oracle.t);
    h.texels = std::hypot((u - oracle.u) * map.width, (v - oracle.v) * map.height);
    h.share_of_bound = std::max(h.texels / tol.texels, std::fabs(t - oracle.t) / tol.dt);
    if (h.share_of_bound <= 1.0) return h;
    h.graze = other_answer_of_a_graze(map, pr, s, oracle.t, t, u, v);
    h.ok = h.graze;
    return h;
}

}  // namespace offsetmap
