// Triplanar relief: the material's parameters and the planes a triplanar frame adds.
#include "offsetmap/triplanar.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "launch.hpp"
#include "offsetmap/engine_gbuffer.hpp"

namespace offsetmap {

void validate(const Triplanar& t, const std::string& what) {
    if (!t.enabled) return;
    auto refuse = [&](const char* name, float v, const char* range) {
        std::ostringstream text;
        text << what << ": " << name << " " << v << " is out of range " << range;
        throw Error(text.str());
    };
    if (!(std::isfinite(t.world_scale) && t.world_scale > 0.0f && t.world_scale <= 1.0e6f))
        refuse("world_scale", t.world_scale, "(0, 1e6] (texture tiles per world unit)");
    if (!(t.sharpness >= 1.0f && t.sharpness <= 64.0f))
        refuse("sharpness", t.sharpness, "[1, 64] (the blend exponent)");
    // The largest weight is at least 1/3: a cutoff below it leaves every pixel a projection.
    if (!(t.cutoff >= 0.0f && t.cutoff <= 0.3f))
        refuse("cutoff", t.cutoff, "[0, 0.3] (the weight below which a projection is dropped)");
}

TriplanarFrame triplanar_frame(int p) {
    const double s = (p & 1) ? -1.0 : 1.0;
    switch (p >> 1) {
        case 0:
            return {{0.0, 0.0, -s}, {0.0, 1.0, 0.0}, {s, 0.0, 0.0}};
        case 1:
            return {{1.0, 0.0, 0.0}, {0.0, 0.0, -s}, {0.0, s, 0.0}};
        default:
            return {{s, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, s}};
    }
}

int triplanar_projection(const std::array<double, 3>& n, int axis) {
    return 2 * axis + (n[static_cast<size_t>(axis)] < 0.0 ? 1 : 0);
}

std::array<double, 3> triplanar_weights(const std::array<double, 3>& n, double sharpness,
                                        double cutoff) {
    std::array<double, 3> a;
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) sum += a[i] = std::pow(std::fabs(n[i]), sharpness);
    double kept = 0.0;
    for (double& x : a) kept += x = std::max(x / sum - cutoff, 0.0);
    for (double& x : a) x /= kept;
    return a;
}

TriplanarPlanes allocate_triplanar(Runtime& rt, int width, int height) {
    TriplanarPlanes t;
    t.second = allocate_gbuffer(rt, width, height, false, false);
    t.third = allocate_gbuffer(rt, width, height, false, false);
    const size_t n = t.second.pixels();
    const cl::Context& c = rt.context();
    const std::string what = "the triplanar frame's ";
    for (DeviceGBuffer* g : {&t.second, &t.third})
        g->material = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(float), what + "ids");
    for (OffsetTargets* o : {&t.second_targets, &t.third_targets}) {
        o->uv = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(cl_float2), what + "uv'");
        o->depth = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(float), what + "depth");
        o->fetches = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(cl_uint), what + "fetches");
        o->flags = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(cl_uint), what + "flags");
    }
    t.blend = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(cl_float4), what + "weights");
    t.ray_scale = device_buffer(c, CL_MEM_READ_WRITE, n * sizeof(float), what + "ray scales");
    return t;
}

}  // namespace offsetmap
