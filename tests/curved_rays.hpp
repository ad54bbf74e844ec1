// Rays over curved bases for the curved trace's tests (test_curved_trace.cpp, test_uv_metric.cpp):
// a pixel's uv, its view and its base, drawn at random, and a hit's distance in texels.
#pragma once
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "offsetmap/oracle.hpp"
#include "support.hpp"

namespace omtest {

struct CurvedRay {
    float u, v;
    std::array<float, 3> V;
    Curvature K;
};

// n rays at uv uniform in the unit square, `lowest` to `lowest` + `span` degrees above the
// plane at any azimuth, over the bases in turn.
inline std::vector<CurvedRay> random_rays(int n, const std::vector<Curvature>& bases, unsigned seed,
                                          double lowest = 12.0, double span = 73.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<CurvedRay> rays;
    for (int i = 0; i < n; ++i) {
        CurvedRay r;
        r.u = static_cast<float>(unit(rng));
        r.v = static_cast<float>(unit(rng));
        r.V = view_dir(lowest + span * unit(rng), 360.0 * unit(rng));
        r.K = bases[i % bases.size()];
        rays.push_back(r);
    }
    return rays;
}

// |uv - the hit's uv| in texels of an n-texel map, across the wrap.
inline double texels(const CurvedHit& c, const cl_float2& got, int n) {
    auto wrapped = [](double d) { return d - std::round(d); };
    return std::hypot(wrapped(got.s[0] - c.u), wrapped(got.s[1] - c.v)) * n;
}

}  // namespace omtest
