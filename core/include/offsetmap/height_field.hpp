// The height field on the device: heights, their mip pyramid and normals.
#pragma once
#include "offsetmap/heightmap.hpp"
#include "offsetmap/input.hpp"
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

// Heights already in the caller's device memory, on the runtime's context: a width x height
// buffer (one value per texel in `storage`: unorm8, unorm16, half or float) or image (its first
// channel, read as float). depth_map: the values are depths, 1 the deepest (H = 1 - value).
struct DeviceHeights {
    int width = 0;
    int height = 0;
    Input texels;
    bool depth_map = false;
};

// As the host upload, from the caller's device memory: copied into the field's own pyramid on the
// device (the caller may reuse its memory once `ready` completes), every step chained by events
// after `wait`. Values outside [0,1] are clamped and NaN read as 0, counted in `clamped` (one
// uint, complete with `ready`), as the file readers count what they clamp.
DeviceHeightField upload(Runtime& runtime, const DeviceHeights& heights,
                         const PassSettings& settings, const Image4* normal_map = nullptr,
                         const std::vector<cl::Event>& wait = {}, cl::Buffer* clamped = nullptr);

// The field's heights rewritten in place, from the host or the caller's device memory: the same
// size and settings, no reallocation. Level 0 is imported after `wait` (give it the events of every
// frame still reading the field: the update overwrites what they read), then the mips, unorm16
// words and normals are rebuilt on the device (the normals from `normal_map` when given, else
// derived from the new heights); `field.ready` becomes the last step's event and the field's
// version advances, so every pass and material frame holding the field, or a copy of it, rebuilds
// its precomputed data on its next enqueue. Returns without waiting, as upload does. Throws Error
// for another size, a buffer the library cannot write, or heights the field's storage cannot keep
// (a field uploaded as unorm16 words takes only 16-bit values under HeightStorage::Auto).
void update(Runtime& runtime, DeviceHeightField& field, const HeightMap& map,
            const PassSettings& settings, const Image4* normal_map = nullptr,
            const std::vector<cl::Event>& wait = {});
void update(Runtime& runtime, DeviceHeightField& field, const DeviceHeights& heights,
            const PassSettings& settings, const Image4* normal_map = nullptr,
            const std::vector<cl::Event>& wait = {}, cl::Buffer* clamped = nullptr);

}  // namespace offsetmap
