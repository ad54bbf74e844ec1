// The shade kernels' parameters, for the shade pass and the material frame's slots.
#pragma once
#include "offsetmap/settings.hpp"
#include "offsetmap/shade_pass.hpp"

namespace offsetmap {

// Everything but the G-buffer's size and has_light, over a map_w x map_h relief; throws
// Error for shadow steps or a light size out of range.
OmShadeParams shade_params(const PassSettings& settings, const ShadeSettings& shade, int map_w,
                           int map_h, const DeviceImage* albedo);

// The checks of a shade pass's uv input, optional flags and colour output for n pixels.
void check_shade_buffers(const cl::Context& context, const cl::Buffer& uv, const cl::Buffer& flags,
                         const cl::Buffer& out_rgba, size_t n);
// The optional shadow mask (read) and visibility (written), float per pixel.
void check_shadow_buffers(const cl::Context& context, const cl::Buffer& mask,
                          const cl::Buffer& visibility, size_t n);

// The shade program's kernel `name` (kernels/shade.cl) at the runtime's lanes, and the grid of
// its blocks over a width x height G-buffer.
cl::Kernel shade_kernel(Runtime& runtime, const std::string& name);
cl::NDRange shade_grid(int lanes, int width, int height);

}  // namespace offsetmap
