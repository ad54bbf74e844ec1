// The G-buffer EXR file format (a public contract) and scene sources.
#include <filesystem>
#include <limits>

#include "support.hpp"

namespace omtest {
namespace {

bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(GBufferFile, RoundTripKeepsEveryChannelBitForBit) {
    GBuffer gb = make_scene(RandomScene{17, 9, 4, 3.0, 80.0});
    gb.light.assign(gb.pixels(), {{0.1f, -0.2f, 0.97f, 0.0f}});
    gb.lod.assign(gb.pixels(), 2.5f);
    for (size_t k = 0; k < gb.pixels(); ++k)
        gb.curvature.push_back({{0.5f * k, -0.25f, 3.0f, 1.0f + 0.125f * (k % 5)}});
    gb.uv[3] = {{std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::quiet_NaN()}};
    gb.view[5] = {{0.0f, 0.0f, -1.0f, 0.0f}};
    auto path = (std::filesystem::temp_directory_path() / "om_gbuffer_rt.exr").string();
    save_gbuffer(path, gb);
    GBuffer back = load_gbuffer(path);
    ASSERT_EQ(back.width, 17);
    ASSERT_EQ(back.height, 9);
    ASSERT_TRUE(back.has_light());
    ASSERT_TRUE(back.has_lod());
    for (size_t k = 0; k < gb.pixels(); ++k) {
        for (int a = 0; a < 2; ++a) EXPECT_TRUE(same_bits(back.uv[k].s[a], gb.uv[k].s[a])) << k;
        for (int a = 0; a < 3; ++a) {
            EXPECT_TRUE(same_bits(back.view[k].s[a], gb.view[k].s[a])) << k;
            EXPECT_TRUE(same_bits(back.light[k].s[a], gb.light[k].s[a])) << k;
        }
        EXPECT_EQ(back.lod[k], 2.5f);
        for (int a = 0; a < 4; ++a)
            EXPECT_TRUE(same_bits(back.curvature[k].s[a], gb.curvature[k].s[a])) << k;
    }
    // A curvature value that is not finite is an error naming the channel and the pixel.
    gb.curvature[20].s[2] = std::numeric_limits<float>::infinity();
    save_gbuffer(path, gb);
    EXPECT_TRUE(contains(error_of([&] { load_gbuffer(path); }),
                         "om_gbuffer_rt.exr': channel kvv is not finite at pixel (3, 1)"));
    // Without the optional channels the file has just u v Vx Vy Vz.
    GBuffer plain = make_scene(RandomScene{4, 4, 1, 5.0, 90.0});
    save_gbuffer(path, plain);
    GBuffer plain_back = load_gbuffer(path);
    EXPECT_FALSE(plain_back.has_light());
    EXPECT_FALSE(plain_back.has_lod());
    EXPECT_FALSE(plain_back.has_curvature());
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in);
    auto names = in->spec().channelnames;  // OpenEXR stores channels sorted by name
    std::sort(names.begin(), names.end());
    EXPECT_EQ(names, (std::vector<std::string>{"Vx", "Vy", "Vz", "u", "v"}));
    std::filesystem::remove(path);
}

TEST(GBufferFile, ChannelsAreFoundByNameInAnyOrder) {
    // An engine may write channels in any order and add its own; only the names matter.
    auto path = (std::filesystem::temp_directory_path() / "om_gbuffer_order.exr").string();
    OIIO::ImageSpec spec(2, 1, 6, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"Vz", "extra", "v", "Vx", "u", "Vy"};
    std::vector<float> px = {0.8f, 9.0f, 0.25f, 0.6f, 0.75f,  0.0f,
                             1.0f, 9.0f, 0.5f,  0.0f, 0.125f, 0.0f};
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    GBuffer gb = load_gbuffer(path);
    EXPECT_EQ(gb.uv[0].s[0], 0.75f);
    EXPECT_EQ(gb.uv[0].s[1], 0.25f);
    EXPECT_EQ(gb.view[0].s[0], 0.6f);
    EXPECT_EQ(gb.view[0].s[2], 0.8f);
    EXPECT_EQ(gb.uv[1].s[0], 0.125f);
    std::filesystem::remove(path);
}

TEST(Scenes, PlaneCameraSeesThePlane) {
    PlaneScene p;
    p.width = 64;
    p.height = 48;
    p.pitch_deg = 10.0;  // the horizon is in view: the top rows miss the plane
    GBuffer gb = make_scene(p);
    EXPECT_TRUE(std::isnan(gb.uv[0].s[0]));  // sky
    size_t bottom = gb.pixels() - 1;
    ASSERT_TRUE(std::isfinite(gb.uv[bottom].s[0]));
    for (size_t k = 0; k < gb.pixels(); ++k) {
        if (std::isnan(gb.uv[k].s[0])) continue;
        const auto& V = gb.view[k].s;
        EXPECT_NEAR(V[0] * V[0] + V[1] * V[1] + V[2] * V[2], 1.0, 1e-6);
        EXPECT_GT(V[2], 0.0f);
        // The eye is on V's line from the surface point: (u, v, 0) + (h / V.z) V = camera.
        double t = p.camera_height / V[2];
        EXPECT_NEAR(gb.uv[k].s[0] + t * V[0], 0.0, 1e-4);
        EXPECT_NEAR(gb.uv[k].s[1] + t * V[1], 0.0, 1e-4);
    }
}

TEST(Scenes, SweepAndRandomCoverTheirRanges) {
    SweepScene sw{5, 4, 3, 10.0, 90.0};
    GBuffer s = make_scene(sw);
    ASSERT_EQ(s.width, 12);
    ASSERT_EQ(s.height, 15);
    EXPECT_NEAR(std::asin(s.view[0].s[2]) * 180 / M_PI, 90.0, 1e-3);
    EXPECT_NEAR(std::asin(s.view[s.pixels() - 1].s[2]) * 180 / M_PI, 10.0, 1e-3);
    EXPECT_FLOAT_EQ(s.uv[0].s[0], 0.5f / 3);
    GBuffer a = make_scene(RandomScene{32, 32, 9, 20.0, 40.0});
    GBuffer b = make_scene(RandomScene{32, 32, 9, 20.0, 40.0});
    for (size_t k = 0; k < a.pixels(); ++k) {
        EXPECT_EQ(std::memcmp(&a.view[k], &b.view[k], sizeof(cl_float4)),
                  0);  // same seed, same buffer
        double e = std::asin(a.view[k].s[2]) * 180 / M_PI;
        EXPECT_GE(e, 20.0 - 1e-4);
        EXPECT_LE(e, 40.0 + 1e-4);
        EXPECT_GE(a.uv[k].s[0], 0.0f);
        EXPECT_LT(a.uv[k].s[0], 1.0f);
    }
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

TEST(ContactSheet, SmallFramesAreEnlargedSoTheirLabelsFit) {
    // A 64 x 32 frame (a small G-buffer): its tile grows by whole texels to at least 560 wide.
    Rgb8 tile{64, 32, std::vector<std::uint8_t>(64 * 32 * 3)};
    for (size_t k = 0; k < tile.rgb.size(); ++k) tile.rgb[k] = static_cast<std::uint8_t>(k * 7);
    Rgb8 sheet = contact_sheet({{"a label as long as the compare command writes", tile}}, 1);
    const int zoom = 9, pad = 6, label_h = 28;  // ceil(560 / 64)
    EXPECT_EQ(sheet.width, 64 * zoom + 2 * pad);
    EXPECT_EQ(sheet.height, 32 * zoom + label_h + 2 * pad);
    // Nearest texel: every sheet pixel of the tile is its source texel.
    for (int y = 0; y < 32 * zoom; y += 13)
        for (int x = 0; x < 64 * zoom; x += 11)
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(sheet.rgb[((pad + label_h + y) * sheet.width + pad + x) * 3 + c],
                          tile.rgb[((y / zoom) * 64 + x / zoom) * 3 + c])
                    << x << ", " << y;
}

}  // namespace
}  // namespace omtest
