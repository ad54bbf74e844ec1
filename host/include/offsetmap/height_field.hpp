// The height field on the device: heights, their mip pyramid and normals.
#pragma once
#include "offsetmap/heightmap.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/settings.hpp"

namespace offsetmap {

// Uploads heights and derives mips and normals on the device (or takes `normal_map` when given),
// after `wait`. Returns without waiting: the host data is copied before it returns, and the
// field's `ready` event completes when the device work does (every step chained by events, so
// any queue, in order or not, gives the same field).
DeviceHeightField upload(Runtime& runtime, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map = nullptr,
                         const std::vector<cl::Event>& wait = {});

}  // namespace offsetmap
