// The C++ peer (the kernel sources compiled as C++) against the OpenCL kernels on PoCL: two
// compilers, one algorithm. Float rounding differs between them (contraction into FMA, library
// sqrt), so a branch on a threshold can flip for a pixel that sits on it; everything else agrees.
#include "cpu_peer.hpp"
#include "support.hpp"

namespace omtest {
namespace {

double texel_distance(const cl_float2& a, const cl_float2& b, const HeightMap& m) {
    return std::hypot((a.s[0] - b.s[0]) * m.width, (a.s[1] - b.s[1]) * m.height);
}

TEST(CpuPeer, MatchesTheKernelsOnRandomRays) {
    // Where the two compilations disagree by more than 1e-3 texel, the pixel must sit on a
    // discontinuity of the kernel itself: its answer jumps by as much when one input (u, v or a
    // component of V) moves by 2^-20 of its size, 8 float ulps, about the rounding the two
    // compilers' differences (FMA contraction, library sqrt) accumulate through a pixel's chain.
    // Everywhere else they agree to 1e-3 texel; flags agree everywhere.
    GBuffer gb = make_scene(RandomScene{64, 32, 4242, 2.0, 90.0});
    // The peer takes the pass's own parameters, so every grazing policy carries over; cliffs
    // put searches on discontinuities.
    for (const HeightMap& map : {smooth_map(64), cliff_map(64)})
        for (GrazingPolicy policy :
             {GrazingPolicy::Clamp, GrazingPolicy::Limit, GrazingPolicy::Cap})
            for (const auto& m : methods()) {
                PassSettings s;
                s.scale = 0.08f;
                s.grazing = policy;
                s.max_offset_texels = 8.0f;
                if (m.precompute) continue;  // the peer builds no precomputed data
                OffsetResult gpu = run(m.name, map, gb, s);
                cpu_peer::Run cpu = cpu_peer::run(m.name, {}, gb, map, s, 0, 2);
                std::vector<size_t> apart;
                for (size_t k = 0; k < gb.pixels(); ++k) {
                    ASSERT_EQ(cpu.result.flags[k], gpu.flags[k]) << m.name << " " << k;
                    if (texel_distance(cpu.result.uv[k], gpu.uv[k], map) > 1e-3) apart.push_back(k);
                }
                if (apart.empty()) continue;
                // Ten nudged copies of each pixel that disagrees.
                std::vector<std::array<float, 5>> nudged;
                for (size_t k : apart) {
                    const float in[5] = {gb.uv[k].s[0], gb.uv[k].s[1], gb.view[k].s[0],
                                         gb.view[k].s[1], gb.view[k].s[2]};
                    for (int c = 0; c < 5; ++c)
                        for (float sign : {-1.0f, 1.0f}) {
                            std::array<float, 5> px;
                            std::copy(in, in + 5, px.begin());
                            px[c] += sign * std::ldexp(std::max(std::fabs(in[c]), 1e-3f), -20);
                            nudged.push_back(px);
                        }
                }
                OffsetResult moved = run(m.name, map, row_gbuffer(nudged), s);
                for (size_t a = 0; a < apart.size(); ++a) {
                    double jump = 0.0;
                    for (int c = 0; c < 10; ++c)
                        jump = std::max(
                            jump, texel_distance(moved.uv[10 * a + c], gpu.uv[apart[a]], map));
                    EXPECT_GT(jump, 1e-3)
                        << m.name << " policy " << static_cast<int>(policy) << ": pixel "
                        << apart[a] << " differs by "
                        << texel_distance(cpu.result.uv[apart[a]], gpu.uv[apart[a]], map)
                        << " texel between the compilations but is not on a discontinuity";
                }
                std::printf("%s, policy %d: %zu of %zu pixels on a discontinuity differ\n",
                            m.name.c_str(), static_cast<int>(policy), apart.size(), gb.pixels());
            }
}

}  // namespace
}  // namespace omtest
