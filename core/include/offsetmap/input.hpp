// An input in the caller's device memory, stored as engines store it: a buffer of float, half,
// snorm or unorm values, or an image whose format converts.
#pragma once
#include <cstddef>

#include "offsetmap/cl.hpp"
#include "offsetmap/shared.h"

namespace offsetmap {

// How a buffer input stores its values (images carry their own format).
enum class Storage : om_int {
    Float = OM_STORAGE_FLOAT,
    Half = OM_STORAGE_HALF,
    Snorm16 = OM_STORAGE_SNORM16,  // max(c / 32767, -1)
    Unorm16 = OM_STORAGE_UNORM16,  // c / 65535
    Unorm8 = OM_STORAGE_UNORM8     // c / 255
};
size_t storage_bytes(Storage storage);

// One input in the caller's memory (a plane of an engine's G-buffer, or heights): either a buffer
// of tightly packed pixels (row 0 first, the input's values per pixel in `storage`), or a
// width x height 2D image read with read_imagef (CL_R, CL_RG or CL_RGBA, or CL_BGRA or CL_ARGB,
// with as many channels as the input needs; CL_FLOAT, CL_HALF_FLOAT, CL_UNORM_INT8/16 or
// CL_SNORM_INT8/16).
struct Input {
    cl::Buffer buffer;
    Storage storage = Storage::Float;
    cl::Image2D image;

    bool bound() const { return buffer() || image(); }
};

}  // namespace offsetmap
