// Long precomputes in slices, so that the runtime's progress callback can follow them.
#include <algorithm>

#include "precompute/precompute.hpp"

namespace offsetmap {

std::vector<cl::Event> enqueue_with_progress(Runtime& rt, cl::Kernel& kernel,
                                             const cl::NDRange& range, const std::string& what,
                                             const std::vector<cl::Event>& wait) {
    const size_t dims = range.dimensions();
    const size_t last = range[dims - 1];
    // About 32 slices: fine enough to follow, few enough that the waits cost nothing.
    const size_t slices = rt.progress() ? std::min<size_t>(last, 32) : 1;
    std::vector<cl::Event> events;
    if (rt.progress()) rt.progress()(what, 0.0);
    for (size_t s = 0; s < slices; ++s) {
        const size_t begin = last * s / slices, end = last * (s + 1) / slices;
        cl::NDRange offset = dims == 3 ? cl::NDRange(0, 0, begin) : cl::NDRange(0, begin);
        cl::NDRange size = dims == 3 ? cl::NDRange(range[0], range[1], end - begin)
                                     : cl::NDRange(range[0], end - begin);
        cl::Event e;
        rt.queue().enqueueNDRangeKernel(kernel, offset, size, cl::NullRange,
                                        events.empty() ? &wait : nullptr, &e);
        events.push_back(e);
        if (rt.progress()) {
            e.wait();
            rt.progress()(what, static_cast<double>(end) / static_cast<double>(last));
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
