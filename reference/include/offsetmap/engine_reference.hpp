// An engine's G-buffer as the engine writes it (depth, camera, tangent frame, uv; float, half,
// snorm16, unorm16 or unorm8; buffers or images) and the reconstruct pass's result in double
// precision from the stored values, with the per-pixel bound a float reconstruction stays within
// (the forward error analysis in engine_reference.cpp). The tests and the device check hold the
// reconstruct pass to it.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/scenes.hpp"

namespace offsetmap::engine_ref {

// IEEE half's bits of x, rounded to nearest even (overflow to infinity, NaN kept), and back.
std::uint16_t half_bits(float x);
float half_value(std::uint16_t bits);

// Values per pixel as floats before storage, and how the engine stores them.
struct Plane {
    int values = 1;
    std::vector<float> v;  // pixels * values
    Storage storage = Storage::Float;
    bool image = false;
};
Plane with_values(int values);

// The value the device reads back from `x` stored as `s` (exact for float and half; the unorm and
// snorm forms are the nearest code, decoded here in double: the device's division may differ from
// it by its rounding, which decode_error carries).
double stored_value(float x, Storage s);
// Relative error of the device's decoding of one stored value.
double decode_error(Storage s);
// The plane's bytes as the engine writes them.
std::vector<unsigned char> encode(const Plane& p);

// Whether the context's device reads an image of the plane's format (rusticl over llvmpipe has
// no CL_RGBA / CL_SNORM_INT16).
bool device_has_image_format(const cl::Context& context, const Plane& p);
Input to_device(const cl::Context& context, const Plane& p, int width, int height);

// An engine's frame: its planes as floats before storage, and how each is stored.
struct EngineFrame {
    int width = 0, height = 0;
    EngineCamera camera;
    Plane depth = with_values(1), normal = with_values(4), tangent = with_values(4),
          uv = with_values(2);
    FrameForm form = FrameForm::NormalTangent;

    EngineGBuffer to_device(const cl::Context& context) const;
    size_t pixels() const { return static_cast<size_t>(width) * height; }
};

// The plane scene as the library's engine scene writes it.
EngineFrame plane_frame(const PlaneScene& scene, DepthConvention depth, FirstRow first_row);

// Random tangent frames on the frame's pixels: unnormalised, the tangent leaning toward the
// normal, half of them mirrored (or quaternions of random length and sign carrying it).
void randomise_frames(EngineFrame& f, FrameForm form, std::uint64_t seed);

// How an engine writes its frame: the tangent frame's form, the depth convention, the row order,
// each plane's storage, buffers or images, and its light.
struct Encoding {
    const char* name;
    FrameForm form;
    DepthConvention projection;
    FirstRow first_row;
    Storage depth, frame, uv;
    bool images;
    EngineLight light;
};
// The plane scene written with the encoding, its tangent frames randomised from `seed`.
EngineFrame encoded_frame(const PlaneScene& scene, const Encoding& e, std::uint64_t seed);
// Whether the context's device reads every image plane of the frame.
bool device_reads_images(const cl::Context& context, const EngineFrame& f);

// Pixel k's tangent-space V (and L) in double from the stored values, and the bound on each
// component a float reconstruction keeps to.
struct Reference {
    bool sky = false;
    std::array<double, 3> v_ts{}, l_ts{};
    double bound = 0.0;    // on each component of V
    double l_bound = 0.0;  // on each component of L
    // A spot light: the light plane's w (the cone's share of the light's absence), and the
    // largest rate of w per unit of the cosine it is taken of (1.5 over the cone's span).
    double cone_dark = 0.0, cone_slope = 0.0;
};
Reference reference(const EngineFrame& f, size_t k, const EngineLight& light);

// The reconstruct pass's outputs read back.
struct Decoded {
    std::vector<cl_float2> uv;
    std::vector<cl_float4> view, light;
};
Decoded reconstruct(const std::shared_ptr<Runtime>& runtime, const EngineGBuffer& in, bool light);

}  // namespace offsetmap::engine_ref
