// The same frames on two OpenCL implementations: PoCL (its own clang path, OM_POCL) and a second
// device ($OFFSETMAP_SECOND_DEVICE, rusticl's llvmpipe in ctest's
// portability.rusticl_matches_pocl), both at one pixel a work-item. Registered only there: the
// suite's default run has one device.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "offsetmap/evaluation.hpp"
#include "support.hpp"

using namespace offsetmap;
using namespace omtest;

namespace {

OffsetResult device_frame(const std::string& filter, const std::string& method,
                          const HeightMap& map, const GBuffer& gb, const PassSettings& s) {
    auto rt = Runtime::create(filter);
    rt->set_lanes(1);
    DeviceHeightField f = upload(*rt, map, s);
    DeviceGBuffer g = upload(*rt, gb);
    OffsetPass pass(rt, method);
    return run_offset(*rt, pass, g, f, s, 1);
}

// The steepest slope of the bilinear relief, |dH/du| or |dH/dv| in uv units (W or H per texel).
double max_slope(const HeightMap& m) {
    double g = 0.0;
    for (int j = 0; j < m.height; ++j)
        for (int i = 0; i < m.width; ++i) {
            const float h = m.at(i, j);
            g = std::max(g, std::abs(m.at((i + 1) % m.width, j) - h) * double(m.width));
            g = std::max(g, std::abs(m.at(i, (j + 1) % m.height) - h) * double(m.height));
        }
    return g;
}

}  // namespace

// Every decision (layers, cells, steps, flags, fetch counts; sphere's step count aside) is the same
// on both, and uv' differs only by rounding. The two differ where OpenCL lets them: division and
// sqrt within 2.5 and 3 ulp (PoCL's builtins against libclc's), and a * b + c fused or not. Each
// perturbs the ray's t by a few ulp of the quantities it is made of; uv' = uv - t V.xy then moves
// by at most 64 eps (1 + s |V.xy| / V.z) in uv, eps = 2^-24: 64 ulp, a generous count of the
// roundings on the way. parallax-iterative repeats the slope step k times, each a map whose
// Lipschitz constant is at most 1 + s G |V.xy| / V.z with G the steepest slope, so its bound grows
// by that factor per step.
TEST(Devices, SecondDeviceGivesPoCLsFrames) {
    const char* env = std::getenv("OFFSETMAP_SECOND_DEVICE");
    const std::string second = env && *env ? env : "llvmpipe";
    const HeightMap map = noisy_map(64);
    const GBuffer gb = make_scene(RandomScene{48, 32, 3, 5.0, 90.0});
    PassSettings s;
    s.scale = 0.08f;
    const double eps = std::ldexp(1.0, -24), slope = max_slope(map);
    const uint32_t rejected = OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING;
    for (const std::string& method : method_names()) {
        const OffsetResult a = device_frame("Portable Computing Language", method, map, gb, s);
        const OffsetResult b = device_frame(second, method, map, gb, s);
        const int steps = method == "parallax-iterative" ? 4 : 0;  // its default iterations
        size_t same = 0, pixels = 0, fetch_diff = 0;
        double worst = 0.0;
        for (size_t k = 0; k < gb.pixels(); ++k) {
            ASSERT_EQ(a.flags[k], b.flags[k]) << method << " pixel " << k;
            if (a.fetches[k] != b.fetches[k]) ++fetch_diff;
            // Sphere's march stops once its distance falls below a threshold, which rounding can
            // cross a step earlier or later; its cells then solve the same hit.
            if (method != "sphere") {
                ASSERT_EQ(a.fetches[k], b.fetches[k]) << method << " pixel " << k;
            }
            if (a.flags[k] & rejected) continue;
            ++pixels;
            if (std::memcmp(&a.uv[k], &b.uv[k], sizeof(cl_float2)) == 0) ++same;
            const cl_float4 v = gb.view[k];
            const double vz = std::max<double>(v.s[2], 1e-3), vxy = std::hypot(v.s[0], v.s[1]);
            const double reach = s.scale * vxy / vz;
            const double bound = 64.0 * eps * (1.0 + reach) * std::pow(1.0 + slope * reach, steps);
            for (int i = 0; i < 2; ++i) {
                const double d = std::abs(double(a.uv[k].s[i]) - b.uv[k].s[i]);
                ASSERT_LE(d, bound) << method << " pixel " << k << " uv[" << i << "]";
                worst = std::max(worst, d / bound);
            }
        }
        if (method == "none") {
            EXPECT_EQ(same, pixels) << "normal mapping moves nothing";
        }
        std::printf(
            "%-20s %zu of %zu pixels bit for bit, worst %.3f of the bound, %zu fetch counts"
            " differ\n",
            method.c_str(), same, pixels, worst, fetch_diff);
    }
}
