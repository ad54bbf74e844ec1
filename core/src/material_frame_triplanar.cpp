// The material frame's triplanar materials: the second and third projections traced where they
// weigh, merged into the first's targets.
#include "launch.hpp"
#include "offsetmap/material_frame.hpp"

namespace offsetmap {

cl::Event MaterialFrame::enqueue(const DeviceGBuffer& g, const OffsetTargets& t,
                                 const TriplanarPlanes& planes, const std::vector<cl::Event>& wait,
                                 const cl::CommandQueue& queue_given) {
    if (!triplanar_table_.any) return enqueue(g, t, wait, queue_given);
    const cl::Context& context = runtime_->context();
    const cl::CommandQueue& queue = checked_queue(g, queue_given);
    const size_t n = g.pixels();
    check_triplanar_planes(context, planes, g);
    const cl::Event first = trace(g, t, wait, queue, true);
    std::vector<Dispatch> all = dispatches_;
    std::vector<cl::Event> events{classify_event_};
    // The second and third projections' id-0 pixels are nobody's: no pass-through for them.
    const cl::Event second = trace(planes.second, planes.second_targets, {first}, queue, false);
    all.insert(all.end(), dispatches_.begin(), dispatches_.end());
    events.push_back(classify_event_);
    const cl::Event third = trace(planes.third, planes.third_targets, {second}, queue, false);
    all.insert(all.end(), dispatches_.begin(), dispatches_.end());
    dispatches_ = all;
    try {
        set_args(triplanar_merge_, static_cast<cl_int>(n), planes.second.material, planes.blend);
        set_optional(triplanar_merge_, 3, t.depth);
        set_optional(triplanar_merge_, 4, t.fetches);
        set_args_from(triplanar_merge_, 5, planes.second_targets.depth,
                      planes.second_targets.fetches, planes.third_targets.depth,
                      planes.third_targets.fetches, planes.ray_scale, planes.second.view,
                      planes.third.view);
        cl::Event merged;
        const std::vector<cl::Event> after{third};
        queue.enqueueNDRangeKernel(triplanar_merge_, cl::NullRange, padded((n + 15) / 16),
                                   cl::NDRange(kLocalSize), &after, &merged);
        // The third classification's event is classify_event_.
        events.push_back(merged);
        triplanar_events_ = events;
        return merged;
    } catch (const cl::Error& e) {
        throw Error("cannot merge the triplanar projections: " + describe_cl_error(e.err()));
    }
}

void MaterialFrame::check_triplanar_planes(const cl::Context& context, const TriplanarPlanes& p,
                                           const DeviceGBuffer& g) const {
    const size_t n = g.pixels();
    for (const DeviceGBuffer* b : {&p.second, &p.third}) {
        if (b->width != g.width || b->height != g.height)
            throw Error("the triplanar planes are " + std::to_string(b->width) + "x" +
                        std::to_string(b->height) + "; the G-buffer is " + std::to_string(g.width) +
                        "x" + std::to_string(g.height));
    }
    for (const OffsetTargets* o : {&p.second_targets, &p.third_targets}) {
        check_targets(context, *o, n);
        if (!o->depth() || !o->fetches() || !o->flags())
            throw Error(
                "the triplanar projections' targets need every output (uv, depth, "
                "fetches, flags)");
    }
    check_buffer(context, p.blend, {"the triplanar weights", "float4", sizeof(cl_float4), n});
    check_buffer(context, p.ray_scale, {"the triplanar ray scales", "float", sizeof(float), n});
}

void MaterialFrame::refuse_without_projections(const char* call) const {
    // Its pixels' G-buffer holds no uv of theirs without the split: a frame would trace and
    // shade them silently wrong.
    if (triplanar_table_.any)
        throw Error(triplanar_table_.name + " is triplanar: the material frame's " + call +
                    " needs its projections (ReconstructPass's triplanar split, then the " + call +
                    " that takes the TriplanarPlanes)");
}

}  // namespace offsetmap
