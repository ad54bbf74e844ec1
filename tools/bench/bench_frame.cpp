#include "bench_frame.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/gltf.hpp"
#include "offsetmap/renderer/mesh.hpp"
#include "offsetmap/renderer/scene.hpp"
#endif

namespace offsetmap::bench {

#ifndef OFFSETMAP_HAVE_RENDERER

nlohmann::json bench_frame(std::shared_ptr<Runtime>, const Resolution&, const std::string&, int,
                           const std::vector<std::string>&) {
    std::printf("\nframe: skipped (built without the renderer: EGL, OpenGL or TinyGLTF)\n");
    return {{"skipped", "built without the renderer (EGL, OpenGL or TinyGLTF missing)"}};
}

nlohmann::json bench_curved_frame(std::shared_ptr<Runtime>, const Resolution&, const std::string&,
                                  int, double) {
    std::printf("\ncurved frame: skipped (built without the renderer)\n");
    return {{"skipped", "built without the renderer (EGL, OpenGL or TinyGLTF missing)"}};
}

nlohmann::json bench_shadow_map(std::shared_ptr<Runtime>, const Resolution&, const std::string&,
                                int, int) {
    std::printf("\nshadow map: skipped (built without the renderer)\n");
    return {{"skipped", "built without the renderer (EGL, OpenGL or TinyGLTF missing)"}};
}

nlohmann::json bench_triplanar_frame(std::shared_ptr<Runtime>, const Resolution&,
                                     const std::string&, int) {
    std::printf("\ntriplanar frame: skipped (built without the renderer)\n");
    return {{"skipped", "built without the renderer (EGL, OpenGL or TinyGLTF missing)"}};
}

#else

namespace {

using namespace offsetmap::renderer;

// A host memcpy of `bytes`, in ms: the copies' yardstick, timed beside them.
double memcpy_ms(std::vector<char>& from, std::vector<char>& to, size_t bytes) {
    if (from.size() < bytes) from.assign(bytes, 1), to.assign(bytes, 0);
    const Stopwatch clock;
    std::memcpy(to.data(), from.data(), bytes);
    return clock.total();
}

const char* const kPasses[] = {"gbuffer",       "to_device", "reconstruct",  "offset",
                               "offset_kernel", "shade",     "shade_kernel", "to_gl",
                               "depth_offset",  "total",     "shade_rerun",  "offset_rerun"};

std::vector<double> pass_values(const FrameRun& r) {
    return {r.ms.gbuffer,       r.ms.to_device, r.ms.reconstruct,  r.ms.offset,
            r.offset_kernel_ms, r.ms.shade,     r.shade_kernel_ms, r.ms.to_gl,
            r.ms.depth_offset,  r.ms.total};
}

}  // namespace

nlohmann::json bench_frame(std::shared_ptr<Runtime> rt, const Resolution& res,
                           const std::string& data_dir, int rounds,
                           const std::vector<std::string>& kernel_dirs) {
    const Scene scene = builtin_room(data_dir);
    const std::vector<LoadedMaterial> table =
        load_materials(read_material_table(data_dir + "/room.json"));
    const std::vector<MethodParams> methods = table_methods(table);
    // One renderer per kernel folder, each built after its folder is set.
    std::vector<std::string> dirs =
        kernel_dirs.empty() ? std::vector<std::string>{""} : kernel_dirs;
    std::vector<std::unique_ptr<FrameRenderer> > renderers;
    for (const std::string& dir : dirs) {
        rt->set_kernel_dir(dir);
        renderers.push_back(std::make_unique<FrameRenderer>(rt, scene, table, methods, res.w, res.h,
                                                            ShadeSettings{}));
    }
    rt->set_kernel_dir("");
    const std::pair<const char*, ShadowMode> modes[] = {
        {"none", ShadowMode::None}, {"hard", ShadowMode::Hard}, {"soft", ShadowMode::Soft}};
    // samples[renderer][mode][pass]: one value per round.
    std::vector<std::vector<std::vector<std::vector<double> > > > samples(
        dirs.size(), std::vector<std::vector<std::vector<double> > >(
                         std::size(modes), std::vector<std::vector<double> >(std::size(kPasses))));
    std::vector<double> copy_in, copy_out;
    std::vector<char> from, to;
    size_t in_bytes = 0, out_bytes = 0;
    for (int round = 0; round < rounds; ++round)
        for (size_t mi = 0; mi < std::size(modes); ++mi)
            for (size_t d = 0; d < dirs.size(); ++d) {
                ShadeSettings shading;
                shading.shadow = modes[mi].second;
                renderers[d]->set_shading(shading);
                const FrameRun r = renderers[d]->render(FrameMode::Deferred, false, 1);
                std::vector<double> v = pass_values(r);
                // The kernels alone, again on this frame's buffers (a kernel A/B's finer clock).
                const auto [shade_rerun, offset_rerun] = renderers[d]->rerun_kernels(3);
                v.push_back(shade_rerun);
                v.push_back(offset_rerun);
                for (size_t p = 0; p < v.size(); ++p) samples[d][mi][p].push_back(v[p]);
                in_bytes = r.to_device_bytes;
                out_bytes = r.to_gl_bytes;
                copy_in.push_back(memcpy_ms(from, to, in_bytes));
                copy_out.push_back(memcpy_ms(from, to, out_bytes));
            }
    const double memcpy_in = median(copy_in), memcpy_out = median(copy_out);
    nlohmann::json out;
    out["resolution"] = {res.w, res.h};
    out["rounds"] = rounds;
    out["gl_renderer"] = renderers.front()->gl_renderer();
    out["interop"] = renderers.front()->interop();
    out["to_device_bytes"] = in_bytes;
    out["to_gl_bytes"] = out_bytes;
    out["memcpy_to_device_ms"] = memcpy_in;
    out["memcpy_to_gl_ms"] = memcpy_out;
    std::printf(
        "\nthe deferred room at %s (%dx%d; GL: %s; %s), medians of %d frames a mode taken in "
        "turns, ms\n  %-6s %-5s %8s %8s %8s %8s %8s %8s %8s %8s %8s %8s | shade/off  to-CL/cpy "
        "to-GL/cpy recon/off depth/off total/off\n",
        res.name, res.w, res.h, out["gl_renderer"].get<std::string>().c_str(),
        out["interop"].get<std::string>().c_str(), rounds, "kernel", "mode", "G-buffer", "to CL",
        "reconstr", "offset", "off kern", "shade", "sh kern", "to GL", "depth", "total");
    nlohmann::json rows = nlohmann::json::array();
    for (size_t d = 0; d < dirs.size(); ++d)
        for (size_t mi = 0; mi < std::size(modes); ++mi) {
            nlohmann::json row;
            row["kernels"] = dirs[d].empty() ? "built-in" : dirs[d];
            row["shadows"] = modes[mi].first;
            std::vector<double> med;
            for (size_t p = 0; p < std::size(kPasses); ++p) {
                med.push_back(median(samples[d][mi][p]));
                row[std::string(kPasses[p]) + "_ms"] = med.back();
            }
            // Kernel against kernel where events time them, else the passes' wall clocks.
            const bool timed = med[4] > 0.0 && med[6] > 0.0;
            const double offset = timed ? med[4] : med[3], shade = timed ? med[6] : med[5];
            row["ratios"] = {{"shade_over_offset", shade / offset},
                             {"to_device_over_memcpy", med[1] / memcpy_in},
                             {"to_gl_over_memcpy", med[7] / memcpy_out},
                             {"reconstruct_over_offset", med[2] / med[3]},
                             {"depth_offset_over_offset", med[8] / med[3]},
                             {"total_over_offset", med[9] / med[3]}};
            row["ratios_by"] = timed ? "kernel events" : "host clock";
            std::printf(
                "  %-6s %-5s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f | %9.2f "
                "%9.2f %9.2f %9.2f %9.2f %9.2f\n",
                dirs.size() > 1 ? (d == 0 ? "A" : "B") : "-", modes[mi].first, med[0], med[1],
                med[2], med[3], med[4], med[5], med[6], med[7], med[8], med[9],
                row["ratios"]["shade_over_offset"].get<double>(),
                row["ratios"]["to_device_over_memcpy"].get<double>(),
                row["ratios"]["to_gl_over_memcpy"].get<double>(),
                row["ratios"]["reconstruct_over_offset"].get<double>(),
                row["ratios"]["depth_offset_over_offset"].get<double>(),
                row["ratios"]["total_over_offset"].get<double>());
            rows.push_back(row);
        }
    std::printf("  host memcpy of the same bytes: to CL %.2f ms (%zu B), to GL %.2f ms (%zu B)\n",
                memcpy_in, in_bytes, memcpy_out, out_bytes);
    if (dirs.size() == 2)
        for (size_t mi = 0; mi < std::size(modes); ++mi) {
            // The median of each round's ratio: both frames of a round met the same machine.
            auto ratio = [&](size_t p) {
                std::vector<double> q;
                for (int r = 0; r < rounds; ++r)
                    if (samples[0][mi][p][r] > 0.0)
                        q.push_back(samples[1][mi][p][r] / samples[0][mi][p][r]);
                return median(q);
            };
            std::printf(
                "  B/A %-5s: shade kernel %.3f (again alone %.3f), offset kernel %.3f (alone "
                "%.3f), total %.3f\n",
                modes[mi].first, ratio(6), ratio(10), ratio(4), ratio(11), ratio(9));
            rows[std::size(modes) + mi]["b_over_a"] = {{"shade_kernel", ratio(6)},
                                                       {"shade_rerun", ratio(10)},
                                                       {"offset_kernel", ratio(4)},
                                                       {"offset_rerun", ratio(11)},
                                                       {"total", ratio(9)}};
        }
    out["rows"] = rows;
    return out;
}

nlohmann::json bench_curved_frame(std::shared_ptr<Runtime> rt, const Resolution& res,
                                  const std::string& data_dir, int rounds, double target_ms) {
    const std::string table_file = data_dir + "/curved.json";
    const std::vector<MaterialSpec> specs = read_material_table(table_file);
    const Scene scene = load_gltf_scene(data_dir + "/curved.gltf", specs, table_file);
    const std::vector<LoadedMaterial> table = load_materials(specs);
    const std::vector<MethodParams> methods = table_methods(table);
    FrameRenderer r(rt, scene, table, methods, res.w, res.h, ShadeSettings{});
    struct Mode {
        const char* name;
        bool curved;
        int layers;
        bool whole;   // the layer behind drawn over the whole frame (set_layers)
        bool metric;  // with the uv metric plane (set_uv_metric)
    };
    const Mode modes[] = {
        {"plane", false, 1, false, false},    {"curved", true, 1, false, false},
        {"metric", true, 1, false, true},     {"two-layers", true, 2, false, false},
        {"two-metric", true, 2, false, true}, {"two-whole", true, 2, true, false}};
    // samples[mode][pass], one value per round.
    std::vector<std::vector<std::vector<double> > > samples(std::size(modes),
                                                            std::vector<std::vector<double> >(10));
    std::vector<size_t> left(std::size(modes));  // pixels the first layer left to the second
    for (int round = 0; round <= rounds; ++round)
        for (size_t m = 0; m < std::size(modes); ++m) {
            r.set_curvature(modes[m].curved);
            r.set_uv_metric(modes[m].metric);
            r.set_layers(modes[m].layers, modes[m].whole);
            const FrameRun run = r.render(FrameMode::Deferred, false, 1);
            const std::vector<double> v = pass_values(run);
            left[m] = run.behind_pixels + run.missed_pixels;
            if (round == 0) continue;  // the first round warms each mode up
            for (size_t p = 0; p < v.size(); ++p) samples[m][p].push_back(v[p]);
        }
    nlohmann::json out;
    out["resolution"] = {res.w, res.h};
    out["rounds"] = rounds;
    out["gl_renderer"] = r.gl_renderer();
    std::printf(
        "\nthe curved scene at %s (%dx%d; GL: %s), medians of %d frames a mode taken in "
        "turns, ms\n  %-10s %8s %8s %8s %8s %8s %8s %8s\n",
        res.name, res.w, res.h, out["gl_renderer"].get<std::string>().c_str(), rounds, "mode",
        "G-buffer", "to CL", "reconstr", "offset", "off kern", "shade", "total");
    nlohmann::json rows = nlohmann::json::array();
    for (size_t m = 0; m < std::size(modes); ++m) {
        nlohmann::json row = {{"mode", modes[m].name}};
        if (modes[m].layers == 2) row["pixels_behind"] = left[m];
        std::vector<double> med;
        for (size_t p = 0; p < 10; ++p) {
            med.push_back(median(samples[m][p]));
            row[std::string(kPasses[p]) + "_ms"] = med.back();
        }
        std::printf("  %-10s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f\n", modes[m].name, med[0],
                    med[1], med[2], med[3], med[4], med[5], med[9]);
        rows.push_back(row);
    }
    // Ratios per round (the two frames of a round share the machine's load), then the median.
    auto ratio = [&](size_t a, size_t b, size_t pass) {
        std::vector<double> q;
        for (size_t k = 0; k < samples[a][pass].size(); ++k)
            q.push_back(samples[a][pass][k] / samples[b][pass][k]);
        return median(q);
    };
    out["rows"] = rows;
    out["ratios"] = {{"curved_over_plane_total", ratio(1, 0, 9)},
                     {"curved_over_plane_offset", ratio(1, 0, 3)},
                     {"two_layers_over_curved_total", ratio(2, 1, 9)},
                     {"two_layers_over_plane_total", ratio(2, 0, 9)},
                     {"two_layers_over_curved_gbuffer", ratio(2, 1, 0)},
                     {"two_layers_over_curved_offset", ratio(2, 1, 3)},
                     {"two_whole_over_curved_total", ratio(3, 1, 9)}};
    std::printf("  the layer behind traced at %zu of %d pixels\n", left[2], res.w * res.h);
    std::printf(
        "  frame totals: curved / plane %.3f, two layers / curved %.3f, two layers / plane "
        "%.3f (G-buffer pass %.3f, offset %.3f); the whole layer behind / curved %.3f\n",
        out["ratios"]["curved_over_plane_total"].get<double>(),
        out["ratios"]["two_layers_over_curved_total"].get<double>(),
        out["ratios"]["two_layers_over_plane_total"].get<double>(),
        out["ratios"]["two_layers_over_curved_gbuffer"].get<double>(),
        out["ratios"]["two_layers_over_curved_offset"].get<double>(),
        out["ratios"]["two_whole_over_curved_total"].get<double>());

    // The curvature plane's read: a plane of zeros (every pixel traced as today) against none.
    PassSettings s;
    s.scale = 0.05f;
    const DeviceHeightField field = upload(*rt, bench_map(1024), s);
    GBuffer flat = camera_gbuffer(res);
    const DeviceGBuffer none = upload(*rt, flat);
    flat.curvature.assign(flat.pixels(), cl_float4{{0.0f, 0.0f, 0.0f, 1.0f}});
    const DeviceGBuffer zeros = upload(*rt, flat);
    OffsetTargets t;
    t.uv = cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, flat.pixels() * sizeof(cl_float2));
    nlohmann::json read = nlohmann::json::array();
    std::printf(
        "  the curvature plane's read (the camera plane, 1024^2, zeros bound against none):");
    for (const char* method : {"pom", "relief", "exact"}) {
        OffsetPass pass(rt, method);
        const std::vector<Timing> ms =
            time_interleaved({[&] { return pass.enqueue(none, field, s, t); },
                              [&] { return pass.enqueue(zeros, field, s, t); }},
                             target_ms);
        read.push_back({{"method", method},
                        {"none_ms", ms[0].median_ms},
                        {"zero_plane_ms", ms[1].median_ms},
                        {"ratio", ms[1].median_ms / ms[0].median_ms},
                        {"rounds", ms[0].runs}});
        std::printf(" %s %.3f / %.3f ms (x%.3f)", method, ms[1].median_ms, ms[0].median_ms,
                    ms[1].median_ms / ms[0].median_ms);
    }
    std::printf("\n");
    out["curvature_read"] = read;
    return out;
}

nlohmann::json bench_shadow_map(std::shared_ptr<Runtime> rt, const Resolution& res,
                                const std::string& data_dir, int rounds, int map_size) {
    Scene scene = builtin_room(data_dir);
    const double e = 20.0 * M_PI / 180.0, a = 60.0 * M_PI / 180.0;
    scene.light = {
        LightKind::Directional,
        {float(std::cos(e) * std::cos(a)), float(std::sin(e)), float(std::cos(e) * std::sin(a))}};
    const std::vector<LoadedMaterial> table =
        load_materials(read_material_table(data_dir + "/room.json"));
    const std::vector<MethodParams> methods = table_methods(table);
    FrameRenderer plain(rt, scene, table, methods, res.w, res.h, ShadeSettings{});
    FrameRenderer mapped(rt, scene, table, methods, res.w, res.h, ShadeSettings{});
    ShadowMapSettings settings;
    settings.size = map_size;
    mapped.set_shadow_map(settings);
    // The passes a shadow map needs: G-buffer, the planes' move, reconstruct, offset, depth offset.
    auto passes = [](const PassTimes& t) {
        return t.gbuffer + t.to_device + t.reconstruct + t.offset + t.depth_offset;
    };
    std::vector<double> camera_px, light_px, ratio, light_ms, mask_ms, shade_plain, shade_mapped;
    std::vector<PassTimes> light_each, camera_each;
    for (int round = 0; round < rounds; ++round) {
        const FrameRun p = plain.render(FrameMode::Deferred, false, 1);
        const FrameRun m = mapped.render(FrameMode::Deferred, false, 1);
        const double cam = passes(p.ms) / (double(res.w) * res.h);
        const double light = passes(m.shadow_map_ms) / (double(map_size) * map_size);
        camera_px.push_back(cam * 1e6);
        light_px.push_back(light * 1e6);
        ratio.push_back(light / cam);
        light_ms.push_back(passes(m.shadow_map_ms));
        mask_ms.push_back(m.ms.shadow_mask);
        shade_plain.push_back(p.ms.shade);
        shade_mapped.push_back(m.ms.shade);
        light_each.push_back(m.shadow_map_ms);
        camera_each.push_back(p.ms);
    }
    // Each of those passes' median, the light's and the camera's (ms).
    auto each = [](const std::vector<PassTimes>& times) {
        nlohmann::json j;
        for (const auto& [name, field] : {std::pair{"gbuffer", &PassTimes::gbuffer},
                                          {"to_device", &PassTimes::to_device},
                                          {"reconstruct", &PassTimes::reconstruct},
                                          {"offset", &PassTimes::offset},
                                          {"depth_offset", &PassTimes::depth_offset}}) {
            std::vector<double> v;
            for (const PassTimes& t : times) v.push_back(t.*field);
            j[name] = median(v);
        }
        return j;
    };
    nlohmann::json out = {{"resolution", {res.w, res.h}},
                          {"map_size", map_size},
                          {"rounds", rounds},
                          {"sun_deg", {20.0, 60.0}},
                          {"camera_ns_per_pixel", median(camera_px)},
                          {"light_ns_per_pixel", median(light_px)},
                          {"light_over_camera_per_pixel", median(ratio)},
                          {"light_passes_ms", median(light_ms)},
                          {"light_passes", each(light_each)},
                          {"camera_passes", each(camera_each)},
                          {"receivers_test_ms", median(mask_ms)},
                          {"shade_ms", median(shade_plain)},
                          {"shade_with_mask_ms", median(shade_mapped)}};
    std::printf(
        "\nthe room under a sun at 20 degrees, %dx%d with a %d^2 displaced shadow map (medians of "
        "%d rounds in turns):\n  light's passes %.1f ms, %.1f ns a map pixel; camera's %.1f ns a "
        "frame pixel: %.2fx a pixel\n  receivers' test %.2f ms; shade %.2f ms without the mask, "
        "%.2f ms with it\n",
        res.w, res.h, map_size, rounds, out["light_passes_ms"].get<double>(),
        out["light_ns_per_pixel"].get<double>(), out["camera_ns_per_pixel"].get<double>(),
        out["light_over_camera_per_pixel"].get<double>(), out["receivers_test_ms"].get<double>(),
        out["shade_ms"].get<double>(), out["shade_with_mask_ms"].get<double>());
    return out;
}

nlohmann::json bench_triplanar_frame(std::shared_ptr<Runtime> rt, const Resolution& res,
                                     const std::string& data_dir, int rounds) {
    const std::string table_file = data_dir + "/terrain.json";
    const std::vector<MaterialSpec> specs = read_material_table(table_file);
    const Scene projected = load_gltf_scene(data_dir + "/terrain.gltf", specs, table_file);
    const std::vector<LoadedMaterial> table = load_materials(specs);
    const std::vector<MethodParams> methods = table_methods(table);
    // The same meshes with uv = world_scale (x, -z), tangents from it, and no projection.
    Scene mapped = projected;
    std::vector<LoadedMaterial> plain = table;
    for (LoadedMaterial& m : plain) m.spec.triplanar.enabled = false;
    for (Mesh& mesh : mapped.meshes) {
        float scale = 1.0f;
        for (const LoadedMaterial& m : table)
            if (m.spec.id == mesh.material) scale = m.spec.triplanar.world_scale;
        for (Vertex& v : mesh.vertices) v.uv = {scale * v.position[0], -scale * v.position[2]};
        derive_tangents(mesh);
    }
    FrameRenderer tri(rt, projected, table, methods, res.w, res.h, ShadeSettings{});
    FrameRenderer uv(rt, mapped, plain, methods, res.w, res.h, ShadeSettings{});
    std::vector<std::vector<double> > a(10), b(10);
    std::array<size_t, 3> projections{};
    for (int round = 0; round <= rounds; ++round) {
        const FrameRun t = tri.render(FrameMode::Deferred, false, 1);
        const FrameRun u = uv.render(FrameMode::Deferred, false, 1);
        projections = t.projections;
        if (round == 0) continue;  // warms both up
        const std::vector<double> vt = pass_values(t), vu = pass_values(u);
        for (size_t p = 0; p < vt.size(); ++p) {
            a[p].push_back(vt[p]);
            b[p].push_back(vu[p]);
        }
    }
    auto ratio = [&](size_t pass) {
        std::vector<double> q;
        for (size_t k = 0; k < a[pass].size(); ++k) q.push_back(a[pass][k] / b[pass][k]);
        return median(q);
    };
    nlohmann::json rows = nlohmann::json::array();
    std::printf(
        "\nthe terrain at %s (%dx%d; GL: %s), medians of %d frames each in turns, ms\n  %-10s "
        "%8s %8s %8s %8s %8s %8s %8s\n",
        res.name, res.w, res.h, tri.gl_renderer().c_str(), rounds, "frame", "G-buffer", "to CL",
        "reconstr", "offset", "off kern", "shade", "total");
    for (const auto& [name, v] : {std::pair{"triplanar", &a}, {"uv-mapped", &b}}) {
        nlohmann::json row = {{"frame", name}};
        std::vector<double> med;
        for (size_t p = 0; p < 10; ++p) {
            med.push_back(median((*v)[p]));
            row[std::string(kPasses[p]) + "_ms"] = med.back();
        }
        std::printf("  %-10s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f\n", name, med[0], med[1],
                    med[2], med[3], med[4], med[5], med[9]);
        rows.push_back(row);
    }
    const double all = double(projections[0] + projections[1] + projections[2]);
    nlohmann::json out = {{"resolution", {res.w, res.h}},
                          {"rounds", rounds},
                          {"gl_renderer", tri.gl_renderer()},
                          {"rows", rows},
                          {"ratios",
                           {{"total", ratio(9)},
                            {"offset", ratio(3)},
                            {"shade", ratio(5)},
                            {"reconstruct", ratio(2)}}},
                          {"projections",
                           {{"pixels", projections[0] + projections[1] + projections[2]},
                            {"one", all > 0 ? projections[0] / all : 0.0},
                            {"two", all > 0 ? projections[1] / all : 0.0},
                            {"three", all > 0 ? projections[2] / all : 0.0}}}};
    std::printf(
        "  triplanar / uv-mapped: frame %.3f, offset %.3f, shade %.3f, reconstruct %.3f; pixels "
        "traced in one projection %.1f %%, two %.1f %%, three %.1f %%\n",
        ratio(9), ratio(3), ratio(5), ratio(2), 100.0 * out["projections"]["one"].get<double>(),
        100.0 * out["projections"]["two"].get<double>(),
        100.0 * out["projections"]["three"].get<double>());
    return out;
}

#endif

}  // namespace offsetmap::bench
