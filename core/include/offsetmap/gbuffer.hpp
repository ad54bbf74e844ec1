#pragma once
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"

namespace offsetmap {

class Runtime;

// The largest G-buffer the host side allocates: 2^27 pixels (16384 x 8192), at most 16384 a side.
inline constexpr size_t kMaxGBufferPixels = size_t(1) << 27;
inline constexpr int kMaxGBufferSide = 16384;

// A deferred G-buffer as the offset pass reads it. Pixel k = y * width + x.
// uv: float2 (a NaN u or v marks an empty pixel); view: tangent-space V toward the eye in xyz
// (w unused); light: optional tangent-space L toward the light; lod: optional mip level.
struct GBuffer {
    int width = 0;
    int height = 0;
    std::vector<cl_float2> uv;
    std::vector<cl_float4> view;
    std::vector<cl_float4> light;  // empty, or width * height
    std::vector<float> lod;        // empty, or width * height
    // empty, or width * height material ids: non-negative integers stored as floats, 0 for no
    // relief (the material frame, offsetmap/material_frame.hpp)
    std::vector<float> material;
    // empty, or width * height: the base surface's second fundamental form in its tangent frame,
    // in uv units (k_uu, k_uv, k_vv), positive where it bends away from its normal, and in w the
    // uv's stretch sqrt(|dP/du| / |dP/dv|) (1, or not a finite value above 0: none). The offset
    // pass then traces the relief over the curved base (docs/design.md, "Curved surfaces").
    std::vector<cl_float4> curvature;
    // empty, or 3 * width * height, beside the curvature (which it needs): the uv's metric and
    // its rates (docs/design.md, "The uv metric"), three planes of width * height one after the
    // other. First dP/du and dP/dv in the pixel's tangent frame, over the uv density:
    // (dP/du.T, dP/du.B, dP/dv.T, dP/dv.B); then the Christoffel symbols of the uv
    // parametrisation, (Gamma^u_uu, Gamma^u_uv, Gamma^u_vv, 0) and (Gamma^v_uu, Gamma^v_uv,
    // Gamma^v_vv, 0). It replaces the curvature plane's stretch wherever it is usable (finite,
    // det above 1e-6 of |J|^2: zeros are none); absent, the frame is today's bit for bit.
    std::vector<cl_float4> uv_metric;

    size_t pixels() const { return static_cast<size_t>(width) * height; }
    bool has_light() const { return !light.empty(); }
    bool has_lod() const { return !lod.empty(); }
    bool has_material() const { return !material.empty(); }
    bool has_curvature() const { return !curvature.empty(); }
    bool has_uv_metric() const { return !uv_metric.empty(); }
    // Throws Error for a size check_gbuffer_size rejects, or when memory runs out.
    void resize(int w, int h, bool with_light, bool with_lod);
};

// Throws Error naming `what` for a side outside [1, kMaxGBufferSide] or more than
// kMaxGBufferPixels pixels.
void check_gbuffer_size(int width, int height, const std::string& what);

// A G-buffer in device buffers: the caller may create these on its own context and fill them.
struct DeviceGBuffer {
    int width = 0;
    int height = 0;
    cl::Buffer uv;         // float2 per pixel
    cl::Buffer view;       // float4 per pixel
    cl::Buffer light;      // float4 per pixel, or a null buffer
    cl::Buffer lod;        // float per pixel, or a null buffer
    cl::Buffer material;   // float per pixel (integer material ids), or a null buffer
    cl::Buffer curvature;  // float4 per pixel (k_uu, k_uv, k_vv in uv units, stretch), or null
    cl::Buffer uv_metric;  // three float4 planes (GBuffer::uv_metric), or null; needs curvature

    size_t pixels() const { return static_cast<size_t>(width) * height; }
};

DeviceGBuffer upload(Runtime& runtime, const GBuffer& gbuffer);

}  // namespace offsetmap
