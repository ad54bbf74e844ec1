// The C++ peer (the kernel sources compiled as C++) against the OpenCL kernels on PoCL: two
// compilers, one algorithm. Float rounding differs between them (contraction into FMA, library
// sqrt), so a branch on a threshold can flip for a pixel that sits on it; everything else agrees.
#include "cpu_peer.hpp"
#include "support.hpp"

namespace omtest {
namespace {

TEST(CpuPeer, MatchesTheKernelsOnRandomRays) {
    HeightMap map = smooth_map(64);
    GBuffer gb = make_scene(RandomScene{64, 32, 4242, 2.0, 90.0});
    // The peer takes the pass's own parameters, so every grazing policy carries over.
    for (GrazingPolicy policy : {GrazingPolicy::Clamp, GrazingPolicy::Limit, GrazingPolicy::Cap})
        for (const auto& m : methods()) {
            PassSettings s;
            s.scale = 0.08f;
            s.grazing = policy;
            s.max_offset_texels = 8.0f;
            if (m.precompute != Precompute::None) continue;  // the peer builds no distance map
            OffsetResult gpu = run(m.name, map, gb, s);
            cpu_peer::Run cpu = cpu_peer::run(m.name, {}, gb, map, s, 0, 2);
            size_t close = 0;
            for (size_t k = 0; k < gb.pixels(); ++k) {
                ASSERT_EQ(cpu.result.flags[k], gpu.flags[k]) << m.name << " " << k;
                double e = std::hypot((cpu.result.uv[k].s[0] - gpu.uv[k].s[0]) * map.width,
                                      (cpu.result.uv[k].s[1] - gpu.uv[k].s[1]) * map.height);
                close += e <= 1e-3;
            }
            EXPECT_GE(close, gb.pixels() * 995 / 1000)
                << m.name << " policy " << static_cast<int>(policy);
        }
}

}  // namespace
}  // namespace omtest
