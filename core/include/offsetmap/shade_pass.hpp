// The shade pass: lights uv' with the relief's normals (and self-shadows), whatever method made it.
#pragma once
#include <memory>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/height_field.hpp"
#include "offsetmap/offset_pass.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/settings.hpp"

namespace offsetmap {

struct ShadeSettings {
    float light[3] = {0.55f, 0.35f, 0.76f};  // tangent-space L when the G-buffer has none
    float ambient = 0.22f;
    float diffuse = 0.85f;
    float specular = 0.25f;
    float shininess = 40.0f;
    ShadowMode shadow = ShadowMode::None;  // self-shadows of the relief
    int shadow_steps = 16;                 // samples along the light ray, [1, 256]
    float light_size_deg = 8.0f;           // soft shadows: the light's angular diameter
};

// An albedo texture on the device (float4 texels, linear RGB).
struct DeviceImage {
    int width = 0;
    int height = 0;
    cl::Buffer texels;
};

DeviceImage upload(Runtime& runtime, const Image4& image);

// What the shade pass reads besides the G-buffer and the field: an offset pass's outputs and the
// albedo.
struct ShadeInputs {
    cl::Buffer uv;                        // float2 per pixel, uv' (OffsetTargets::uv)
    cl::Buffer flags;                     // uint per pixel (OffsetTargets::flags), or null
    const DeviceImage* albedo = nullptr;  // null: a neutral procedural checker
    // float per pixel, rows as the G-buffer's: the lit fraction a shadow map's test gave each
    // pixel (ShadowMaskPass), or null. With one, the diffuse term takes the smaller of
    // it and the self-shadow march, and the specular term is scaled by it; without one the
    // shading is as it was, bit for bit.
    cl::Buffer shadow_mask{};
};
// An offset pass's targets as the shade pass's inputs.
inline ShadeInputs shade_inputs(const OffsetTargets& offsets, const DeviceImage* albedo = nullptr) {
    return {offsets.uv, offsets.flags, albedo};
}

// What it writes.
struct ShadeTargets {
    cl::Buffer rgba;  // float4 per pixel, linear RGBA (alpha 0 where the pixel is empty)
    // Optional, float per pixel: the light's visibility the diffuse term was scaled by (the
    // march's, the shadow map's or the smaller; 1 unshadowed, 0 where no surface or no light).
    cl::Buffer visibility{};
};

// Blinn-Phong at uv' with the field's normals (and the relief's self-shadows). Knows nothing of
// the method that produced uv'. Enqueues on `queue` (the runtime's when null) after `wait`.
class ShadePass {
  public:
    explicit ShadePass(std::shared_ptr<Runtime> runtime);

    cl::Event enqueue(const DeviceGBuffer& gbuffer, const DeviceHeightField& field,
                      const ShadeInputs& inputs, const PassSettings& settings,
                      const ShadeSettings& shade, const ShadeTargets& targets,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

  private:
    std::shared_ptr<Runtime> runtime_;
    int lanes_ = 1;  // the kernel's, from the runtime when it was built
    cl::Kernel kernel_;
};

}  // namespace offsetmap
