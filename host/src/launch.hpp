// What every pass's launch shares: the fixed work-group size and the checks of its inputs.
#pragma once
#include <climits>
#include <string>

#include "offsetmap/error.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"

namespace offsetmap {

// PoCL compiles a kernel once per local size: keep it fixed and pad the global size.
inline constexpr size_t kLocalSize = 64;

inline cl::NDRange padded(size_t n) {
    return cl::NDRange((n + kLocalSize - 1) / kLocalSize * kLocalSize);
}

// A kernel's arguments, in order.
template <typename... Args>
void set_args(cl::Kernel& k, const Args&... args) {
    cl_uint index = 0;
    (k.setArg(index++, args), ...);
}

inline void set_optional(cl::Kernel& k, cl_uint index, const cl::Buffer& b) {
    if (b())
        k.setArg(index, b);
    else
        k.setArg(index, sizeof(cl_mem), nullptr);  // a NULL global pointer in the kernel
}

inline void check_field(const DeviceHeightField& f) {
    if (f.width <= 0 || f.height <= 0 || !f.heights())
        throw Error("the height field has not been uploaded");
}

inline void check_gbuffer(const DeviceGBuffer& g) {
    if (g.width <= 0 || g.height <= 0 || !g.uv() || !g.view())
        throw Error("the G-buffer has no uv or view buffer");
    if (g.pixels() > static_cast<size_t>(INT_MAX))
        throw Error("the G-buffer is too large (" + std::to_string(g.pixels()) + " pixels)");
}

}  // namespace offsetmap
