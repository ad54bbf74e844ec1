// The offset pass: one method's program over the G-buffer, its precomputed data built on first use
// (through the method's registry row), the LOD footprint pre-pass.
#include "offsetmap/offset_pass.hpp"

#include <algorithm>
#include <sstream>

#include "launch.hpp"
#include "precompute/precompute.hpp"

namespace offsetmap {

void check_targets(const cl::Context& context, const OffsetTargets& t, size_t n) {
    check_buffer(context, t.uv,
                 {"the offset pass's uv output", "float2", sizeof(cl_float2), n, true});
    check_buffer(context, t.depth,
                 {"the offset pass's depth output", "float", sizeof(float), n, true, true});
    check_buffer(context, t.fetches,
                 {"the offset pass's fetches output", "uint", sizeof(cl_uint), n, true, true});
    check_buffer(context, t.flags,
                 {"the offset pass's flags output", "uint", sizeof(cl_uint), n, true, true});
}

OffsetVariant variant_writing(const OffsetTargets& t) {
    OffsetVariant v;
    v.depth = t.depth() != nullptr;
    v.fetches = t.fetches() != nullptr;
    v.flags = t.flags() != nullptr;
    return v;
}

OffsetVariant variant_writing_every_output() {
    OffsetVariant v;
    v.depth = v.fetches = v.flags = true;
    return v;
}

OffsetPass::OffsetPass(std::shared_ptr<Runtime> runtime, const std::string& method,
                       const std::map<std::string, std::string>& params)
    : OffsetPass(std::move(runtime), resolve_params(find_method(method), params)) {}

OffsetPass::OffsetPass(std::shared_ptr<Runtime> runtime, const MethodParams& params)
    : runtime_(std::move(runtime)), method_(params.method), params_(params) {
    if (!method_ || params_.values.size() != method_->params.size())
        throw Error("the offset pass needs resolved method parameters (resolve_params)");
    lanes_ = runtime_->lanes();
    groups_ = lane_groups(*method_, lanes_);
    // Compile now (the tools' usual outputs), so a method's build errors surface here.
    OffsetVariant usual = variant_writing_every_output();
    usual.images = runtime_->images();
    kernel(usual);
}

cl::Kernel& OffsetPass::kernel(OffsetVariant v) {
    // One program per combination actually used: each drops the branches it does not need.
    v.lanes = lanes_;
    const std::string defines = offset_program_defines(*method_, v);
    auto it = kernels_.find(defines);
    if (it == kernels_.end())
        it = kernels_
                 .emplace(defines, runtime_->kernel(
                                       runtime_->program(offset_program_files(*method_), defines),
                                       "om_offset"))
                 .first;
    return it->second;
}

void OffsetPass::prepare(const DeviceHeightField& f, const PassSettings& settings) {
    check_field(runtime_->context(), f);
    build_precomputed(f, settings);
}

void OffsetPass::build_precomputed(const DeviceHeightField& f, const PassSettings& settings) {
    const PrecomputeSpec* spec = method_->precompute;
    if (!spec) return;
    std::ostringstream detail;
    detail << f.width << 'x' << f.height << ' ' << settings.scale << ' '
           << static_cast<int>(settings.address);
    for (float p : params_.values) detail << ' ' << p;
    FieldKey key = field_key(f, detail.str());
    if (key == aux_key_) return;
    aux_key_ = FieldKey();
    precomputed_.bytes = spec->bytes(params_, settings, f.width, f.height);
    try {
        PrecomputeSpec::Built built = spec->build(*runtime_, f, settings, params_);
        aux_ = built.data;
        aux_events_ = built.events;
        // Submitted now: the caller's queue may be another, which would wait on them for ever
        // where the runtime's queue holds back unflushed work.
        runtime_->queue().flush();
    } catch (const cl::Error& e) {
        throw Error("cannot build the precomputed data of '" + method_->name + "' (" +
                    std::to_string(precomputed_.bytes) + " bytes): " + describe_cl_error(e.err()));
    }
    build_ms_known_ = false;
    aux_key_ = std::move(key);
}

const OffsetPass::Precomputed& OffsetPass::precomputed() const {
    if (!build_ms_known_) {
        precomputed_.build_ms = events_ms(*runtime_, aux_events_);
        build_ms_known_ = true;
    }
    return precomputed_;
}

const cl::Image1DBuffer& OffsetPass::heights_image(const DeviceHeightField& f) {
    if (image_of_() != f.heights()) {
        const size_t floats = f.heights.getInfo<CL_MEM_SIZE>() / sizeof(float);
        heights_image_ = floats <= runtime_->device().getInfo<CL_DEVICE_IMAGE_MAX_BUFFER_SIZE>()
                             ? cl::Image1DBuffer(runtime_->context(), CL_MEM_READ_ONLY,
                                                 cl::ImageFormat(CL_R, CL_FLOAT), floats, f.heights)
                             : cl::Image1DBuffer();
        image_of_ = f.heights;
    }
    return heights_image_;
}

cl::Buffer OffsetPass::footprint(const DeviceGBuffer& g, const DeviceHeightField& f,
                                 const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                                 cl::Event& done) {
    auto& rt = *runtime_;
    if (footprint_pixels_ != g.pixels()) {
        footprint_ = device_buffer(rt.context(), CL_MEM_READ_WRITE, g.pixels() * sizeof(float),
                                   "the LOD footprint levels");
        footprint_pixels_ = g.pixels();
    }
    if (!footprint_kernel_())
        footprint_kernel_ = rt.kernel(rt.program({"prep/footprint.cl"}), "om_footprint_lod");
    cl::Kernel& k = footprint_kernel_;
    set_args(k, g.uv, g.width, g.height, static_cast<float>(f.width), static_cast<float>(f.height),
             footprint_);
    enqueue_grid(queue, k, cl::NDRange(g.width, g.height), &wait, &done);
    return footprint_;
}

cl::Event OffsetPass::enqueue(const DeviceGBuffer& g, const DeviceHeightField& f,
                              const PassSettings& settings, const OffsetTargets& t,
                              const std::vector<cl::Event>& wait, const cl::CommandQueue& queue) {
    return launch(g, f, settings, t, wait, queue, false);
}

void OffsetPass::prepare(const DeviceGBuffer& g, const DeviceHeightField& f,
                         const PassSettings& settings, const OffsetTargets& t) {
    launch(g, f, settings, t, {}, cl::CommandQueue(), true).wait();
}

cl::Event OffsetPass::launch(const DeviceGBuffer& g, const DeviceHeightField& f,
                             const PassSettings& settings, const OffsetTargets& t,
                             const std::vector<cl::Event>& wait,
                             const cl::CommandQueue& queue_given, bool no_pixels) {
    validate(settings);
    const cl::Context& context = runtime_->context();
    const cl::CommandQueue& queue = pass_queue(*runtime_, queue_given);
    check_gbuffer(context, g);
    check_field(context, f);
    const size_t n = g.pixels();
    check_targets(context, t, n);
    build_precomputed(f, settings);
    // Over no pixels, the launch only makes the driver generate the kernel's code (PoCL does it at
    // a kernel's first launch): every work-item returns at once and nothing is written.
    OmOffsetParams p = no_pixels ? offset_params(settings, f.width, f.height)
                                 : offset_params(settings, f.width, f.height, g.width, g.height);
    p.mip_levels = f.mip_levels;
    p.packed_heights = packed_heights_offset(f);
    std::copy(params_.values.begin(), params_.values.end(), p.p);
    // The image path where the runtime wants it and the pyramid fits an image1d_buffer.
    const bool images = runtime_->images() && heights_image(f)() != nullptr;
    OffsetVariant variant = variant_writing(t);
    variant.images = images;
    variant.lod = settings.lod.enabled;
    variant.curved = g.curvature() != nullptr;
    variant.uv_metric = g.uv_metric() != nullptr;
    cl::Kernel& k = kernel(variant);
    k.setArg(0, p);
    k.setArg(1, g.uv);
    k.setArg(2, g.view);
    k.setArg(3, f.heights);
    set_optional(k, 4, aux_);
    k.setArg(6, t.uv);
    set_optional(k, 7, t.depth);
    set_optional(k, 8, t.fetches);
    set_optional(k, 9, t.flags);
    set_optional(k, 10, g.curvature);
    set_optional(k, 11, g.uv_metric);
    if (images) k.setArg(12, heights_image(f));
    cl::Event event;
    try {
        // The caller's events, the field's upload and the precomputed data's build.
        std::vector<cl::Event> deps = wait;
        const std::vector<cl::Event> ready = field_ready(f);
        deps.insert(deps.end(), ready.begin(), ready.end());
        deps.insert(deps.end(), aux_events_.begin(), aux_events_.end());
        cl::Buffer lod;
        if (settings.lod.enabled) {
            if (g.lod()) {
                lod = g.lod;
            } else {
                cl::Event levels;
                lod = footprint(g, f, wait, queue, levels);
                deps.push_back(levels);
            }
        }
        set_optional(k, 5, lod);
        const cl::NDRange global =
            no_pixels
                ? cl::NDRange(kLocalSize)
                : padded((om_image_blocks(g.width, g.height, lanes_) + groups_ - 1) / groups_);
        queue.enqueueNDRangeKernel(k, cl::NullRange, global, cl::NDRange(kLocalSize), &deps,
                                   &event);
    } catch (const cl::Error& e) {
        throw Error("cannot run the '" + method_->name +
                    "' offset pass: " + describe_cl_error(e.err()));
    }
    return event;
}

}  // namespace offsetmap
