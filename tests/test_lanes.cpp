// Lane methods run OM_LANES pixels per work-item (kernels/common/lanes.h): 1 on GPUs and in the
// C++ peer, 8 or 16 on CPUs, and read heights from the buffer or (GPUs) through an image view of
// it. Every lane count and both paths must give the same frame: the same arithmetic per pixel, only
// spread over SIMD lanes or read through another path, so results are compared bit for bit,
// including the flags and fetch counts of rejected pixels and a last work-item only partly filled.
#include <cstring>
#include <limits>
#include <map>
#include <random>

#include "support.hpp"

namespace omtest {
namespace {

// A work-item's group of lanes is a block of the image, 4 x 4 pixels for 16 lanes (4 x 2 for 8).
// 37 x 7 by default: whole blocks, blocks cut by the right edge to one column and by the bottom to
// three rows (or one), and the corner; 25 x 11 gives 7 x 3 blocks, so with lane pairs the last
// work-item has no second group.
GBuffer mixed_scene(int width = 37, int height = 7) {
    GBuffer gb = make_scene(RandomScene{width, height, 99, 0.5, 90.0});
    const float nan = std::numeric_limits<float>::quiet_NaN(),
                inf = std::numeric_limits<float>::infinity();
    const float bad[][5] = {{nan, 0.5f, 0, 0, 1},      {0.5f, 0.5f, inf, 0, 1},
                            {0.5f, 0.5f, 0, 0, 0},     {0.5f, 0.5f, 0.6f, 0, -0.8f},
                            {0.5f, 0.5f, 6, 0, 8},     {1e6f, -1e6f, 0.6f, 0, 0.8f},
                            {0.5f, 0.5f, 1, 0, 1e-30f}};
    for (size_t k = 0; k < std::size(bad); ++k) {
        const size_t at = 13 * k + 5;
        gb.uv[at] = {{bad[k][0], bad[k][1]}};
        gb.view[at] = {{bad[k][2], bad[k][3], bad[k][4], 0.0f}};
    }
    return gb;
}

std::shared_ptr<Runtime> runtime_with_lanes(int lanes, bool images = false) {
    static std::map<std::pair<int, bool>, std::shared_ptr<Runtime>> runtimes;
    auto& rt = runtimes[{lanes, images}];
    if (!rt) {
        rt = Runtime::create();
        rt->set_lanes(lanes);
        rt->set_images(images);
    }
    return rt;
}

OffsetResult run_with_lanes(int lanes, const std::string& method, const HeightMap& map,
                            const GBuffer& gb, const PassSettings& s, bool images = false) {
    auto rt = runtime_with_lanes(lanes, images);
    DeviceHeightField f = upload(*rt, map, s);
    DeviceGBuffer g = upload(*rt, gb);
    OffsetPass pass(rt, method);
    EXPECT_EQ(pass.lanes(), lanes) << method;
    EXPECT_EQ(pass.pixels_per_item(), lanes * (lanes > 1 && pass.method().lane_pairs ? 2 : 1))
        << method;
    return run_offset(*rt, pass, g, f, s, 1);
}

// Bit for bit, every pixel: uv', depth, flags and fetch count.
void expect_same_frame(const OffsetResult& r, const OffsetResult& ref, size_t pixels,
                       const std::string& what) {
    for (size_t k = 0; k < pixels; ++k) {
        SCOPED_TRACE(what + " pixel " + std::to_string(k));
        ASSERT_EQ(std::memcmp(&r.uv[k], &ref.uv[k], sizeof(cl_float2)), 0)
            << r.uv[k].s[0] << "," << r.uv[k].s[1] << " vs " << ref.uv[k].s[0] << ","
            << ref.uv[k].s[1];
        ASSERT_EQ(std::memcmp(&r.depth[k], &ref.depth[k], sizeof(float)), 0);
        ASSERT_EQ(r.flags[k], ref.flags[k]);
        ASSERT_EQ(r.fetches[k], ref.fetches[k]);
    }
}

TEST(Lanes, EveryLaneCountAndTheImagePathGiveTheSameFrame) {
    HeightMap map = noisy_map(64, 17);
    GBuffer gb = mixed_scene();
    // Wrap with the clamp grazing rule; and clamp addressing, offset limiting and footprint LOD.
    PassSettings plain, other;
    plain.scale = other.scale = 0.1f;
    other.lod.enabled = other.lod.footprint = true;
    other.grazing = GrazingPolicy::Limit;
    other.address = AddressMode::Clamp;
    for (const auto& name : method_names()) {
        for (const PassSettings* s : {&plain, &other}) {
            OffsetResult ref = run_with_lanes(1, name, map, gb, *s);
            // Lanes 8 and 16 from the buffer; lanes 1 and 16 through the image path.
            for (auto [lanes, images] : {std::pair{8, false}, {16, false}, {1, true}, {16, true}}) {
                if (lanes == 8 && s == &other) continue;  // 8 and 16 share every code path
                OffsetResult r = run_with_lanes(lanes, name, map, gb, *s, images);
                expect_same_frame(
                    r, ref, gb.pixels(),
                    name + " lanes " + std::to_string(lanes) + (images ? " images" : ""));
            }
        }
    }
}

TEST(Lanes, BlocksCoverEveryPixelOfImagesOfAnySize) {
    // The block layout alone, quickly (the planted bugs in it run this test): sides 1 to 3 pixels
    // past a multiple of the block's, images smaller than a block, and whole blocks; pom (one group
    // a work-item) and cone (two: 4 x 4 is one block, so its work-item walks one group), at 16 and
    // 8 lanes against one pixel a work-item.
    HeightMap map = noisy_map(32, 5);
    PassSettings s;
    s.scale = 0.1f;
    for (auto [w, h] : {std::pair{37, 7}, {6, 9}, {4, 4}, {1, 5}, {13, 2}}) {
        const GBuffer gb = make_scene(RandomScene{w, h, 7, 0.5, 90.0});
        for (const char* name : {"pom", "cone"}) {
            const OffsetResult ref = run_with_lanes(1, name, map, gb, s);
            for (int lanes : {8, 16})
                expect_same_frame(run_with_lanes(lanes, name, map, gb, s), ref, gb.pixels(),
                                  std::string(name) + " " + std::to_string(w) + "x" +
                                      std::to_string(h) + " lanes " + std::to_string(lanes));
        }
    }
}

TEST(Lanes, TwoGroupsPerWorkItemGiveTheSameFrame) {
    // The methods whose work-items walk two groups of lanes (lane_pairs), against one pixel per
    // work-item: wrap, and clamp with footprint LOD (each group's lanes at their own levels), on
    // 25 x 11 pixels: 21 blocks, so the last work-item walks one group.
    HeightMap map = noisy_map(48, 29);
    GBuffer gb = mixed_scene(25, 11);
    PassSettings wrap, other;
    wrap.scale = other.scale = 0.1f;
    other.lod.enabled = other.lod.footprint = true;
    other.address = AddressMode::Clamp;
    int paired = 0;
    for (const auto& name : method_names()) {
        if (!find_method(name).lane_pairs) continue;
        ++paired;
        for (const PassSettings* s : {&wrap, &other})
            expect_same_frame(run_with_lanes(16, name, map, gb, *s),
                              run_with_lanes(1, name, map, gb, *s), gb.pixels(),
                              name + (s == &wrap ? " wrap" : " clamp, LOD"));
    }
    EXPECT_GE(paired, 3);  // cone, exact, sphere
}

TEST(Lanes, RowsReadAsPairsGiveTheSameFrameOnMapsOfAnySize) {
    // On a CPU, lanes read a patch row as one 64-bit pair unless a lane's row wraps or is clamped
    // at the map's edge (kernels/common/lanes.h). Sizes that are not powers of two take the other
    // wrap path; with 16 random pixels per work-item on a map 48 texels wide, about 1 - (47/48)^16
    // = 29 % of a work-item's fetches have a lane at the wrap edge and read singly.
    std::mt19937 rng(23);
    HeightMap map =
        make_map(48, 40, [&rng](int, int) { return static_cast<float>((rng() >> 8) * 0x1.0p-24); });
    GBuffer gb = mixed_scene(25, 11);
    PassSettings wrap, clamp;
    wrap.scale = clamp.scale = 0.2f;
    clamp.address = AddressMode::Clamp;
    for (const auto& name : method_names())
        for (const PassSettings* s : {&wrap, &clamp})
            expect_same_frame(run_with_lanes(16, name, map, gb, *s),
                              run_with_lanes(1, name, map, gb, *s), gb.pixels(),
                              name + (s == &wrap ? " wrap" : " clamp"));
}

// The shade pass in blocks of lanes (kernels/shade.cl) against one pixel a work-item, every shadow
// mode, with and without an albedo image, under both address modes and offset limiting. The
// arithmetic per pixel is the same; what may differ is a transcendental function's vector and
// scalar forms in the math library, each within OpenCL's bound of the true value. The specular
// term 2^y, y = shininess log2(n.h) <= 0: exp2 within 3 ulp (results up to 1, ulp 2^-23 taken),
// and log2's 3 ulp (relative) with the product's half ulp move y by 3.5 2^-23 |y|, the result by
// ln 2 times that times 2^y, where 2^y |y| <= 1 / (e ln 2): at most 4.3 2^-23 a form, weighted by
// specular. The soft shadow's visibility: atan 5 ulp and atan2 6 ulp of angles below pi / 2 (ulp
// 2^-23), divided by the light's size and weighted by diffuse times an albedo of at most 1. Two
// forms differ by at most twice each bound. Everything else (the hard shadow's slope test, the
// march's samples) is exact arithmetic and so the same bits; blocks cut by the image's edges and
// rejected pixels included.
TEST(Lanes, ShadeInBlocksGivesOnePixelAWorkItemsImage) {
    HeightMap map = noisy_map(48, 31);
    const GBuffer gb = mixed_scene(37, 7);
    Image4 albedo{5, 3, {}};
    for (int k = 0; k < 15; ++k)
        albedo.texels.push_back({{0.1f + 0.05f * k, 1.0f - 0.06f * k, 0.5f, 1.0f}});
    PassSettings wrap, clamp;
    wrap.scale = clamp.scale = 0.1f;
    clamp.address = AddressMode::Clamp;
    clamp.grazing = GrazingPolicy::Limit;
    auto shade_with = [&](int lanes, const PassSettings& s, const ShadeSettings& ss, bool image) {
        auto rt = runtime_with_lanes(lanes);
        DeviceHeightField f = upload(*rt, map, s);
        DeviceGBuffer g = upload(*rt, gb);
        const OffsetResult r = run_with_lanes(1, "pom", map, gb, s);
        ShadePass pass(rt);
        DeviceImage a;
        if (image) a = upload(*rt, albedo);
        return run_shade(*rt, pass, r, g, f, image ? &a : nullptr, s, ss);
    };
    for (ShadowMode mode : {ShadowMode::None, ShadowMode::Hard, ShadowMode::Soft})
        for (const PassSettings* s : {&wrap, &clamp})
            for (bool image : {false, true}) {
                ShadeSettings ss;
                ss.shadow = mode;
                ss.light[0] = 0.8f, ss.light[1] = -0.3f, ss.light[2] = 0.45f;  // long shadows
                const double bound =
                    ss.specular * 2 * 4.3 * 0x1.0p-23 +
                    (mode == ShadowMode::Soft
                         ? ss.diffuse * 2 * (5 + 6) * 0x1.0p-23 / (ss.light_size_deg * M_PI / 180)
                         : 0.0);
                const auto ref = shade_with(1, *s, ss, image);
                if (mode != ShadowMode::None) {  // the march shades something: shadows are cast
                    ShadeSettings lit = ss;
                    lit.shadow = ShadowMode::None;
                    const auto unshadowed = shade_with(1, *s, lit, image);
                    size_t darker = 0;
                    for (size_t k = 0; k < gb.pixels(); ++k)
                        darker += ref[k].s[0] < unshadowed[k].s[0] - 0.01f;
                    EXPECT_GT(darker, gb.pixels() / 20) << static_cast<int>(mode);
                }
                for (int lanes : {8, 16}) {
                    const auto c = shade_with(lanes, *s, ss, image);
                    double worst = 0;
                    for (size_t k = 0; k < gb.pixels(); ++k)
                        for (int ch = 0; ch < 4; ++ch)
                            worst = std::max(worst,
                                             std::fabs(double(c[k].s[ch]) - double(ref[k].s[ch])));
                    EXPECT_LE(worst, bound)
                        << "shadows " << static_cast<int>(mode) << (s == &wrap ? " wrap" : " clamp")
                        << (image ? " albedo" : " checker") << " lanes " << lanes;
                    std::printf("shade lanes %d, shadows %d%s%s: worst %.3g (bound %.3g)\n", lanes,
                                static_cast<int>(mode), s == &wrap ? " wrap" : " clamp",
                                image ? " albedo" : "", worst, bound);
                }
            }
}

}  // namespace
}  // namespace omtest
