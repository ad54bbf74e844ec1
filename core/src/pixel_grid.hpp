// A frame's pixels and camera as the kernels that unproject them read them (shared.h's
// OmPixelGrid, kernels/common/unproject.cl), with the checks every such pass makes of the camera.
#pragma once
#include <array>
#include <string>

#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/shared.h"

namespace offsetmap {

bool finite(const float* v, size_t n);

// Throws Error naming `what` ("the engine camera") for a depth convention or first row outside
// their enums, a matrix or eye that is not finite, or an orthographic view with no direction.
void check_camera(const EngineCamera& camera, const std::string& what);

// The grid of width x height pixels `camera` sees (its conventions checked by check_camera).
OmPixelGrid pixel_grid(const EngineCamera& camera, int width, int height, const std::string& what);

// Throws Error naming `what` unless `view_projection` is the inverse of the camera's
// inverse_view_projection (their product within 1e-3 of the identity, in the larger of its
// entries' scale): the two matrices a pass that projects back reads must be one camera's.
void check_inverse(const std::array<float, 16>& view_projection, const EngineCamera& camera,
                   const std::string& what);

}  // namespace offsetmap
