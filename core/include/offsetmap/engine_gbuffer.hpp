// The G-buffer as engines write it (depth, camera, tangent frame, uv; buffers or images, float,
// half or snorm16) and the pass that reconstructs from it, on the device, the explicit G-buffer the
// offset and shade passes read (tangent-space V and L per pixel).
#pragma once
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/input.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/shared.h"
#include "offsetmap/triplanar.hpp"

namespace offsetmap {

// Window depth d as the depth buffer holds it: GL, NDC z = 2d - 1 (far plane d = 1); zero-one,
// NDC z = d (D3D, Vulkan, GL with glClipControl; far d = 1); reversed, NDC z = d with the far plane
// at d = 0 (infinite far planes included).
enum class DepthConvention : om_int {
    GL = OM_DEPTH_GL,
    ZeroToOne = OM_DEPTH_ZERO_ONE,
    Reversed = OM_DEPTH_REVERSED
};

// Which NDC y pixel row 0 sits at: the top (+1; D3D) or the bottom (-1; GL's framebuffer rows,
// Vulkan).
enum class FirstRow : om_int { Top = 1, Bottom = -1 };

struct EngineCamera {
    // NDC -> world, column-major (GLM's and GL's layout): row r, column c at [4 c + r].
    std::array<float, 16> inverse_view_projection = {1, 0, 0, 0, 0, 1, 0, 0,
                                                     0, 0, 1, 0, 0, 0, 0, 1};
    std::array<float, 3> eye = {0, 0, 0};  // world position
    // An orthographic view (a directional light's, for a shadow map): every pixel's view is the
    // one direction `eye`, toward the viewer (any length but zero).
    bool orthographic = false;
    DepthConvention depth = DepthConvention::ZeroToOne;
    FirstRow first_row = FirstRow::Top;
};

// The tangent frame's form. NormalTangent: world normal (xyz; w unused) and tangent (xyz along
// +u; w the handedness: w < 0 gives B = -N x T). Quaternion: the unit quaternion (x, y, z, w)
// rotating tangent space (T, B, N columns) into the world; q and -q are the same rotation, so
// w < 0 marks a mirrored frame (B = -N x T), and writers keep |w| at least one step of their
// storage for mirrored frames.
enum class FrameForm : om_int {
    NormalTangent = OM_FRAME_NORMAL_TANGENT,
    Quaternion = OM_FRAME_QUATERNION
};

enum class LightKind : om_int {
    None = OM_LIGHT_NONE,
    Directional = OM_LIGHT_DIRECTIONAL,  // vector: world direction toward the light
    Point = OM_LIGHT_POINT,              // vector: world position of the light
    Spot = OM_LIGHT_SPOT                 // vector: world position; axis and cone below
};

struct EngineLight {
    LightKind kind = LightKind::None;
    std::array<float, 3> vector = {0, 0, 1};
    // A spot light: the world direction it shines along (any length but zero), and the cone's
    // half-angles in radians: whole within cone_inner of the axis, fading smoothly (smoothstep
    // of the angle's cosine) to nothing at cone_outer; 0 <= inner <= outer < pi / 2. The
    // reconstruct pass writes the cone's share of the light's absence in the light plane's w
    // (0 whole, 1 none: 0 for every other kind), and the shade passes dim the light by it.
    std::array<float, 3> axis = {0, 0, -1};
    float cone_inner = 0.0f, cone_outer = 0.0f;
};

// A rectangle of pixels, its first row and column counted as the G-buffer stores them.
struct PixelRegion {
    int x = 0, y = 0, width = 0, height = 0;
};

// The engine's G-buffer: per pixel depth (1 value), tangent frame (4 values each input) and uv
// (2 values), with the camera that rendered it and the light. World units are the engine's.
struct EngineGBuffer {
    int width = 0;
    int height = 0;
    EngineCamera camera;
    Input depth;
    FrameForm frame = FrameForm::NormalTangent;
    Input normal;   // NormalTangent; for Quaternion, the quaternion
    Input tangent;  // NormalTangent only
    Input uv;
    EngineLight light;
    // Optional: reconstruct only these rectangles (rows as stored), for a layer the engine drew
    // only at some pixels; the rest of the output then holds what its unread input gives (lanes
    // and work-groups round each rectangle out). Empty: every pixel.
    std::vector<PixelRegion> regions;

    size_t pixels() const { return static_cast<size_t>(width) * height; }
};

// Device buffers for an explicit G-buffer of width x height (light and lod when asked), readable
// and writable: the reconstruct pass's output, the offset and shade passes' input.
DeviceGBuffer allocate_gbuffer(Runtime& runtime, int width, int height, bool light, bool lod);

// The reconstruction's program (kernels/gbuffer/reconstruct.cl) and its build for one combination
// of inputs: each of depth, frame (normal or quaternion), tangent and uv read from an image
// (kImageInput), from a buffer of OM_STORAGE_* `inputs[k]` values, or (kNoInput) not at all; the
// tangent is never read in the quaternion form.
constexpr int kImageInput = -1, kNoInput = -2;
std::vector<std::string> reconstruct_program_files();
// With `triplanar`, the variant that also splits triplanar pixels into their projections; there
// uv and the tangent may be kNoInput.
std::string reconstruct_program_defines(int lanes, const std::array<int, 4>& inputs,
                                        bool quaternion, LightKind light, bool triplanar = false);

// Reconstructs `out` (uv, view and, with a light, light) from the engine's G-buffer. Sky (depth
// at the far plane) becomes an empty pixel (NaN uv); a degenerate frame or a depth that is not
// finite a NaN V, which the offset pass flags INVALID, passing uv through.
class ReconstructPass {
  public:
    explicit ReconstructPass(std::shared_ptr<Runtime> runtime);

    // Enqueues on `queue` (the runtime's when null) after `wait`; returns the kernel's event.
    // Throws Error naming the input whose buffer or image has the wrong size, type, format or
    // context, before anything is enqueued.
    cl::Event enqueue(const EngineGBuffer& in, const DeviceGBuffer& out,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

    // The same over a frame with triplanar materials (offsetmap/triplanar.hpp): `out.material`
    // (the pixels' ids, read) and `table` (MaterialFrame::triplanar_table) say which pixels are
    // triplanar. They take their dominant projection's frame, uv, V and L; `planes` the other two
    // projections where they weigh, and every pixel's weights, projections and normal. uv and the
    // tangent may be unbound (the other pixels then get an empty uv, or an invalid frame). Throws
    // Error naming the material and the plane when the depth or the normal is missing.
    cl::Event enqueue(const EngineGBuffer& in, const DeviceGBuffer& out,
                      const TriplanarTable& table, const TriplanarPlanes& planes,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

    // Checks the inputs, builds the program for this combination of buffers and images and the
    // driver's code for it (a launch over no pixels), and waits: the first enqueue compiles
    // nothing.
    void prepare(const EngineGBuffer& in, const DeviceGBuffer& out);

  private:
    cl::Kernel& kernel(const EngineGBuffer& in, bool triplanar);
    cl::Event launch(const EngineGBuffer& in, const DeviceGBuffer& out,
                     const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                     bool no_pixels, const TriplanarTable* table = nullptr,
                     const TriplanarPlanes* planes = nullptr);

    std::shared_ptr<Runtime> runtime_;
    std::map<std::string, cl::Kernel> kernels_;
};

}  // namespace offsetmap
