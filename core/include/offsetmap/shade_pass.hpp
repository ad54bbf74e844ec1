// The shade pass: lights uv' with the relief's normals (and self-shadows), whatever method made it.
#pragma once
#include <memory>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/height_field.hpp"
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

// Blinn-Phong at uv' with the field's normals; writes linear RGBA float4 per pixel (alpha 0 where
// the pixel is empty). Knows nothing of the method that produced uv'. Enqueues on `queue` (the
// runtime's when null) after `wait`.
class ShadePass {
  public:
    explicit ShadePass(std::shared_ptr<Runtime> runtime);

    cl::Event enqueue(const cl::Buffer& uv, const cl::Buffer& flags, const DeviceGBuffer& gbuffer,
                      const DeviceHeightField& field, const DeviceImage* albedo,
                      const PassSettings& settings, const ShadeSettings& shade,
                      const cl::Buffer& out_rgba, const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

  private:
    std::shared_ptr<Runtime> runtime_;
    int lanes_ = 1;  // the kernel's, from the runtime when it was built
    cl::Kernel kernel_;
};

}  // namespace offsetmap
