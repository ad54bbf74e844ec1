// `offsetmap render --materials FILE.json`: a frame of many materials (tiles, one dispatch per
// method, `auto` by error budget), its table against exact, and the demo's material frame.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "cli.hpp"

namespace offsetmap::cli {

namespace {

// Distinct colours for ids and methods in the pictures (cycled, named in the labels); id 0 and
// empty pixels are dark grey.
const std::uint8_t kPalette[][3] = {{230, 159, 0},   {86, 180, 233}, {0, 158, 115},
                                    {240, 228, 66},  {0, 114, 178},  {213, 94, 0},
                                    {204, 121, 167}, {150, 150, 150}};

const char* const kPaletteNames[] = {"orange", "sky", "green", "yellow",
                                     "blue",   "red", "pink",  "grey"};

Rgb8 index_image(int w, int h, const std::vector<int>& index) {
    Rgb8 img;
    img.width = w;
    img.height = h;
    img.rgb.resize(static_cast<size_t>(w) * h * 3);
    for (size_t k = 0; k < index.size(); ++k) {
        const int i = index[k];
        for (int c = 0; c < 3; ++c) img.rgb[3 * k + c] = i < 0 ? 40 : kPalette[i % 8][c];
    }
    return img;
}

}  // namespace

std::string method_text(const MethodParams& p) {
    std::string s = p.method->name;
    for (size_t k = 0; k < p.values.size(); ++k) {
        char v[32];
        std::snprintf(v, sizeof v, "%g", p.values[k]);
        s += " " + p.method->params[k].name + "=" + v;
    }
    return s;
}

std::string kernel_time_text(double ms) {
    if (!std::isfinite(ms)) return "kernel not timed (the device's profiling timer is not a clock)";
    char text[48];
    std::snprintf(text, sizeof text, "kernel %.3f ms", ms);
    return text;
}

int run_materials_job(const MaterialsJob& job, const ReliefOptions& relief,
                      const ShadingOptions& shading, const SceneOptions& scene) {
    // Every option checked before any file is read.
    scene.check();
    const PassSettings defaults = relief.settings();
    if (defaults.lod.enabled) throw UsageError("the LOD options do not apply with --materials");
    for (const auto& [given, what] : {std::pair{!relief.height_map.empty(), "--height-map"},
                                      {relief.depth_map, "--depth-map"},
                                      {relief.channel != 0, "--channel"},
                                      {!shading.normal_map.empty(), "--normal-map"},
                                      {!shading.albedo.empty(), "--albedo"},
                                      {shading.flip_green, "--flip-green"}})
        if (given)
            throw UsageError(std::string(what) +
                             " belongs to one material: with --materials each entry of the "
                             "table gives its own");
    if (job.color_out.empty() && job.out_dir.empty() && !shading.first_given().empty())
        throw UsageError(shading.first_given() +
                         " changes only the shaded image: add --color-out FILE");

    const std::vector<MaterialSpec> specs = read_material_table(job.table, defaults);
    const std::vector<LoadedMaterial> table = load_materials(specs);
    GBuffer gb = scene.make();
    if (!gb.has_material()) {
        if (!scene.gbuffer.empty())
            throw Error("G-buffer '" + scene.gbuffer +
                        "' has no 'material' channel: --materials needs each pixel's id");
        std::vector<int> ids;
        for (const auto& s : specs) ids.push_back(s.id);
        lay_out_materials(gb, ids);
    }
    {  // every id known before anything is traced (auto's calibration included)
        std::set<float> known = {0.0f};
        for (const auto& s : specs) known.insert(static_cast<float>(s.id));
        size_t unknown = 0, first = 0;
        for (size_t k = 0; k < gb.pixels(); ++k)
            if (!known.count(gb.material[k]) && unknown++ == 0) first = k;
        if (unknown) throw Error(unknown_material(gb.material[first], first, gb.width, unknown));
    }
    if (shading.light.size() == 3) gb.light.clear();  // an explicit light wins
    if (!job.out_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(job.out_dir, ec);
        if (ec) throw Error("cannot create output folder '" + job.out_dir + "': " + ec.message());
    }

    auto rt = Runtime::create(relief.device);
    show_progress(*rt);
    // Each material's method: its own, or the cheapest within its budget.
    std::vector<MethodParams> chosen;
    std::vector<AutoChoice> autos(table.size());
    for (size_t s = 0; s < table.size(); ++s) {
        const MaterialSpec& m = table[s].spec;
        if (m.method != "auto") {
            chosen.push_back(resolve_params(find_method(m.method), m.params));
            continue;
        }
        const bool terminal = isatty(fileno(stderr));  // a log gets no carriage returns
        if (terminal)
            progress_line("auto: calibrating material " + std::to_string(m.id) + " (" + m.name +
                          ")...");
        try {
            autos[s] = choose_method(rt, table[s], gb);
        } catch (...) {
            if (terminal) progress_line("");  // the error's line starts clean
            throw;
        }
        if (terminal) progress_line("");
        chosen.push_back(autos[s].chosen.params);
    }

    DeviceGBuffer dg = upload(*rt, gb);
    const MaterialFrameRun run = run_materials(rt, table, chosen, dg, job.tile_rows, job.repeats);
    const OffsetResult& result = run.result;
    MaterialFrame* frame = run.pass.get();
    const std::vector<MaterialFrame::Dispatch> dispatches = frame->dispatches();  // before reruns
    const double classify_ms = rt->profiling() ? event_ms(frame->classify_event()) : 0.0;
    const double frame_ms = result.median_kernel_ms();
    std::vector<cl_float4> rgba;
    if (!job.color_out.empty() || !job.out_dir.empty()) {
        const size_t n = gb.pixels();
        cl::Buffer uv(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float2),
                      const_cast<cl_float2*>(result.uv.data()));
        cl::Buffer flags(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                         n * sizeof(cl_uint), const_cast<std::uint32_t*>(result.flags.data()));
        cl::Buffer out(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
        frame->shade(uv, flags, dg, shading.shade_settings(), out).wait();
        rgba.resize(n);
        rt->queue().enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(cl_float4), rgba.data());
    }
    // The same frame with every material traced exactly: the reference.
    const OffsetResult exact = run_materials_exact(rt, *frame, dg);
    std::vector<float> err;
    const std::vector<MaterialError> stats = material_errors(gb, result, exact, table, &err);
    const std::vector<double> ns = material_ns_per_pixel(*rt, *frame, gb, job.repeats);

    std::printf(
        "materials (%s) on %s: %s %dx%d, %zu materials, tiles %dx%d, %s "
        "(classification %.3f ms)\n",
        job.table.c_str(), rt->device_name().c_str(), scene.describe().c_str(), gb.width, gb.height,
        table.size(), OM_TILE_W, job.tile_rows, kernel_time_text(frame_ms).c_str(), classify_ms);
    std::printf("%4s %-12s %-56s %8s %8s %8s %9s %9s\n", "id", "material", "method", "pixels",
                "ns/px", "fetches", "mean err", "p95 err");
    nlohmann::json rows = nlohmann::json::array();
    for (size_t s = 0; s < table.size(); ++s) {
        const MaterialError& m = stats[s];
        const std::string method = method_text(chosen[s]);
        std::printf("%4d %-12s %-56s %8zu %8.2f %8.2f %9.4f %9.4f\n", table[s].spec.id,
                    table[s].spec.name.c_str(), method.c_str(), m.pixels, ns[s], m.fetches,
                    m.error.mean, m.error.p95);
        rows.push_back({{"id", table[s].spec.id},
                        {"name", table[s].spec.name},
                        {"method", method},
                        {"auto", table[s].spec.method == "auto"},
                        {"pixels", m.pixels},
                        {"traced", m.traced},
                        {"ns_per_pixel", ns[s]},
                        {"fetches_per_pixel", m.fetches},
                        {"mean_err_texels", m.error.mean},
                        {"p95_err_texels", m.error.p95},
                        {"max_err_texels", m.error.max}});
    }
    nlohmann::json djson = nlohmann::json::array();
    for (const auto& d : dispatches) {
        const double ms = rt->profiling() ? event_ms(d.event) : 0.0;
        std::printf("  dispatch %-10s %6zu tiles (%zu work-items) %9.3f ms\n",
                    d.method->name.c_str(), d.entries, d.work_items, ms);
        djson.push_back({{"method", d.method->name},
                         {"tiles", d.entries},
                         {"work_items", d.work_items},
                         {"ms", ms}});
    }
    if (job.explain) {
        for (size_t s = 0; s < table.size(); ++s) {
            const MaterialSpec& m = table[s].spec;
            std::printf("material %d (%s): ", m.id, m.name.c_str());
            if (m.method != "auto") {
                std::printf("%s, as the table names it\n", method_text(chosen[s]).c_str());
                continue;
            }
            const AutoChoice& a = autos[s];
            const char* stat = budget_statistic_name(m.budget);
            auto describe = [&](const AutoCandidate& c) {
                char text[256];
                std::snprintf(text, sizeof text, "%s: %s %.3f texels, %.1f ns/pixel, %.1f fetches",
                              method_text(c.params).c_str(), stat,
                              budget_statistic(m.budget, c.error), c.ns_per_pixel, c.fetches);
                return std::string(text);
            };
            std::printf("auto, %s <= %g texels -> %s\n", stat, m.budget.texels,
                        describe(a.chosen).c_str());
            std::printf("    runner-up: %s\n",
                        a.runner_up.params.method ? describe(a.runner_up).c_str() : "none");
            std::printf(
                "    %zu candidates on %zu of its pixels (%zu against the exact hit), cheapest by "
                "%s%s; %zu not tried (precomputed data over 4x the map's pyramid)\n",
                a.candidates.size(), a.pixels, a.samples, a.by_time ? "kernel time" : "fetches",
                a.cached ? "; from the cache" : "", a.skipped);
        }
    }

    // The cheapest single method for the whole frame that keeps every material within the
    // table's worst-material p95.
    nlohmann::json single;
    if (job.compare_single || !job.out_dir.empty()) {
        const bool terminal = isatty(fileno(stderr));
        // Among the settings auto may choose: precomputed data within its bound.
        const AutoOptions bound;
        const auto records = sweep_material_frame(
            rt, table, chosen, gb, scene.describe(), job.repeats,
            [&](const std::string& line) {
                if (terminal) progress_line(line);
            },
            {}, &bound);
        if (terminal) progress_line("");
        const SweepRecord& mix = records.front();
        const SweepRecord* best = nullptr;
        for (const SweepRecord& r : records)
            if (r.method != "per-material" && r.worst_material_p95 <= mix.worst_material_p95 &&
                (!best || r.kernel_ms < best->kernel_ms))
                best = &r;
        // The two frames again, timed in turns: their ratio shares the machine's load.
        double mix_ms = mix.kernel_ms, best_ms = best ? best->kernel_ms : 0.0;
        if (best) {
            MethodParams one;
            for (const MethodInfo& info : methods())
                for (const auto& setting : info.sweep)
                    if (info.name == best->method && describe_setting(setting) == best->setting)
                        one = resolve_params(info, setting);
            if (!one.method) one = resolve_params(find_method(best->method), {});
            MaterialFrame single(
                rt, upload_materials(*rt, table, std::vector<MethodParams>(table.size(), one)),
                job.tile_rows);
            const auto ms = time_frames_in_turns(*rt, {frame, &single}, dg, 2 * job.repeats + 1);
            mix_ms = ms[0], best_ms = ms[1];
        }
        std::printf("per-material methods: worst material p95 %.4f texels, %.3f ms\n",
                    mix.worst_material_p95, mix_ms);
        if (best)
            std::printf(
                "best single method at that error: %s %s, worst material p95 %.4f, %.3f ms "
                "(%.2fx the per-material frame's time; the two timed in turns)\n",
                best->method.c_str(), best->setting.c_str(), best->worst_material_p95, best_ms,
                best_ms / mix_ms);
        else
            std::printf("no single method reaches that error on every material\n");
        nlohmann::json all = nlohmann::json::array();
        for (const SweepRecord& r : records)
            all.push_back({{"method", r.method},
                           {"setting", r.setting},
                           {"worst_material_p95", r.worst_material_p95},
                           {"p95_err_texels", r.uv.p95},
                           {"mean_err_texels", r.uv.mean},
                           {"fetches_per_pixel", r.fetches_mean},
                           {"kernel_ms", r.kernel_ms}});
        single = {
            {"per_material_ms", mix_ms},
            {"worst_material_p95", mix.worst_material_p95},
            {"best_single", best ? nlohmann::json{{"method", best->method},
                                                  {"setting", best->setting},
                                                  {"kernel_ms", best_ms},
                                                  {"worst_material_p95", best->worst_material_p95}}
                                 : nlohmann::json()},
            {"cases", all}};
    }

    // Pictures: the frame, the ids, the method per pixel, the error against exact.
    std::vector<int> id_index(gb.pixels(), -1), method_index(gb.pixels(), -1);
    std::vector<const MethodInfo*> method_list;
    for (const auto& p : chosen)
        if (std::find(method_list.begin(), method_list.end(), p.method) == method_list.end())
            method_list.push_back(p.method);
    for (size_t k = 0; k < gb.pixels(); ++k)
        for (size_t s = 0; s < table.size(); ++s)
            if (gb.material[k] == static_cast<float>(table[s].spec.id)) {
                id_index[k] = static_cast<int>(s);
                method_index[k] = static_cast<int>(
                    std::find(method_list.begin(), method_list.end(), chosen[s].method) -
                    method_list.begin());
            }
    if (!job.uv_out.empty()) write_uv_exr(job.uv_out, result);
    if (!job.color_out.empty()) write_image(job.color_out, to_srgb8(gb.width, gb.height, rgba));
    if (!job.error_out.empty())
        write_image(job.error_out, heat_map(gb.width, gb.height, err, 16.0f));
    if (!job.ids_out.empty()) write_image(job.ids_out, index_image(gb.width, gb.height, id_index));
    if (!job.out_dir.empty()) {
        const std::string d = job.out_dir + "/materials";
        std::string ids_label = "ids:", methods_label = "method per pixel:";
        for (size_t s = 0; s < table.size(); ++s)
            ids_label += std::string(s ? "," : "") + " " + kPaletteNames[s % 8] + " " +
                         std::to_string(table[s].spec.id) + " " + table[s].spec.name;
        for (size_t k = 0; k < method_list.size(); ++k)
            methods_label +=
                std::string(k ? "," : "") + " " + kPaletteNames[k % 8] + " " + method_list[k]->name;
        std::vector<std::pair<std::string, Rgb8>> tiles = {
            {"the frame, each material its own method", to_srgb8(gb.width, gb.height, rgba)},
            {ids_label, index_image(gb.width, gb.height, id_index)},
            {methods_label, index_image(gb.width, gb.height, method_index)},
            {"uv error vs exact (log, white = 16 texels)",
             heat_map(gb.width, gb.height, err, 16.0f)}};
        write_image(d + "-frame.png", tiles[0].second);
        write_image(d + "-sheet.png", contact_sheet(tiles, 2));
        nlohmann::json doc = {{"device", rt->device_name()},
                              {"table", job.table},
                              {"gbuffer_source", scene.describe()},
                              {"width", gb.width},
                              {"height", gb.height},
                              {"tile", {OM_TILE_W, job.tile_rows}},
                              {"frame_ms", frame_ms},
                              {"classify_ms", classify_ms},
                              {"materials", rows},
                              {"dispatches", djson},
                              {"single_method", single}};
        std::ofstream(d + ".json") << doc.dump(2) << "\n";
        std::printf("wrote %s-{frame,sheet}.png, %s.json\n", d.c_str(), d.c_str());
    }
    return 0;
}

}  // namespace offsetmap::cli
