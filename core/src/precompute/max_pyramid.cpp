// maxmip's pyramid of maxima (kernels/prep/maxmip.cl): level k (from 1) holds, per 2^k x 2^k
// block of cells, the largest texel its patches touch; level 0 is the height map itself.
#include <algorithm>
#include <cstddef>

#include "launch.hpp"
#include "methods/maxmip_pyramid.h"
#include "offsetmap/passes.hpp"
#include "offsetmap/runtime.hpp"
#include "precompute/precompute.hpp"

namespace offsetmap {
namespace {

int levels(const PassSettings& s, int w, int h) {
    return om_maxmip_levels(w, h, static_cast<om_int>(s.address));
}

// Over the map padded to a multiple of 2^levels a side (om_maxmip_padded).
size_t floats(const PassSettings& s, int w, int h) {
    const int top = levels(s, w, h), wp = om_maxmip_padded(w, top), hp = om_maxmip_padded(h, top);
    size_t n = 0;
    for (int k = 1; k <= top; ++k) n += static_cast<size_t>(wp >> k) * (hp >> k);
    return n;
}

size_t bytes(const MethodParams&, const PassSettings& s, int w, int h) {
    return floats(s, w, h) * sizeof(float);
}

PrecomputeSpec::Built build(Runtime& rt, const DeviceHeightField& f, const PassSettings& settings,
                            const MethodParams&) {
    PrecomputeSpec::Built out;
    const int top = levels(settings, f.width, f.height);
    const int wp = om_maxmip_padded(f.width, top), hp = om_maxmip_padded(f.height, top);
    out.data = cl::Buffer(rt.context(), CL_MEM_READ_WRITE,
                          std::max<size_t>(floats(settings, f.width, f.height), 1) * sizeof(float));
    if (top == 0) return out;  // no hierarchy: the walk is exact's
    cl::Program program = rt.program(prep_program_files(kMaxPyramid));
    OmOffsetParams p = offset_params(settings, f.width, f.height);
    cl::Kernel first = rt.kernel(program, "om_maxmip_first");
    set_args(first, p, f.heights, out.data, wp >> 1, hp >> 1);
    std::vector<cl::Event>& events = out.events;
    events.resize(1);
    std::vector<cl::Event> after_field = field_ready(f);
    enqueue_grid(rt.queue(), first, cl::NDRange(wp >> 1, hp >> 1), &after_field, &events[0]);
    cl::Kernel next = rt.kernel(program, "om_maxmip_next");
    int offset = 0;
    for (int k = 2; k <= top; ++k) {
        const int pw = wp >> (k - 1), ph = hp >> (k - 1), cw = wp >> k, ch = hp >> k;
        set_args(next, out.data, offset, pw, offset + pw * ph, cw, ch);
        // Each level reads the one before: wait for it (the queue may be out of order).
        std::vector<cl::Event> after = {events.back()};
        events.emplace_back();
        enqueue_grid(rt.queue(), next, cl::NDRange(cw, ch), &after, &events.back());
        offset += pw * ph;
    }
    return out;
}

}  // namespace

const PrecomputeSpec kMaxPyramid = {
    "max pyramid from level 1: about W H / 3 floats (4 W H / 3 bytes) over the map padded to a "
    "multiple of 2^levels (at most 1/8 more a side), built by a kernel per height map; any size, "
    "either address mode",
    "prep/maxmip.cl", "methods/maxmip_pyramid.h", bytes, build};

}  // namespace offsetmap
