// The device check (offsetmap_check): what each OpenCL device offers and what the passes choose
// there, every kernel against its CPU reference on maps and views it makes itself, and each
// method's speed beside the device's fetch roofline. The core, the reference and the C++ peer
// alone: it builds and runs where only an OpenCL driver is installed (docs/integrating.md,
// "Checking your device").
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/offsetmap.hpp"
#include "offsetmap/scenes.hpp"

namespace offsetmap::check {

struct Options {
    bool quick = false;                // smaller cases and timing frames (CI's run)
    bool timing = true;                // --no-timing: correctness alone
    std::vector<std::string> devices;  // platform/device substrings; empty: every device
    std::vector<std::string> methods;  // empty: every method
    std::string json;                  // write the report here ("" none)
};

// A value of the device's description: text, or a number written as such in the JSON.
struct Fact {
    std::string key, value;
    bool number = false;
};

// One checked case: a kernel on one input against its reference.
struct CaseResult {
    std::string kernel;  // the method or pass
    std::string name;    // the case: map, storage, address mode, views
    size_t pixels = 0;   // pixels compared
    bool passed = true;
    std::string measure;  // what `worst` is ("share of bound", "texels from the C++ peer", ...)
    double worst = 0.0;
    std::string worst_pixel;  // "(x, y): what it got and what was expected"
    std::string note;         // a line of context (error against the oracle, ...)
};

struct MethodTime {
    std::string method;
    double camera_ns = 0, random_ns = 0;  // per pixel
    double camera_fetches = 0, random_fetches = 0;
};

struct Roofline {
    double passthrough_ns = 0;  // the G-buffer in and uv' out, no work, per pixel
    double chain_ns = 0;        // per dependent bilinear fetch (32 a pixel)
    double line_ns = 0;         // per independent fetch along a line (32 a pixel)
};

struct DeviceReport {
    std::string name;  // "platform / device"
    std::vector<Fact> facts;
    std::vector<CaseResult> cases;
    std::string timing_frame;  // "1920x1080", the map's size
    std::vector<MethodTime> times;
    Roofline roof;
    std::vector<std::string> failures;  // one line each
};

std::vector<Fact> describe_device(const Runtime& runtime);

// A relief the check makes itself, as the passes read it (rounded to 16 bits where kept as words).
struct MapCase {
    std::string name;  // relief, size, address mode, storage, s and r
    HeightMap map;
    PassSettings settings;
};
// Power-of-two, odd and other sizes; wrap and clamp; floats and unorm16 words (two with `quick`).
std::vector<MapCase> map_cases(bool quick);
// Views over the tile down to grazing ones, and a row with an empty, a back-facing and a zero view.
GBuffer case_views(bool quick);
// A texel's hash in [0, 1): inputs without files, the same on every machine.
float hashed(std::uint64_t seed, int i, int j);

// Every selected method on the check's maps and views: the exact walks against the double oracle
// within the per-ray float bound, the others against the C++ peer (the same kernel compiled as
// C++) to 1e-3 texel except where the kernel itself jumps; flags and fetch caps too.
void check_methods(const std::shared_ptr<Runtime>& runtime, const Options& options,
                   DeviceReport& report);
// A material frame of three materials with id 0 and empty pixels: every pixel its material's pass
// alone, bit for bit.
void check_material_frame(const std::shared_ptr<Runtime>& runtime, const Options& options,
                          DeviceReport& report);
// The shade pass (lit, hard and soft self-shadows, albedo or checker, global or per-pixel light)
// over each map's relief against the shade kernel compiled as C++, off its discontinuities.
void check_shade(const std::shared_ptr<Runtime>& runtime, const Options& options,
                 DeviceReport& report);
// The reconstruct pass over engine G-buffer forms (both frame forms, every depth convention and
// storage, buffers and images, lights) against the double reference within its float bound.
void check_reconstruct(const std::shared_ptr<Runtime>& runtime, const Options& options,
                       DeviceReport& report);
// Each method's time at 1080p (a camera view and random rays) and the fetch roofline.
void time_methods(const std::shared_ptr<Runtime>& runtime, const Options& options,
                  DeviceReport& report);

// The cases a report holds as a failure line each (device, kernel, case, worst pixel).
void collect_failures(DeviceReport& report);
void print_report(const DeviceReport& report);
std::string report_json(const std::vector<DeviceReport>& reports, const Options& options);

// Pixel k of a width-wide frame as "(x, y)".
std::string pixel_name(size_t k, int width);

}  // namespace offsetmap::check
