// The material frame's layer behind: the first layer's see-behind pixels traced on the second
// layer, its results and planes taken where it shows a surface.
#include <algorithm>

#include "launch.hpp"
#include "offsetmap/material_frame.hpp"

namespace offsetmap {

const cl::CommandQueue& MaterialFrame::check_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                                    const LayerBehind& behind,
                                                    const cl::CommandQueue& queue_given) {
    if (triplanar_table_.any)
        throw Error("the layer behind does not trace triplanar materials: " +
                    triplanar_table_.name + " is one");
    const cl::Context& context = runtime_->context();
    const cl::CommandQueue& queue = checked_queue(g, queue_given);
    const DeviceGBuffer& b = behind.gbuffer;
    const size_t n = g.pixels();
    if (b.width != g.width || b.height != g.height)
        throw Error("the layer behind is " + std::to_string(b.width) + "x" +
                    std::to_string(b.height) + "; the G-buffer is " + std::to_string(g.width) +
                    "x" + std::to_string(g.height));
    if (!t.flags()) throw Error("a frame with a layer behind needs the offset pass's flags output");
    checked_queue(b, queue);
    check_targets(context, behind.targets, n);
    if (!behind.targets.depth() || !behind.targets.fetches() || !behind.targets.flags())
        throw Error("the layer behind's targets need every output (uv, depth, fetches, flags)");
    // Read back here as well as written: none may be write-only.
    check_buffer(context, t.flags, {"the offset pass's flags output", "uint", sizeof(cl_uint), n});
    check_buffer(context, behind.targets.uv,
                 {"the layer behind's uv output", "float2", sizeof(cl_float2), n});
    check_buffer(context, behind.targets.depth,
                 {"the layer behind's depth output", "float", sizeof(float), n});
    check_buffer(context, behind.targets.fetches,
                 {"the layer behind's fetches output", "uint", sizeof(cl_uint), n});
    check_buffer(context, behind.targets.flags,
                 {"the layer behind's flags output", "uint", sizeof(cl_uint), n});
    if (static_cast<bool>(g.light()) != static_cast<bool>(b.light()) ||
        static_cast<bool>(g.lod()) != static_cast<bool>(b.lod()))
        throw Error("the layer behind must carry the same planes (light, lod) as the G-buffer");
    // The first layer's planes its pixels that show the second take from it.
    const struct {
        const cl::Buffer& plane;
        const char* name;
        size_t bytes;
    } taken[] = {{g.uv, "the G-buffer's uv", sizeof(cl_float2)},
                 {g.view, "the G-buffer's view", sizeof(cl_float4)},
                 {g.material, "the G-buffer's material", sizeof(float)},
                 {g.light, "the G-buffer's light", sizeof(cl_float4)},
                 {g.lod, "the G-buffer's lod", sizeof(float)},
                 {g.curvature, "the G-buffer's curvature", sizeof(cl_float4)},
                 {g.uv_metric, "the G-buffer's uv metric", 3 * sizeof(cl_float4)}};
    for (const auto& p : taken)
        check_buffer(context, p.plane, {p.name, "value", p.bytes, n, true, true});
    return queue;
}

cl::Event MaterialFrame::enqueue(const DeviceGBuffer& g, const OffsetTargets& t,
                                 const LayerBehind& behind, const std::vector<cl::Event>& wait,
                                 const cl::CommandQueue& queue_given) {
    const cl::CommandQueue& queue = check_behind(g, t, behind, queue_given);
    const cl::Event first = enqueue(g, t, wait, queue);
    return trace_behind(g, t, behind, {first}, queue);
}

cl::Event MaterialFrame::enqueue_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                        const LayerBehind& behind,
                                        const std::vector<cl::Event>& wait,
                                        const cl::CommandQueue& queue_given) {
    const cl::CommandQueue& queue = check_behind(g, t, behind, queue_given);
    // After the first layer's trace whatever the caller waits on (an out-of-order queue too).
    std::vector<cl::Event> after = wait;
    if (classify_event_()) after.push_back(classify_event_);
    for (const Dispatch& d : dispatches_)
        if (d.event()) after.push_back(d.event);
    return trace_behind(g, t, behind, after, queue);
}

cl::Event MaterialFrame::trace_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                      const LayerBehind& behind, const std::vector<cl::Event>& wait,
                                      const cl::CommandQueue& queue) {
    const cl::Context& context = runtime_->context();
    const DeviceGBuffer& b = behind.gbuffer;
    const size_t n = g.pixels();
    const std::vector<Dispatch> first_dispatches = dispatches_;
    const cl::Event first_classify = classify_event_;
    try {
        if (!behind_ids_() || behind_ids_.getInfo<CL_MEM_SIZE>() != n * sizeof(float))
            behind_ids_ = device_buffer(context, CL_MEM_READ_WRITE, n * sizeof(float),
                                        "the layer behind's masked ids");
        const cl_int count = static_cast<cl_int>(n);
        cl::Event masked, chosen;
        set_args(behind_mask_, count, t.flags, b.material, behind_ids_);
        queue.enqueueNDRangeKernel(behind_mask_, cl::NullRange, padded(n), cl::NDRange(kLocalSize),
                                   &wait, &masked);
        DeviceGBuffer kept = b;
        kept.material = behind_ids_;
        const cl::Event second = enqueue(kept, behind.targets, {masked}, queue);
        // The planes the layers share (a null one where either lacks it).
        auto both = [](const cl::Buffer& from, const cl::Buffer& to) {
            return from() && to() ? std::make_pair(from, to)
                                  : std::make_pair(cl::Buffer(), cl::Buffer());
        };
        const auto light = both(b.light, g.light), lod = both(b.lod, g.lod),
                   curvature = both(b.curvature, g.curvature),
                   uv_metric = both(b.uv_metric, g.uv_metric);
        set_args(behind_choose_, count, t.flags, behind.targets.flags, behind.targets.uv,
                 behind.targets.depth, behind.targets.fetches, t.uv);
        set_optional(behind_choose_, 7, t.depth);
        set_optional(behind_choose_, 8, t.fetches);
        set_args_from(behind_choose_, 9, b.uv, b.view);
        set_optional(behind_choose_, 11, light.first);
        set_optional(behind_choose_, 12, lod.first);
        behind_choose_.setArg(13, b.material);
        set_optional(behind_choose_, 14, curvature.first);
        set_args_from(behind_choose_, 15, g.uv, g.view);
        set_optional(behind_choose_, 17, light.second);
        set_optional(behind_choose_, 18, lod.second);
        behind_choose_.setArg(19, g.material);
        set_optional(behind_choose_, 20, curvature.second);
        set_optional(behind_choose_, 21, uv_metric.first);
        set_optional(behind_choose_, 22, uv_metric.second);
        const std::vector<cl::Event> after_second{second};
        queue.enqueueNDRangeKernel(behind_choose_, cl::NullRange, padded(n),
                                   cl::NDRange(kLocalSize), &after_second, &chosen);
        std::vector<Dispatch> layers = first_dispatches;
        layers.insert(layers.end(), dispatches_.begin(), dispatches_.end());
        dispatches_ = layers;
        // The second classification's event is classify_event_.
        behind_events_ = {first_classify, masked, chosen};
        return chosen;
    } catch (const cl::Error& e) {
        throw Error("cannot run the material frame's layer behind: " + describe_cl_error(e.err()));
    }
}

cl::Event MaterialFrame::take_behind(const cl::Buffer& flags, const cl::Buffer& from,
                                     const cl::Buffer& to, size_t pixels, int words,
                                     const std::vector<cl::Event>& wait,
                                     const cl::CommandQueue& queue_given) {
    const cl::CommandQueue& queue = pass_queue(*runtime_, queue_given);
    const cl::Context& context = runtime_->context();
    const size_t bytes = static_cast<size_t>(words) * 4;
    check_buffer(context, flags, {"the frame's flags", "uint", sizeof(cl_uint), pixels});
    check_buffer(context, from, {"the layer behind's plane", "word", bytes, pixels});
    check_buffer(context, to, {"the G-buffer's plane", "word", bytes, pixels, true, false});
    set_args(behind_take_, static_cast<cl_int>(pixels), static_cast<cl_int>(words), flags, from,
             to);
    cl::Event done;
    try {
        queue.enqueueNDRangeKernel(behind_take_, cl::NullRange, padded(pixels),
                                   cl::NDRange(kLocalSize), &wait, &done);
    } catch (const cl::Error& e) {
        throw Error("cannot copy a plane of the layer behind: " + describe_cl_error(e.err()));
    }
    return done;
}

}  // namespace offsetmap
