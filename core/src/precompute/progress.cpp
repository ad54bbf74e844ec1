// Long precomputes in slices, so that the runtime's progress callback can follow them.
#include <algorithm>

#include "launch.hpp"
#include "precompute/precompute.hpp"

namespace offsetmap {

std::vector<cl::Event> enqueue_with_progress(Runtime& rt, cl::Kernel& kernel,
                                             const cl::NDRange& range, const std::string& what,
                                             const std::vector<cl::Event>& wait) {
    // Slices along the last dimension, whole work-groups each (launch.hpp's fixed group).
    const size_t dims = range.dimensions();
    const size_t last = range[dims - 1];
    const cl::NDRange global = grid_global(range);
    const size_t unit = dims == 2 ? kGridTile : 1;  // the group's extent along it
    const size_t groups = global[dims - 1] / unit;
    // About 32 slices: fine enough to follow, few enough that the waits cost nothing.
    const size_t slices = rt.progress() ? std::min<size_t>(groups, 32) : 1;
    std::vector<cl::Event> events;
    if (rt.progress()) rt.progress()(what, 0.0);
    for (size_t s = 0; s < slices; ++s) {
        const size_t begin = groups * s / slices * unit, end = groups * (s + 1) / slices * unit;
        cl::NDRange offset = dims == 3 ? cl::NDRange(0, 0, begin) : cl::NDRange(0, begin);
        cl::NDRange size = dims == 3 ? cl::NDRange(global[0], global[1], end - begin)
                                     : cl::NDRange(global[0], end - begin);
        cl::Event e;
        rt.queue().enqueueNDRangeKernel(kernel, offset, size, grid_local(dims),
                                        events.empty() ? &wait : nullptr, &e);
        events.push_back(e);
        if (rt.progress()) {
            e.wait();
            rt.progress()(what,
                          static_cast<double>(std::min(end, last)) / static_cast<double>(last));
        }
    }
    return events;
}

double events_ms(const Runtime& rt, const std::vector<cl::Event>& events) {
    double ms = 0.0;
    if (rt.profiling())
        for (const auto& e : events) {
            e.wait();
            ms += event_ms(e);
        }
    return ms;
}

}  // namespace offsetmap
