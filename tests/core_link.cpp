// An engine's view: a program that links only the library (offsetmap::offsetmap, no
// OpenImageIO), on its own OpenCL objects through Runtime::create, runs a pass over a G-buffer it
// filled itself and checks the answer against the plane hit: on a constant field H = c every
// method meets the plane at t = s (r - c) / V.z.
#include <cmath>
#include <cstdio>

#include "offsetmap/offsetmap.hpp"

int main() {
    using namespace offsetmap;
    try {
        auto rt = Runtime::create();
        HeightMap map;
        map.width = map.height = 8;
        map.h.assign(64, 0.25f);
        PassSettings s;
        s.scale = 0.1f;
        GBuffer gb;
        gb.resize(4, 1, false, false);
        const float vz[4] = {1.0f, 0.8f, 0.5f, 0.3f};
        for (int k = 0; k < 4; ++k) {
            gb.uv[k] = {{0.1f * k, 0.5f}};
            gb.view[k] = {{std::sqrt(1 - vz[k] * vz[k]), 0.0f, vz[k], 0.0f}};
        }
        DeviceHeightField field = upload(*rt, map, s);
        DeviceGBuffer g = upload(*rt, gb);
        OffsetTargets out;
        out.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, 4 * sizeof(cl_float2));
        out.depth = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, 4 * sizeof(float));
        OffsetPass pass(rt, "exact");
        pass.enqueue(g, field, s, out).wait();
        float depth[4];
        rt->queue().enqueueReadBuffer(out.depth, CL_TRUE, 0, sizeof depth, depth);
        for (int k = 0; k < 4; ++k) {
            const double t = 0.1 * (1.0 - 0.25) / vz[k];
            if (std::fabs(depth[k] - t) > 1e-5 * t + 1e-7) {
                std::fprintf(stderr, "core_link: pixel %d depth %g, expected %g\n", k, depth[k], t);
                return 1;
            }
        }
        std::printf("core_link: the library alone ran exact on %s\n", rt->device_name().c_str());
        return 0;
    } catch (const Error& e) {
        std::fprintf(stderr, "core_link: %s\n", e.what());
        return 1;
    }
}
