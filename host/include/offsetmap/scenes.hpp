#pragma once
#include <cstdint>

#include "offsetmap/gbuffer.hpp"

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
GBuffer make_scene(const SweepScene& scene);
GBuffer make_scene(const RandomScene& scene);

}  // namespace offsetmap
