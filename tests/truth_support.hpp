// What the tests against the displaced-mesh truth share (test_truth.cpp, test_truth_triplanar.cpp).
#pragma once
#include "offsetmap/renderer/scene.hpp"

namespace omtest {

// A camera at `eye` looking at `target`, 40 degrees high, near 0.05 and far 20.
inline offsetmap::renderer::Camera looking_at(offsetmap::renderer::Vec3 eye,
                                              offsetmap::renderer::Vec3 target) {
    offsetmap::renderer::Camera c;
    c.eye = eye;
    c.target = target;
    c.fov_y_deg = 40.0f;
    c.near_plane = 0.05f;
    c.far_plane = 20.0f;
    return c;
}

// The exact walk's float error and the raster's (its uv interpolated in float over a sub-texel
// triangle, 2^-23 of a uv of at most 8 tiles, times 64 texels: 6e-5 texel) together stay below
// this; the oracle bound the exact methods are held to is a few thousandths of a texel here.
constexpr double kFloatTexels = 0.01;

}  // namespace omtest
