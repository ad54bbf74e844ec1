#pragma once
#include <cstdint>

#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"

namespace offsetmap {

// A pinhole camera over the plane z = 0, tiled with the texture every `tile` world units. The
// plane's tangent frame is the world frame (x = +u, y = +v, z = normal), so V and L are world
// directions. Pixels whose ray misses the plane are empty (uv NaN).
struct PlaneScene {
    int width = 960;
    int height = 540;
    double camera_x = 0.0, camera_y = 0.0;  // camera position over the plane (world units)
    double camera_height = 0.4;             // world units above the plane
    double pitch_deg = 35.0;                // look-down angle below the horizon
    double yaw_deg = 30.0;                  // heading, from +x toward +y
    double fov_deg = 55.0;                  // vertical field of view
    double tile = 1.0;                      // world units per uv unit
    double light[3] = {0.55, 0.35, 0.76};   // directional light toward the light (world = tangent)
    bool with_light = true;
};

// Elevation x azimuth grid: an (azimuths * patch) x (elevations * patch) image whose
// patch x patch blocks each cover the unit uv tile at texel-like centres with one view direction.
// Rows go from max_elevation_deg (top) down to min_elevation_deg (bottom).
struct SweepScene {
    int elevations = 12;
    int azimuths = 8;
    int patch = 16;
    double min_elevation_deg = 5.0;
    double max_elevation_deg = 90.0;
};

// width x height independent samples: uv uniform in [0,1)^2, V uniform on the spherical cap of
// elevations [min, max] (uniform in solid angle), from a seed (same seed, same G-buffer).
struct RandomScene {
    int width = 256;
    int height = 256;
    std::uint64_t seed = 1;
    double min_elevation_deg = 5.0;
    double max_elevation_deg = 90.0;
};

GBuffer make_scene(const PlaneScene& scene);

// Several octaves of tiling sines: smooth at large scale, detailed at texel scale, so the access
// pattern of a march is realistic for any size. Rounded to 16 bits, as a height texture an engine
// ships holds it (R16 / unorm16), so uploads keep it as unorm16 words (HeightStorage::Auto). The
// map the bench and the device check time the methods on.
HeightMap bench_map(int n);

// The plane scene as an engine writes it, on the host (float, row 0 first): window depth in the
// given convention (the far value where the ray misses the plane or passes the far plane, 10^4;
// near 0.01), the camera's inverse view-projection (GLM's right-handed perspective) and eye, the
// plane's tangent frame (normal +z, tangent +x, handedness +1) and uv (NaN on sky). The same
// pixels, rays and uv as make_scene's.
struct EngineScene {
    int width = 0;
    int height = 0;
    EngineCamera camera;
    std::vector<float> depth;  // 1 value per pixel
    FrameForm frame = FrameForm::NormalTangent;
    std::vector<float> normal;    // 4 per pixel (the quaternion in the quaternion form)
    std::vector<float> tangent;   // 4 per pixel (empty in the quaternion form)
    std::vector<float> uv;        // 2 per pixel
    EngineLight light;            // the plane scene's light, directional, when it has one
    std::vector<float> material;  // empty, or 1 material id per pixel (files keep it)
    // empty, or 4 per pixel: du/dx, dv/dx per pixel step right, du/dy, dv/dy per row step in file
    // order (a rasterizer's uv derivatives; files keep them)
    std::vector<float> uv_derivatives;
    // empty, or 3 per pixel: the base surface's second fundamental form k_uu, k_uv, k_vv in the
    // pixel's tangent frame (T, B = w N x T) in uv units (world curvature times the uv density),
    // positive where the surface bends away from its normal (files keep it)
    std::vector<float> curvature;
    // empty, or 1 per pixel beside the curvature: the uv's stretch sqrt(|dP/du| / |dP/dv|), the
    // unit the curvature and the trace take along u being one uv density times it (1, or not
    // above 0: none; files keep it)
    std::vector<float> uv_stretch;

    size_t pixels() const { return static_cast<size_t>(width) * height; }
};
EngineScene make_engine_scene(const PlaneScene& scene, DepthConvention depth,
                              FirstRow first_row = FirstRow::Top);

// The explicit G-buffer of an engine scene, reconstructed on `runtime`'s device by the
// reconstruct pass (from float buffers) and read back: what the offset pass sees in a frame.
GBuffer reconstruct(std::shared_ptr<Runtime> runtime, const EngineScene& scene);
GBuffer make_scene(const SweepScene& scene);
GBuffer make_scene(const RandomScene& scene);

}  // namespace offsetmap
