// The height field on the device: heights, their mip pyramid and normals.
#pragma once
#include "offsetmap/heightmap.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/settings.hpp"

namespace offsetmap {

// Uploads heights and derives normals on the device (or takes `normal_map` when given).
DeviceHeightField upload(Runtime& runtime, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map = nullptr);

}  // namespace offsetmap
