// Pixel depth offset: the depth output is the distance along the view ray from the polygon point
// to the hit, in uv units, so an engine can write the displaced depth (README, "Depth output").
#include "support.hpp"

namespace omtest {
namespace {

TEST(DepthOffset, MatchesTheAnalyticDepthUnderACamera) {
    // A camera over the tiled plane (tile world units per uv); a constant field H = 0 with r = 1 is
    // a floor s * tile world units below the polygon. Along the pixel's ray from the eye E through
    // the polygon point P, the floor is met at distance lambda = (E.z + s tile) / E.z * |P - E|;
    // the pass must report t with t * tile = lambda - |P - E|, and view-space depth then scales as
    // depth_hit = depth_P * (1 + t tile / |P - E|).
    PlaneScene cam;
    cam.width = 96;
    cam.height = 54;
    cam.tile = 2.5;
    cam.camera_height = 0.7;
    GBuffer gb = make_scene(cam);
    PassSettings s;
    s.scale = 0.04f;
    for (const char* method : {"exact", "maxmip", "cone", "pom", "parallax"}) {
        OffsetResult r = run(method, constant_map(0.0f, 64, 64), gb, s);
        size_t checked = 0;
        for (size_t k = 0; k < gb.pixels(); ++k) {
            if (!traced(r.flags[k])) continue;
            const auto& V = gb.view[k].s;
            double dist = cam.camera_height / V[2];  // |P - E|: E is above P along V
            double lambda = (cam.camera_height + s.scale * cam.tile) / V[2];
            // pom and parallax meet a plane exactly, like exact (constant-field rows).
            EXPECT_NEAR(r.depth[k] * cam.tile, lambda - dist, 2e-5 * lambda) << method << " " << k;
            ++checked;
        }
        EXPECT_GT(checked, gb.pixels() / 2);
    }
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

TEST(TileMask, FlagsRaysThatLeaveTheTileAndShadingDiscardsThem) {
    // A clamped (non-tiling) surface: near the edge u = 0, a view from +u sends the ray toward -u;
    // with a deep floor the hit lies outside the tile, past the polygon's edge.
    PassSettings s;
    s.scale = 0.1f;
    s.address = AddressMode::Clamp;
    auto V = view_dir(30, 0);
    GBuffer gb = row_gbuffer({{0.02f, 0.5f, V[0], V[1], V[2]}, {0.6f, 0.5f, V[0], V[1], V[2]}});
    HeightMap floor = constant_map(0.0f, 32, 32);
    OffsetResult off = run("exact", floor, gb, s);
    EXPECT_LT(off.uv[0].s[0], 0.0f);
    EXPECT_FALSE(off.flags[0] & OM_FLAG_OUT_OF_TILE);  // off by default
    s.out_of_tile_mask = true;
    OffsetResult on = run("exact", floor, gb, s);
    EXPECT_TRUE(on.flags[0] & OM_FLAG_OUT_OF_TILE);
    EXPECT_FALSE(on.flags[1] & OM_FLAG_OUT_OF_TILE);  // 0.6 - 0.17 stays inside
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, floor, s);
    DeviceGBuffer g = upload(*rt, gb);
    ShadePass shade(rt);
    auto rgba = run_shade(*rt, shade, on, g, f, nullptr, s, ShadeSettings{});
    EXPECT_EQ(rgba[0].s[3], 0.0f);  // discarded: background
    EXPECT_EQ(rgba[1].s[3], 1.0f);
}

}  // namespace
}  // namespace omtest
