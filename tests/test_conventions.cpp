// The binding conventions of docs/design.md, pinned through the kernels themselves.
#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "support.hpp"

namespace omtest {
namespace {

// parallax straight down reads H at uv exactly: t = s (r - H) / 1, so H = r - t / s.
std::vector<float> probe_heights(const HeightMap& map, const std::vector<std::array<float, 2>>& uvs,
                                 AddressMode address = AddressMode::Wrap) {
    std::vector<std::array<float, 5>> px;
    for (auto& uv : uvs) px.push_back({uv[0], uv[1], 0.0f, 0.0f, 1.0f});
    PassSettings s;
    s.scale = 1.0f;
    s.reference_plane = 1.0f;
    s.address = address;
    OffsetResult r = run("parallax", map, row_gbuffer(px), s);
    std::vector<float> h;
    for (float t : r.depth) h.push_back(1.0f - t);
    return h;
}

TEST(Conventions, TexelCentresAndRowOrder) {
    // One bright texel at (i, j) = (2, 1) of a 4x4 map: row 1 holds it, column 2.
    HeightMap m = make_map(4, 4, [](int i, int j) { return (i == 2 && j == 1) ? 1.0f : 0.0f; });
    auto h = probe_heights(m, {{2.5f / 4, 1.5f / 4},    // its centre
                               {3.0f / 4, 1.5f / 4},    // halfway to (3, 1)
                               {2.5f / 4, 2.0f / 4},    // halfway to (2, 2)
                               {3.0f / 4, 2.0f / 4},    // the corner shared by four centres
                               {1.5f / 4, 2.5f / 4}});  // a dark centre
    EXPECT_NEAR(h[0], 1.0f, 1e-6f);
    EXPECT_NEAR(h[1], 0.5f, 1e-6f);
    EXPECT_NEAR(h[2], 0.5f, 1e-6f);
    EXPECT_NEAR(h[3], 0.25f, 1e-6f);
    EXPECT_NEAR(h[4], 0.0f, 1e-6f);
}

TEST(Conventions, WrapAndClampAddressing) {
    // Texel 0 is 1, texel 3 is 0 (in every row). At u = 0 the patch spans texels 3 and 0.
    HeightMap m = make_map(4, 2, [](int i, int) { return i == 0 ? 1.0f : 0.0f; });
    auto wrap = probe_heights(m, {{0.0f, 0.25f}, {-0.875f, 0.25f}, {1.125f, 0.25f}, {7.125f, 3.25f}});
    EXPECT_NEAR(wrap[0], 0.5f, 1e-6f);  // halfway between texel 3 (0) and texel 0 (1)
    EXPECT_NEAR(wrap[1], 1.0f, 1e-6f);  // -0.875 wraps to 0.125, texel 0's centre
    EXPECT_NEAR(wrap[2], 1.0f, 1e-6f);
    EXPECT_NEAR(wrap[3], 1.0f, 1e-5f);  // any tile
    auto clamp = probe_heights(m, {{0.0f, 0.25f}, {1.125f, 0.25f}, {-3.0f, 0.25f}}, AddressMode::Clamp);
    EXPECT_NEAR(clamp[0], 1.0f, 1e-6f);  // left of texel 0's centre: texel 0 repeated
    EXPECT_NEAR(clamp[1], 0.0f, 1e-6f);  // right of texel 3: texel 3 repeated
    EXPECT_NEAR(clamp[2], 1.0f, 1e-6f);
}

TEST(Conventions, ViewVectorPointsToTheEye) {
    // Eye toward +u (and then +v): the ray goes down toward -u, so a deep surface is seen at u' < u.
    HeightMap m = constant_map(0.0f);
    PassSettings s;
    s.scale = 0.1f;
    auto vx = view_dir(45, 0), vy = view_dir(45, 90);
    OffsetResult r = run("exact", m,
                         row_gbuffer({{0.5f, 0.5f, vx[0], vx[1], vx[2]}, {0.5f, 0.5f, vy[0], vy[1], vy[2]}}),
                         s);
    EXPECT_NEAR(r.uv[0].s[0], 0.5f - 0.1f, 1e-6f);  // depth s at 45 degrees: offset s
    EXPECT_NEAR(r.uv[0].s[1], 0.5f, 1e-6f);
    EXPECT_NEAR(r.uv[1].s[0], 0.5f, 1e-6f);
    EXPECT_NEAR(r.uv[1].s[1], 0.5f - 0.1f, 1e-6f);
    EXPECT_NEAR(r.depth[0], 0.1f * std::sqrt(2.0f), 1e-6f);  // t is the distance along the ray
}

TEST(Conventions, HeightVersusDepthMapFiles) {
    // 8-bit PNG: top row white, the rest black. Heights: white = 1 at row 0; --depth-map inverts.
    auto path = (std::filesystem::temp_directory_path() / "om_conv_rows.png").string();
    std::vector<unsigned char> px(4 * 3, 0);
    for (int i = 0; i < 4; ++i) px[i] = 255;
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(4, 3, 1, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    out->close();
    HeightMap h = load_height_map(path);
    HeightMap d = load_height_map(path, {0, true});
    EXPECT_EQ(h.width, 4);
    EXPECT_EQ(h.height, 3);
    EXPECT_FLOAT_EQ(h.at(1, 0), 1.0f);
    EXPECT_FLOAT_EQ(h.at(1, 2), 0.0f);
    EXPECT_FLOAT_EQ(d.at(1, 0), 0.0f);
    EXPECT_FLOAT_EQ(d.at(1, 2), 1.0f);
    // Row 0 is at v near 0.
    auto probe = probe_heights(h, {{0.5f, 0.5f / 3}, {0.5f, 2.5f / 3}});
    EXPECT_NEAR(probe[0], 1.0f, 1e-6f);
    EXPECT_NEAR(probe[1], 0.0f, 1e-6f);
    std::filesystem::remove(path);
}

TEST(Conventions, ReferencePlaneAndRayEnds) {
    // Constant H = c: the surface is at z = s (c - r); straight down the hit is at t = s (r - c),
    // negative when the relief stands above the polygon (r < c).
    for (float r : {1.0f, 0.5f, 0.0f})
        for (float c : {0.0f, 0.3f, 1.0f}) {
            PassSettings s;
            s.scale = 0.2f;
            s.reference_plane = r;
            OffsetResult res = run("exact", constant_map(c), row_gbuffer({{0.3f, 0.6f, 0, 0, 1}}), s);
            EXPECT_NEAR(res.depth[0], 0.2f * (r - c), 1e-6f) << "r " << r << " c " << c;
        }
}

TEST(Conventions, NormalsFromHeights) {
    // A ramp H = u (clamped between centres) has normal normalize(-s, 0, 1) away from the borders.
    const int n = 16;
    HeightMap m = make_map(n, 4, [](int i, int) { return (i + 0.5f) / n; });
    PassSettings s;
    s.scale = 0.25f;
    s.address = AddressMode::Clamp;
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, m, s);
    std::vector<cl_float4> normals(m.h.size());
    rt->queue().enqueueReadBuffer(f.normals, CL_TRUE, 0, normals.size() * sizeof(cl_float4),
                                  normals.data());
    const float len = std::sqrt(1.0f + 0.25f * 0.25f);
    for (int i = 0; i < n; ++i) {  // one-sided differences at the clamped borders are exact too
        EXPECT_NEAR(normals[n + i].s[0], -0.25f / len, 1e-5f) << i;
        EXPECT_NEAR(normals[n + i].s[1], 0.0f, 1e-6f);
        EXPECT_NEAR(normals[n + i].s[2], 1.0f / len, 1e-5f);
    }
}

}  // namespace
}  // namespace omtest
