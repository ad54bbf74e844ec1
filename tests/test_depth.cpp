// Pixel depth offset: the depth output is the distance along the view ray from the polygon point
// to the hit, in uv units, so an engine can write the displaced depth (docs/conventions.md, "Depth
// output").
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "support.hpp"

namespace omtest {
namespace {

// A camera built independently of make_scene (glm's lookAt and perspective, each pixel's ray
// unprojected through the inverse view-projection) looks at the tiled plane z = 0, one uv unit =
// `tile` world units, tangent frame = world frame. For every traced pixel the pass's depth t must
// place the hit at X = P - t tile V_world (docs/conventions.md, "Depth output") so that
//   - X lies on this camera's ray through the pixel (the G-buffer's P and V are the camera's),
//   - X lies on the relief in world units, z = tile s (H(X.xy / tile) - r), and no point of the
//     ray before it is below the relief (the first hit),
//   - X's view-space depth, from the camera's view matrix, is depth_P (1 + t tile / |P - E|).
// r = 1 and r = 0.6 (t < 0 where the ray meets relief above the polygon: depth toward the eye).
TEST(DepthOffset, ViewSpaceDepthFormulaHoldsUnderARealCamera) {
    PlaneScene cam;
    cam.width = 96;
    cam.height = 54;
    cam.tile = 2.5;
    cam.camera_height = 0.7;
    cam.pitch_deg = 30.0;
    cam.yaw_deg = 20.0;
    GBuffer gb = make_scene(cam);
    const glm::dvec3 eye(cam.camera_x, cam.camera_y, cam.camera_height);
    const double yaw = glm::radians(cam.yaw_deg), pitch = glm::radians(cam.pitch_deg);
    const glm::dvec3 fwd(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                         -std::sin(pitch));
    const glm::dmat4 view = glm::lookAt(eye, eye + fwd, glm::dvec3(0, 0, 1));
    const glm::dmat4 proj =
        glm::perspective(glm::radians(cam.fov_deg), double(cam.width) / cam.height, 0.01, 100.0);
    const glm::dmat4 inv_vp = glm::inverse(proj * view);
    auto view_depth = [&](const glm::dvec3& x) { return -(view * glm::dvec4(x, 1.0)).z; };

    const HeightMap map = smooth_map(64);
    const double L = cam.tile;
    for (float ref : {1.0f, 0.6f}) {
        PassSettings s;
        s.scale = 0.04f;
        s.reference_plane = ref;
        OffsetResult r = run("exact", map, gb, s);
        // Positions: the pass agrees with the double oracle to 1e-3 texel along the ray (its
        // test), i.e. tol_t = 1e-3 / 64 uv of t; in world units L tol_t. On the relief the height
        // differs by at most that times (1 + slope), slope = L s |grad H| <= L s 64 (H in [0,1]
        // changes by at most 1 per texel), per world unit of travel over L.
        const double tol_t = 1e-3 / map.width, tol_x = L * tol_t;
        const double tol_z = tol_x * (1.0 + s.scale * map.width);
        size_t checked = 0, negative = 0;
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const size_t k = static_cast<size_t>(y) * cam.width + x;
                if (!traced(r.flags[k])) continue;
                // This pixel's ray from the camera (NDC y up, image rows down).
                const double nx = 2.0 * (x + 0.5) / cam.width - 1.0;
                const double ny = 1.0 - 2.0 * (y + 0.5) / cam.height;
                glm::dvec4 far = inv_vp * glm::dvec4(nx, ny, 1.0, 1.0);
                const glm::dvec3 d = glm::normalize(glm::dvec3(far) / far.w - eye);
                const glm::dvec3 P = eye + d * (eye.z / -d.z);
                const glm::dvec3 Vw(gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]);
                ASSERT_NEAR(P.x / L, gb.uv[k].s[0], 1e-6) << k;  // float uv of the G-buffer
                ASSERT_NEAR(P.y / L, gb.uv[k].s[1], 1e-6) << k;
                const double t = r.depth[k];
                const glm::dvec3 X = P - t * L * Vw;
                // On the camera's ray: X - E is along d, at distance |P - E| + t L.
                const double along = glm::dot(X - eye, d);
                EXPECT_NEAR(glm::length(X - eye - along * d), 0.0, 1e-5 * along) << k;
                EXPECT_NEAR(along, glm::length(P - eye) + t * L, tol_x + 1e-6 * along) << k;
                // At the uv' the pass returns, and on the relief there.
                EXPECT_NEAR(X.x / L, r.uv[k].s[0], tol_t + 1e-6) << k;
                EXPECT_NEAR(X.y / L, r.uv[k].s[1], tol_t + 1e-6) << k;
                const double surface =
                    L * s.scale * (bilinear_height(map, X.x / L, X.y / L, s.address) - ref);
                EXPECT_NEAR(X.z, surface, tol_z) << k;
                // The first hit: 64 points of the ray between the top plane and X lie above the
                // relief (by more than the position tolerance).
                const double t_top = -s.scale * (1.0 - ref) / Vw.z;
                for (int i = 0; i < 64; ++i) {
                    const double ti = t_top + (t - t_top) * i / 64.0;
                    const glm::dvec3 Y = P - ti * L * Vw;
                    const double h =
                        L * s.scale * (bilinear_height(map, Y.x / L, Y.y / L, s.address) - ref);
                    ASSERT_GT(Y.z, h - tol_z) << "pixel " << k << " sample " << i;
                }
                // The view-space depth of docs/conventions.md.
                const double dist = glm::length(P - eye);
                EXPECT_NEAR(view_depth(X), view_depth(P) * (1.0 + t * L / dist),
                            view_depth(P) * tol_x / dist + 1e-9)
                    << k;
                negative += t < 0.0;
                ++checked;
            }
        EXPECT_GT(checked, gb.pixels() / 2);
        if (ref < 1.0f) {
            EXPECT_GT(negative, 0u) << "some hits above the polygon";
        }
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

TEST(TileMask, BoundsAreTheSurfacesUvRangeAndAnInfiniteSideIsOpen) {
    // A surface whose uv runs over [0, 3] x [1, 2]: the mask keeps what lies in that range, not
    // in [0,1]^2. Rays from +u and from +v toward the low edges; one stays inside.
    PassSettings s;
    s.scale = 0.1f;
    s.out_of_tile_mask = true;
    s.tile_bounds = {0.0f, 1.0f, 3.0f, 2.0f};
    auto U = view_dir(30, 0), V = view_dir(30, 90);
    GBuffer gb = row_gbuffer({{0.02f, 1.5f, U[0], U[1], U[2]},
                              {2.5f, 1.02f, V[0], V[1], V[2]},
                              {2.5f, 1.5f, U[0], U[1], U[2]}});
    HeightMap floor = constant_map(0.0f, 32, 32);
    OffsetResult off = run("exact", floor, gb, s);
    ASSERT_LT(off.uv[0].s[0], 0.0f);
    ASSERT_LT(off.uv[1].s[1], 1.0f);
    EXPECT_TRUE(off.flags[0] & OM_FLAG_OUT_OF_TILE);
    EXPECT_TRUE(off.flags[1] & OM_FLAG_OUT_OF_TILE);
    EXPECT_FALSE(off.flags[2] & OM_FLAG_OUT_OF_TILE) << "u of 2.33 lies inside [0, 3]";
    s.tile_bounds[0] = -INFINITY;  // u open toward -u, as around a cylinder
    OffsetResult open = run("exact", floor, gb, s);
    EXPECT_FALSE(open.flags[0] & OM_FLAG_OUT_OF_TILE);
    EXPECT_TRUE(open.flags[1] & OM_FLAG_OUT_OF_TILE);
    EXPECT_EQ(open.uv[0].s[0], off.uv[0].s[0]) << "the mask flags; it moves nothing";
    s.tile_bounds = {1.0f, 0.0f, 1.0f, 1.0f};
    EXPECT_TRUE(contains(error_of([&] { validate(s); }), "u_min < u_max"));
}

}  // namespace
}  // namespace omtest
