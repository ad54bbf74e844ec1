// The offset pass: one method over a G-buffer, on the runtime's context and queue.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/height_field.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/settings.hpp"

namespace offsetmap {

// Output buffers of the offset pass. uv (float2 per pixel) is required; depth (float: the ray
// parameter t of the hit, the distance along the eye ray from the polygon point in uv units),
// fetches (uint: bilinear height fetches) and flags (uint, OM_FLAG_*) may be null buffers.
struct OffsetTargets {
    cl::Buffer uv;
    cl::Buffer depth;
    cl::Buffer fetches;
    cl::Buffer flags;
};

// Throws Error naming the target that is missing, too small, read-only or of another context, for
// a G-buffer of n pixels.
void check_targets(const cl::Context& context, const OffsetTargets& targets, size_t n);

// The program variant that writes the targets bound (OM_OUT_*), the rest left at their defaults;
// and the one the passes compile up front, writing all three (the tools' usual outputs).
OffsetVariant variant_writing(const OffsetTargets& targets);
OffsetVariant variant_writing_every_output();

// One method's offset pass. Enqueues on `queue` (any queue of the runtime's context; the runtime's
// own when null) after `wait`, and returns the kernel's event. One runtime serves any number of
// queues: programs are built once per runtime. A pass object keeps its kernels' arguments, so
// each thread that enqueues uses its own OffsetPass.
class OffsetPass {
  public:
    // The method by name with parameter overrides (name -> text), resolved here; or with
    // parameters already resolved (resolve_params).
    OffsetPass(std::shared_ptr<Runtime> runtime, const std::string& method,
               const std::map<std::string, std::string>& params = {});
    OffsetPass(std::shared_ptr<Runtime> runtime, const MethodParams& params);

    cl::Event enqueue(const DeviceGBuffer& gbuffer, const DeviceHeightField& field,
                      const PassSettings& settings, const OffsetTargets& targets,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());

    // Everything the first enqueue of this shape (settings, which outputs are bound, the field)
    // would otherwise do itself, done now and waited for: the program variant, the driver's code
    // for it (a launch over no pixels), the footprint pre-pass and the precomputed data. A frame
    // enqueued after it compiles nothing (tested).
    void prepare(const DeviceGBuffer& gbuffer, const DeviceHeightField& field,
                 const PassSettings& settings, const OffsetTargets& targets);

    const MethodInfo& method() const { return *method_; }
    const MethodParams& params() const { return params_; }
    int lanes() const { return lanes_; }  // pixels per group of lanes
    // Pixels per work-item: two groups of lanes for a method with lane pairs, else one. A group is
    // a block of the image, 4 x 4 pixels for 16 lanes (OM_BLOCK_W, OM_BLOCK_H).
    int pixels_per_item() const { return lanes_ * groups_; }

    // The method's precomputed data for the last field it ran on (bytes 0 when it needs none),
    // and the kernel time its build took (from profiling events: 0 without a profiling queue;
    // asking waits for the build).
    struct Precomputed {
        size_t bytes = 0;
        double build_ms = 0.0;
    };
    const Precomputed& precomputed() const;
    // The precomputed data itself on the device (layout in the method's prep kernel file).
    const cl::Buffer& precomputed_buffer() const { return aux_; }

    // Enqueues the precomputed data's build for `field` now (enqueue does it on first use), after
    // the field's `ready` event; the next enqueue waits for it. It is kept for the field's
    // generation (its version: every upload, update() and mark_changed() gives a new one), its
    // heights buffer (held until the pass meets another field), size, scale, address mode and
    // parameters, and rebuilt by the first enqueue after any of them changes.
    void prepare(const DeviceHeightField& field, const PassSettings& settings);

  private:
    // prepare(field, settings) without the field's check (launch has made it).
    void build_precomputed(const DeviceHeightField& f, const PassSettings& settings);
    cl::Event launch(const DeviceGBuffer& g, const DeviceHeightField& f,
                     const PassSettings& settings, const OffsetTargets& t,
                     const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                     bool no_pixels);
    // Enqueues the footprint pre-pass on `queue` after `wait`; `done` becomes its event.
    cl::Buffer footprint(const DeviceGBuffer& g, const DeviceHeightField& f,
                         const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                         cl::Event& done);

    // The entry kernel built as `variant` asks, at the runtime's lanes.
    cl::Kernel& kernel(OffsetVariant variant);
    // An image1d_buffer view of the field's height pyramid (the image path), made once per field;
    // a null image when the pyramid is larger than the device's image buffers allow.
    const cl::Image1DBuffer& heights_image(const DeviceHeightField& f);

    std::shared_ptr<Runtime> runtime_;
    const MethodInfo* method_;
    MethodParams params_;
    std::map<std::string, cl::Kernel> kernels_;
    int lanes_ = 1;   // pixels per group of lanes (the runtime's)
    int groups_ = 1;  // groups of lanes per work-item
    // Derived from the last field, each with what it was made from: the key of a cache holds
    // the buffer it names, so that its handle cannot be recycled while the cache lives.
    cl::Image1DBuffer heights_image_;
    cl::Buffer image_of_;  // the height buffer heights_image_ views (its contents may change)
    cl::Buffer aux_;
    std::vector<cl::Event> aux_events_;  // aux_ is complete when these are
    FieldKey aux_key_;                   // what aux_ was built for
    cl::Buffer footprint_;               // per-pixel mip levels when the G-buffer brings none
    cl::Kernel footprint_kernel_;        // created on first use, reused every frame
    size_t footprint_pixels_ = 0;
    mutable Precomputed precomputed_;
    mutable bool build_ms_known_ = true;
};

}  // namespace offsetmap
