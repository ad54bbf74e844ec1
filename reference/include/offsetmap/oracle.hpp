#pragma once
#include <cstdint>
#include <functional>

#include "offsetmap/heightmap.hpp"
#include "offsetmap/passes.hpp"

namespace offsetmap {

// A G-buffer pixel after the pass's input rules (docs/design.md, "Bad input and grazing views"), in
// double precision.
struct PreparedRay {
    std::uint32_t flags = 0;  // OM_FLAG_* as the kernels set them
    bool traced = false;      // false: uv passes through unchanged
    double u = 0, v = 0;      // the G-buffer uv
    double V[3] = {0, 0, 1};  // unit, grazing rule applied
};

// The pass's input rules, grazing policy included (`cap` needs the height map's size).
PreparedRay prepare_ray(double u, double v, const double view[3], const PassSettings& settings,
                        int map_w = 0, int map_h = 0);

struct ExactHit {
    double u, v;  // uv' (unwrapped, in the same frame as the input uv)
    double t;     // ray parameter of the hit
};

// The exact first hit of p(t) = (u, v, 0) - t V with the bilinear height field, in double
// precision on the host: an implementation independent of the exact kernel (segments between all
// cell-boundary crossings; the quadratic in each segment is fitted through three samples of the
// generic bilinear sampler), used as the tests' oracle. V must be unit with V.z > 0.
ExactHit exact_hit(const HeightMap& map, double u, double v, const double V[3],
                   const PassSettings& settings);

// A height field moved by a constant in each bilinear cell (cell (i, j) spans the centres of
// texels i, i + 1 and j, j + 1; unwrapped indices): the surfaces that bracket one known within a
// bound per cell. `lowest` and `highest` bound every cell's lift.
struct CellLift {
    std::function<double(long long i, long long j)> at;
    double lowest = 0.0, highest = 0.0;
};

// The exact first hit with H + lift instead of H (the same segments and fits as exact_hit).
ExactHit exact_hit(const HeightMap& map, double u, double v, const double V[3],
                   const PassSettings& settings, const CellLift& lift);

// The base surface's second fundamental form at the pixel in its tangent frame, uv units
// (EngineScene::curvature): positive where the surface bends away from its normal.
struct Curvature {
    double uu = 0.0, uv = 0.0, vv = 0.0;
    // The uv's stretch a = sqrt(|dP/du| / |dP/dv|): the curvature and the ray are in the
    // surface's lengths (one uv density each way), an offset (x, y) there is (x / a, y a) in uv.
    double stretch = 1.0;
    // The uv metric (docs/design.md, "The uv metric"), used where `metric` is set, in place of
    // the stretch: dP/du and dP/dv in the tangent frame in the pass's lengths
    // (j = {dP/du.T, dP/du.B, dP/dv.T, dP/dv.B}) and the Christoffel symbols of the uv
    // parametrisation (gamma_u = Gamma^u_uu, _uv, _vv; gamma_v the same for v). The footprint
    // at arc length l along e and `side` across it is l A e + side A e_perp - l^2 Gamma(A e,
    // A e) / 2 (A = J^-1), and the relief there 1 / clamp(1 - d.offset, 1/4, 4) times as
    // deep (d_k = (Gamma^u_uk + Gamma^v_vk) / 2, the uv density's log rate).
    bool metric = false;
    double j[4] = {1.0, 0.0, 0.0, 1.0};
    double gamma_u[3] = {0.0, 0.0, 0.0}, gamma_v[3] = {0.0, 0.0, 0.0};
};

struct CurvedHit {
    double u, v;  // uv' (the relief's texture coordinate at the hit, or where the ray left)
    double t;     // ray parameter
    bool miss;    // the ray left the relief's slab over the curved base before meeting it
};

// The model's ray at t over the base K: the footprint's offset (dx, dy) from the pixel in uv and
// the height h above the base along its normal (docs/design.md, "Curved surfaces"); under the uv
// metric `he` = h clamp(1 - d.offset, 1/4, 4), the height the relief is compared with (h itself
// without it).
struct CurvedPoint {
    double dx, dy, h, he;
};
CurvedPoint curved_point(const double V[3], const Curvature& K, double t);

// The first hit of the same ray with the relief over a curved base (docs/design.md, "Curved
// surfaces"): in the ray's vertical plane the base is the circle of its normal curvature
// k_n = e.K.e (e the direction the ray travels over the surface), the relief stands along the
// circle's normals, its texture runs along the circle by arc length, and the cross term
// k_c = e_perp.K.e moves it sideways by -h k_c (arc) to first order. This agrees with the
// quadric z = -(k_uu x^2 + 2 k_uv x y + k_vv y^2) / 2 to second order and is exact on a sphere
// (geodesic polar coordinates). A double-precision march in steps of 1/32 texel and s/256 of
// depth, each sign change bisected: the tests' oracle for the curved trace. Zero curvature gives
// exact_hit's hit up to the bisection's tolerance.
CurvedHit curved_hit(const HeightMap& map, double u, double v, const double V[3],
                     const PassSettings& settings, const Curvature& k);

// Bilinear height in double with the project's texel-centre convention.
double bilinear_height(const HeightMap& map, double u, double v, AddressMode address);

}  // namespace offsetmap
