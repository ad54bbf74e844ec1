// The offset kernels run as plain threaded C++ loops over pixels (the kernel sources compiled as
// C++ with -O3 -march=native): the peer the OpenCL kernels are compared against in the bench, and
// an independent compilation of the same code for the tests.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/passes.hpp"
#include "offsetmap/shared.h"

namespace offsetmap::cpu_peer {

// Raw pointers as the kernel sees them (any may be null where the kernel allows it).
struct Args {
    OmOffsetParams params;
    const void* uv;    // float2 per pixel
    const void* view;  // float4 per pixel
    const float* heights;
    const float* aux;
    const float* lod;
    void* out_uv;
    float* out_depth;
    std::uint32_t* out_fetches;
    std::uint32_t* out_flags;
    const void* curvature = nullptr;  // float4 per pixel (the peer builds without OM_CURVED)
};

// The shade kernel's arguments (om_shade); light, flags and albedo may be null.
struct ShadeArgs {
    OmShadeParams params;  // as the shade pass sets them, the G-buffer's size and has_light too
    const void* uv;        // float2 per pixel
    const std::uint32_t* flags;
    const void* view;  // float4 per pixel
    const void* light;
    const void* normals;  // float4 per texel
    const float* heights;
    const void* albedo;                  // float4 per texel
    void* out_rgba;                      // float4 per pixel
    const float* shadow_mask = nullptr;  // the lit fraction a pixel (a shadow map's), or null
    float* out_visibility = nullptr;     // the diffuse term's light visibility a pixel, or null
};
// om_shade over its work-items [begin, end): one pixel each (one lane).
void shade(const ShadeArgs& args, int begin, int end);

// The compiled peer of a method (by kernel file, e.g. "pom.cl"); throws Error if none.
using Entry = void (*)(const Args&, int begin, int end);
Entry entry_for(const std::string& kernel_file);

struct Run {
    OffsetResult result;
    double median_ms = 0;  // wall time of the threaded loop
};

// Runs `method` over the G-buffer with `threads` threads (0: all), `repeats` times after a
// warm-up. Methods with precomputed data are not supported (throws Error).
Run run(const std::string& method, const std::map<std::string, std::string>& params,
        const GBuffer& gbuffer, const HeightMap& map, const PassSettings& settings, int repeats,
        unsigned threads = 0);

}  // namespace offsetmap::cpu_peer
