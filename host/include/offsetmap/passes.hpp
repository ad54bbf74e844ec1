#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/runtime.hpp"
#include "om_shared.h"

namespace offsetmap {

// Tatarchuk's level-of-detail system (off by default). The per-pixel mip level m comes from the
// G-buffer's lod buffer, or from the uv footprint between neighbouring pixels when it has none.
// Heights are read at level floor(m), step counts scale by mix(1, min_detail, m / threshold), and
// the offset fades to plain normal mapping over `fade` levels below `threshold`.
// Footprint mode (footprint = true) keeps the per-pixel level and the height reads but caps each
// method's step count at the texels of that level the ray's footprint crosses (plus one) and fades
// to normal mapping as that count falls from fade_texels_hi to fade_texels_lo.
struct LodSettings {
    bool enabled = false;
    float threshold = 4.0f;    // mip level at and past which uv' = uv, [0.5, 16]
    float fade = 1.0f;         // (0, threshold]
    float min_detail = 0.25f;  // (0, 1]
    bool footprint = false;
    float fade_texels_lo = 0.5f;  // [0, fade_texels_hi)
    float fade_texels_hi = 2.0f;
};

// The relief's placement (DESIGN.md): surface z = scale * (H - reference_plane), in uv units.
struct PassSettings {
    float scale = 0.05f;             // depth scale s, in uv units, [0, 1]
    float reference_plane = 1.0f;    // r in [0,1]: the polygon's height
    float min_elevation_deg = 1.0f;  // grazing rule: views lower than this are raised to it
    AddressMode address = AddressMode::Wrap;
    LodSettings lod;
    // What happens at grazing views (GrazingPolicy, om_shared.h; bounded loops, finite outputs):
    //  Clamp: views below min_elevation_deg are traced at that elevation (the default).
    //  Limit: Welsh's offset limiting for every method: rays along normalize(V.x, V.y, 1), so an
    //         offset never exceeds the depth it crosses (biased at every view but straight down).
    //  Cap:   a march-length cap: the ray's footprint through the whole slab is at most
    //         max_offset_texels, i.e. views are raised to atan(s max(W, H) / max_offset_texels).
    GrazingPolicy grazing = GrazingPolicy::Clamp;
    float max_offset_texels = 32.0f;  // Cap policy: longest footprint of a ray, [1, 1e6]
    // Flag pixels whose uv' leaves [0,1]^2 (OM_FLAG_OUT_OF_TILE), for silhouettes on non-tiling
    // (clamped) surfaces; the shade pass draws them as background.
    bool out_of_tile_mask = false;
};

// Throws Error naming the setting that is out of range.
void validate(const PassSettings& settings);

// The grazing rule and the march cap, derived once (host/src/grazing.cpp) for the offset pass, the
// shade pass (the light obeys the view's rule), the oracle and the tests.
struct GrazingRule {
    // Views with a lower V.z are flagged GRAZING and, but under Limit, raised to it (same
    // azimuth). sin(min_elevation_deg), raised by the Cap policy so that a footprint through the
    // whole slab spans at most max_offset_texels. A float, as the kernels compare it.
    float min_vz = 0.0f;
    bool limit = false;  // Limit policy: rays along normalize(V.x, V.y, 1)
    // The most cells a ray's footprint crosses between the top and bottom planes (it spans at
    // most s / min_vz in uv), plus the start cell and rounding: every cell walk's hard cap.
    int max_cells = 0;
};
GrazingRule grazing_rule(const PassSettings& settings, int map_w, int map_h);

// The kernel parameters a pass with these settings uses over a hf_w x hf_h height map (grazing
// rule, march cap, LOD); method parameters and mip levels are the caller's to fill in.
OmOffsetParams offset_params(const PassSettings& settings, int pixels, int hf_w, int hf_h);

// Uploads heights and derives normals on the device (or takes `normal_map` when given).
DeviceHeightField upload(Runtime& runtime, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map = nullptr);

// Output buffers of the offset pass. uv (float2 per pixel) is required; depth (float: the ray
// parameter t of the hit, the distance along the eye ray from the polygon point in uv units),
// fetches (uint: bilinear height fetches) and flags (uint, OM_FLAG_*) may be null buffers.
struct OffsetTargets {
    cl::Buffer uv;
    cl::Buffer depth;
    cl::Buffer fetches;
    cl::Buffer flags;
};

// One method's offset pass. Enqueues on the runtime's queue (the caller's, when the runtime wraps
// the caller's objects) after `wait`, and returns the kernel's event.
class OffsetPass {
  public:
    OffsetPass(std::shared_ptr<Runtime> runtime, const std::string& method,
               const std::map<std::string, std::string>& params = {});

    cl::Event enqueue(const DeviceGBuffer& gbuffer, const DeviceHeightField& field,
                      const PassSettings& settings, const OffsetTargets& targets,
                      const std::vector<cl::Event>& wait = {});

    const MethodInfo& method() const { return *method_; }
    const std::vector<float>& params() const { return params_; }
    int lanes() const { return lanes_; }  // pixels per work-item

    // The method's precomputed data for the last field it ran on (bytes 0 when it needs none),
    // and the time its build took (kernel time from profiling events, else wall time).
    struct Precomputed {
        size_t bytes = 0;
        double build_ms = 0.0;
    };
    const Precomputed& precomputed() const { return precomputed_; }
    // The precomputed data itself on the device (layout in the method's prep kernel file).
    const cl::Buffer& precomputed_buffer() const { return aux_; }

    // Builds the precomputed data for `field` now (enqueue does it on first use). It is cached by
    // the height buffer, size, scale, address mode and parameters: after rewriting the heights in
    // the same buffer, use a new OffsetPass.
    void prepare(const DeviceHeightField& field, const PassSettings& settings);

  private:
    // Build the method's precomputed data into aux_; return kernel milliseconds (profiling).
    double build_distance_map(const DeviceHeightField& f, const PassSettings& settings);
    double build_max_pyramid(const DeviceHeightField& f, const PassSettings& settings);
    double build_cone_map(const DeviceHeightField& f, const PassSettings& settings);

    // Enqueues the footprint pre-pass after `wait`; `deps` becomes its event.
    cl::Buffer footprint(const DeviceGBuffer& g, const DeviceHeightField& f,
                         const std::vector<cl::Event>& wait, std::vector<cl::Event>& deps);

    // The entry kernel specialised for LOD on/off and the optional outputs bound.
    cl::Kernel& kernel(bool lod, bool depth, bool fetches, bool flags, bool images);
    // An image1d_buffer view of the field's height pyramid (the image path), made once per field;
    // a null image when the pyramid is larger than the device's image buffers allow.
    const cl::Image1DBuffer& heights_image(const DeviceHeightField& f);

    std::shared_ptr<Runtime> runtime_;
    const MethodInfo* method_;
    std::vector<float> params_;
    std::map<std::string, cl::Kernel> kernels_;
    int lanes_ = 1;  // pixels per work-item (the runtime's)
    cl::Image1DBuffer heights_image_;
    cl_mem image_of_ = nullptr;  // the height buffer heights_image_ views
    cl::Buffer aux_;
    std::string aux_key_;          // what aux_ was built for
    cl::Buffer footprint_;         // per-pixel mip levels when the G-buffer brings none
    cl::Kernel footprint_kernel_;  // created on first use, reused every frame
    size_t footprint_pixels_ = 0;
    Precomputed precomputed_;
};

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
// the pixel is empty). Knows nothing of the method that produced uv'.
class ShadePass {
  public:
    explicit ShadePass(std::shared_ptr<Runtime> runtime);

    cl::Event enqueue(const cl::Buffer& uv, const cl::Buffer& flags, const DeviceGBuffer& gbuffer,
                      const DeviceHeightField& field, const DeviceImage* albedo,
                      const PassSettings& settings, const ShadeSettings& shade,
                      const cl::Buffer& out_rgba, const std::vector<cl::Event>& wait = {});

  private:
    std::shared_ptr<Runtime> runtime_;
    cl::Kernel kernel_;
};

}  // namespace offsetmap
