#include "offsetmap/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "launch.hpp"
#include "offsetmap/shared.h"
#include "offsetmap/timing.hpp"

namespace offsetmap {

double OffsetResult::median_kernel_ms() const {
    return median(kernel_ms, std::numeric_limits<double>::quiet_NaN());
}

bool traced(std::uint32_t flags) {
    return (flags & (OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING)) == 0u;
}

size_t traced_pixels(const OffsetResult& r) {
    return static_cast<size_t>(std::count_if(r.flags.begin(), r.flags.end(), traced));
}

double mean_fetches(const OffsetResult& r) {
    double sum = 0;
    size_t n = 0;
    for (size_t k = 0; k < r.fetches.size() && k < r.flags.size(); ++k)
        if (traced(r.flags[k])) sum += r.fetches[k], ++n;
    return n ? sum / static_cast<double>(n) : 0.0;
}

double max_fetches(const OffsetResult& r) {
    std::uint32_t most = 0;
    for (size_t k = 0; k < r.fetches.size() && k < r.flags.size(); ++k)
        if (traced(r.flags[k])) most = std::max(most, r.fetches[k]);
    return most;
}

namespace {

OffsetTargets all_targets(Runtime& rt, size_t n) {
    OffsetTargets t;
    t.uv = device_buffer(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float2), "the uv output");
    t.depth = device_buffer(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(float), "the depth output");
    t.fetches = device_buffer(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(std::uint32_t),
                              "the fetches output");
    t.flags = device_buffer(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(std::uint32_t),
                            "the flags output");
    return t;
}

void read_back(Runtime& rt, const OffsetTargets& t, OffsetResult& r) {
    const size_t n = static_cast<size_t>(r.width) * r.height;
    r.uv.resize(n);
    r.depth.resize(n);
    r.fetches.resize(n);
    r.flags.resize(n);
    auto& q = rt.queue();
    q.enqueueReadBuffer(t.uv, CL_FALSE, 0, n * sizeof(cl_float2), r.uv.data());
    q.enqueueReadBuffer(t.depth, CL_FALSE, 0, n * sizeof(float), r.depth.data());
    q.enqueueReadBuffer(t.fetches, CL_FALSE, 0, n * sizeof(std::uint32_t), r.fetches.data());
    q.enqueueReadBuffer(t.flags, CL_TRUE, 0, n * sizeof(std::uint32_t), r.flags.data());
}

}  // namespace

OffsetResult run_offset(Runtime& rt, OffsetPass& pass, const DeviceGBuffer& g,
                        const DeviceHeightField& f, const PassSettings& settings, int repeats) {
    const OffsetTargets t = all_targets(rt, g.pixels());
    OffsetResult r;
    r.width = g.width;
    r.height = g.height;
    for (int k = 0; k < std::max(1, repeats); ++k) {
        cl::Event e = pass.enqueue(g, f, settings, t);
        e.wait();
        if (rt.profiling()) r.kernel_ms.push_back(event_ms(e));
    }
    read_back(rt, t, r);
    return r;
}

OffsetResult run_material_frame(Runtime& rt, MaterialFrame& frame, const DeviceGBuffer& g,
                                int repeats) {
    const OffsetTargets t = all_targets(rt, g.pixels());
    OffsetResult r;
    r.width = g.width;
    r.height = g.height;
    for (int k = 0; k < std::max(1, repeats); ++k) {
        frame.enqueue(g, t).wait();
        if (!rt.profiling()) continue;
        r.kernel_ms.push_back(frame.kernel_ms());
    }
    read_back(rt, t, r);
    return r;
}

std::vector<cl_float4> run_shade(Runtime& rt, ShadePass& pass, const OffsetResult& r,
                                 const DeviceGBuffer& g, const DeviceHeightField& f,
                                 const DeviceImage* albedo, const PassSettings& settings,
                                 const ShadeSettings& shade) {
    const size_t n = g.pixels();
    cl::Buffer uv(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float2),
                  const_cast<cl_float2*>(r.uv.data()));
    cl::Buffer flags(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                     n * sizeof(std::uint32_t), const_cast<std::uint32_t*>(r.flags.data()));
    cl::Buffer out(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
    pass.enqueue(g, f, {uv, flags, albedo}, settings, shade, {out}).wait();
    std::vector<cl_float4> rgba(n);
    rt.queue().enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(cl_float4), rgba.data());
    return rgba;
}

ErrorStats error_stats(std::vector<double> errs) {
    ErrorStats s;
    s.count = errs.size();
    if (errs.empty()) return s;
    double sum = 0;
    size_t wrong = 0;
    for (double e : errs) {
        sum += e;
        s.max = std::max(s.max, e);
        wrong += e > 1.0;
    }
    s.mean = sum / errs.size();
    s.wrong_share = static_cast<double>(wrong) / errs.size();
    size_t p = static_cast<size_t>(std::ceil(0.95 * errs.size())) - 1;
    std::nth_element(errs.begin(), errs.begin() + p, errs.end());
    s.p95 = errs[p];
    return s;
}

ErrorStats uv_error(const OffsetResult& r, const OffsetResult& ref, int fw, int fh,
                    std::vector<float>* per_pixel, const std::function<bool(size_t)>& include) {
    const size_t n = r.uv.size();
    std::vector<double> errs;
    errs.reserve(n);
    if (per_pixel) per_pixel->assign(n, std::numeric_limits<float>::quiet_NaN());
    for (size_t k = 0; k < n; ++k) {
        if (!traced(r.flags[k]) || !traced(ref.flags[k]) || (include && !include(k))) continue;
        double du = (static_cast<double>(r.uv[k].s[0]) - ref.uv[k].s[0]) * fw;
        double dv = (static_cast<double>(r.uv[k].s[1]) - ref.uv[k].s[1]) * fh;
        double e = std::hypot(du, dv);
        errs.push_back(e);
        if (per_pixel) (*per_pixel)[k] = static_cast<float>(e);
    }
    return error_stats(std::move(errs));
}

}  // namespace offsetmap
