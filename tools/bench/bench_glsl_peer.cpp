#include "bench_glsl_peer.hpp"

#include <cstdio>

#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/glsl_peer.hpp"
#endif

namespace offsetmap::bench {

#ifndef OFFSETMAP_HAVE_RENDERER

nlohmann::json bench_glsl_peer(std::shared_ptr<Runtime>, const Resolution&, const HeightMap&,
                               const PassSettings&, double) {
    std::printf("\nGLSL peer: skipped (built without the renderer: EGL, OpenGL or TinyGLTF)\n");
    return {{"skipped", "built without the renderer (EGL, OpenGL or TinyGLTF missing)"}};
}

#else

nlohmann::json bench_glsl_peer(std::shared_ptr<Runtime> rt, const Resolution& res,
                               const HeightMap& map, const PassSettings& s, double target_ms) {
    PlaneScene plane;
    plane.width = res.w;
    plane.height = res.h;
    const std::vector<std::pair<const char*, GBuffer> > scenes = {
        {"camera", make_scene(plane)},
        {"random", make_scene(RandomScene{res.w, res.h, 1, 10, 90})}};
    const DeviceHeightField f = upload(*rt, map, s);
    nlohmann::json rows = nlohmann::json::array();
    std::string gl_name;
    std::printf(
        "\nkernels against the same methods in GLSL, a full-screen pass over the same G-buffer "
        "(%s, %dx%d map, wall clock per finished run, timed in turns)\n  %-7s %-7s %11s %11s "
        "%9s %17s %17s\n",
        res.name, map.width, map.height, "scene", "method", "kernel ns", "GLSL ns", "kernel x",
        "kernel mean/p95", "GLSL mean/p95");
    for (const auto& [scene, gb] : scenes) {
        const DeviceGBuffer g = upload(*rt, gb);
        renderer::GlslPeer peer(gb, map, s);
        gl_name = peer.gl_renderer();
        OffsetPass exact_pass(rt, "exact");
        const OffsetResult exact = run_offset(*rt, exact_pass, g, f, s, 1);
        const double n = static_cast<double>(gb.pixels());
        OffsetTargets t;  // the timed runs' outputs, shared by the methods
        t.uv = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, gb.pixels() * sizeof(cl_float2));
        t.depth = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, gb.pixels() * sizeof(float));
        for (const MethodInfo& info : methods()) {
            // The marches with a forward version (a single fetch is not worth a row).
            const MethodParams params = resolve_params(info, {});
            if (info.glsl.empty() || info.fetch_cap(params) <= 1) continue;
            const char* method = info.name.c_str();
            OffsetPass pass(rt, params);
            const OffsetResult kernel = run_offset(*rt, pass, g, f, s, 1);
            peer.set_method(params);
            const auto kernel_run = [&] {
                const Stopwatch clock;
                pass.enqueue(g, f, s, t).wait();
                return clock.total();
            };
            const std::vector<Timing> tm =
                time_interleaved_ms({kernel_run, [&] { return peer.run(); }}, target_ms);
            const OffsetResult glsl = peer.result();
            const ErrorStats ek = uv_error(kernel, exact, map.width, map.height);
            const ErrorStats eg = uv_error(glsl, exact, map.width, map.height);
            const double kns = tm[0].median_ms * 1e6 / n, gns = tm[1].median_ms * 1e6 / n;
            std::printf("  %-7s %-7s %11.2f %11.2f %8.2fx %8.4f /%7.4f %8.4f /%7.4f\n", scene,
                        method, kns, gns, gns / kns, ek.mean, ek.p95, eg.mean, eg.p95);
            rows.push_back({{"scene", scene},
                            {"method", method},
                            {"kernel_ns_per_pixel", kns},
                            {"glsl_ns_per_pixel", gns},
                            {"kernel_speedup", gns / kns},
                            {"rounds", tm[0].runs},
                            {"kernel_fetches_per_pixel", mean_fetches(kernel)},
                            {"glsl_fetches_per_pixel", mean_fetches(glsl)},
                            {"kernel_mean_err_texels", ek.mean},
                            {"kernel_p95_err_texels", ek.p95},
                            {"glsl_mean_err_texels", eg.mean},
                            {"glsl_p95_err_texels", eg.p95}});
        }
    }
    return {{"resolution", res.name}, {"gl_renderer", gl_name}, {"rows", rows}};
}

#endif

}  // namespace offsetmap::bench
