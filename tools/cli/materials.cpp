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

namespace {

// Options that belong to one material, refused beside a table; every option checked before any
// file is read.
void check_job_options(const MaterialsJob& job, const ReliefOptions& relief,
                       const ShadingOptions& shading, const SceneOptions& scene) {
    scene.check();
    if (relief.settings().lod.enabled)
        throw UsageError("the LOD options do not apply with --materials");
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
}

// The scene's G-buffer with an id a pixel (the table's laid out over it where it has none), every
// id known before anything is traced (auto's calibration included).
GBuffer job_gbuffer(const SceneOptions& scene, const ShadingOptions& shading,
                    const std::vector<MaterialSpec>& specs) {
    GBuffer gb = scene.make();
    if (!gb.has_material()) {
        if (!scene.gbuffer.empty())
            throw Error("G-buffer '" + scene.gbuffer +
                        "' has no 'material' channel: --materials needs each pixel's id");
        std::vector<int> ids;
        for (const auto& s : specs) ids.push_back(s.id);
        lay_out_materials(gb, ids);
    }
    std::set<float> known = {0.0f};
    for (const auto& s : specs) known.insert(static_cast<float>(s.id));
    size_t unknown = 0, first = 0;
    for (size_t k = 0; k < gb.pixels(); ++k)
        if (!known.count(gb.material[k]) && unknown++ == 0) first = k;
    if (unknown) throw Error(unknown_material(gb.material[first], first, gb.width, unknown));
    if (shading.light.size() == 3) gb.light.clear();  // an explicit light wins
    return gb;
}

// What the job's sections share: the table, its G-buffer, each material's method and the frame.
struct JobRun {
    JobRun(const MaterialsJob& job, const SceneOptions& scene, std::vector<LoadedMaterial> table,
           GBuffer gb)
        : job(job), scene(scene), table(std::move(table)), gb(std::move(gb)) {}

    const MaterialsJob& job;
    const SceneOptions& scene;
    std::shared_ptr<Runtime> rt;
    std::vector<LoadedMaterial> table;
    GBuffer gb;
    std::vector<MethodParams> chosen;
    std::vector<AutoChoice> autos;
    DeviceGBuffer dg;
    MaterialFrameRun run;
    OffsetResult exact;
    std::vector<MaterialError> stats;  // against exact
    std::vector<float> err;            // uv error against exact a pixel
};

// Each material's method: its own, or the cheapest within its budget.
void choose_methods(JobRun& j) {
    j.autos.resize(j.table.size());
    for (size_t s = 0; s < j.table.size(); ++s) {
        const MaterialSpec& m = j.table[s].spec;
        if (m.method != "auto") {
            j.chosen.push_back(resolve_params(find_method(m.method), m.params));
            continue;
        }
        const bool terminal = isatty(fileno(stderr));  // a log gets no carriage returns
        if (terminal)
            progress_line("auto: calibrating material " + std::to_string(m.id) + " (" + m.name +
                          ")...");
        try {
            j.autos[s] = choose_method(j.rt, j.table[s], j.gb);
        } catch (...) {
            if (terminal) progress_line("");  // the error's line starts clean
            throw;
        }
        if (terminal) progress_line("");
        j.chosen.push_back(j.autos[s].chosen.params);
    }
}

// The frame shaded, read back (empty when no picture asks for it).
std::vector<cl_float4> shade_frame(JobRun& j, const ShadingOptions& shading) {
    if (j.job.color_out.empty() && j.job.out_dir.empty()) return {};
    const OffsetResult& result = j.run.result;
    const cl::Context& c = j.rt->context();
    const size_t n = j.gb.pixels();
    cl::Buffer uv(c, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float2),
                  const_cast<cl_float2*>(result.uv.data()));
    cl::Buffer flags(c, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_uint),
                     const_cast<std::uint32_t*>(result.flags.data()));
    cl::Buffer out(c, CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
    j.run.pass->shade(j.dg, {uv, flags}, shading.shade_settings(), {out}).wait();
    std::vector<cl_float4> rgba(n);
    j.rt->queue().enqueueReadBuffer(out, CL_TRUE, 0, n * sizeof(cl_float4), rgba.data());
    return rgba;
}

// A row a material: its method, cost and error against exact (printed and frame.json's).
nlohmann::json material_rows(const JobRun& j) {
    const std::vector<MaterialError>& stats = j.stats;
    const std::vector<double> ns = material_ns_per_pixel(*j.rt, *j.run.pass, j.gb, j.job.repeats);
    std::printf("%4s %-12s %-56s %8s %8s %8s %9s %9s\n", "id", "material", "method", "pixels",
                "ns/px", "fetches", "mean err", "p95 err");
    nlohmann::json rows = nlohmann::json::array();
    for (size_t s = 0; s < j.table.size(); ++s) {
        const MaterialError& m = stats[s];
        const std::string method = method_text(j.chosen[s]);
        std::printf("%4d %-12s %-56s %8zu %8.2f %8.2f %9.4f %9.4f\n", j.table[s].spec.id,
                    j.table[s].spec.name.c_str(), method.c_str(), m.pixels, ns[s], m.fetches,
                    m.error.mean, m.error.p95);
        rows.push_back({{"id", j.table[s].spec.id},
                        {"name", j.table[s].spec.name},
                        {"method", method},
                        {"auto", j.table[s].spec.method == "auto"},
                        {"pixels", m.pixels},
                        {"traced", m.traced},
                        {"ns_per_pixel", ns[s]},
                        {"fetches_per_pixel", m.fetches},
                        {"mean_err_texels", m.error.mean},
                        {"p95_err_texels", m.error.p95},
                        {"max_err_texels", m.error.max}});
    }
    return rows;
}

nlohmann::json dispatch_rows(const Runtime& rt,
                             const std::vector<MaterialFrame::Dispatch>& dispatches) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& d : dispatches) {
        const double ms = rt.profiling() ? event_ms(d.event) : 0.0;
        std::printf("  dispatch %-10s %6zu tiles (%zu work-items) %9.3f ms\n",
                    d.method->name.c_str(), d.entries, d.work_items, ms);
        rows.push_back({{"method", d.method->name},
                        {"tiles", d.entries},
                        {"work_items", d.work_items},
                        {"ms", ms}});
    }
    return rows;
}

// --explain: why each material got its method.
void explain_choices(const JobRun& j) {
    for (size_t s = 0; s < j.table.size(); ++s) {
        const MaterialSpec& m = j.table[s].spec;
        std::printf("material %d (%s): ", m.id, m.name.c_str());
        if (m.method != "auto") {
            std::printf("%s, as the table names it\n", method_text(j.chosen[s]).c_str());
            continue;
        }
        const AutoChoice& a = j.autos[s];
        const char* stat = budget_statistic_name(m.budget);
        auto describe = [&](const AutoCandidate& c) {
            char text[256];
            std::snprintf(text, sizeof text, "%s: %s %.3f texels, %.1f ns/pixel, %.1f fetches",
                          method_text(c.params).c_str(), stat, budget_statistic(m.budget, c.error),
                          c.ns_per_pixel, c.fetches);
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

// A sweep record's setting as parameters.
MethodParams record_params(const SweepRecord& r) {
    for (const MethodInfo& info : methods())
        for (const auto& setting : info.sweep)
            if (info.name == r.method && describe_setting(setting) == r.setting)
                return resolve_params(info, setting);
    return resolve_params(find_method(r.method), {});
}

nlohmann::json sweep_rows(const std::vector<SweepRecord>& records) {
    nlohmann::json all = nlohmann::json::array();
    for (const SweepRecord& r : records)
        all.push_back({{"method", r.method},
                       {"setting", r.setting},
                       {"worst_material_p95", r.worst_material_p95},
                       {"p95_err_texels", r.uv.p95},
                       {"mean_err_texels", r.uv.mean},
                       {"fetches_per_pixel", r.fetches_mean},
                       {"kernel_ms", r.kernel_ms}});
    return all;
}

// The cheapest single method for the whole frame that keeps every material within the table's
// worst-material p95, among the settings auto may choose (precomputed data within its bound).
nlohmann::json single_method_section(JobRun& j) {
    const bool terminal = isatty(fileno(stderr));
    const AutoOptions bound;
    const auto records = sweep_material_frame(
        j.rt, j.table, j.chosen, j.gb, j.scene.describe(), j.job.repeats,
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
        const MethodParams one = record_params(*best);
        MaterialFrame single(
            j.rt, upload_materials(*j.rt, j.table, std::vector<MethodParams>(j.table.size(), one)),
            j.job.tile_rows);
        const auto ms =
            time_frames_in_turns(*j.rt, {j.run.pass.get(), &single}, j.dg, 2 * j.job.repeats + 1);
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
    return {{"per_material_ms", mix_ms},
            {"worst_material_p95", mix.worst_material_p95},
            {"best_single", best ? nlohmann::json{{"method", best->method},
                                                  {"setting", best->setting},
                                                  {"kernel_ms", best_ms},
                                                  {"worst_material_p95", best->worst_material_p95}}
                                 : nlohmann::json()},
            {"cases", sweep_rows(records)}};
}

// Per pixel the index of its material in the table and of its method among the chosen ones (-1
// where none), and those methods.
struct PixelIndex {
    std::vector<int> id, method;
    std::vector<const MethodInfo*> methods;
};
PixelIndex pixel_index(const JobRun& j) {
    PixelIndex x{std::vector<int>(j.gb.pixels(), -1), std::vector<int>(j.gb.pixels(), -1), {}};
    for (const auto& p : j.chosen)
        if (std::find(x.methods.begin(), x.methods.end(), p.method) == x.methods.end())
            x.methods.push_back(p.method);
    for (size_t k = 0; k < j.gb.pixels(); ++k)
        for (size_t s = 0; s < j.table.size(); ++s)
            if (j.gb.material[k] == static_cast<float>(j.table[s].spec.id)) {
                x.id[k] = static_cast<int>(s);
                x.method[k] = static_cast<int>(
                    std::find(x.methods.begin(), x.methods.end(), j.chosen[s].method) -
                    x.methods.begin());
            }
    return x;
}

// The files the options name; with --out the frame, its sheet (the ids, the method per pixel,
// the error against exact) and materials.json.
void write_job_files(const JobRun& j, const std::vector<cl_float4>& rgba, nlohmann::json doc) {
    const MaterialsJob& job = j.job;
    const int w = j.gb.width, h = j.gb.height;
    const PixelIndex x = pixel_index(j);
    if (!job.uv_out.empty()) write_uv_exr(job.uv_out, j.run.result);
    if (!job.color_out.empty()) write_image(job.color_out, to_srgb8(w, h, rgba));
    if (!job.error_out.empty()) write_image(job.error_out, heat_map(w, h, j.err, 16.0f));
    if (!job.ids_out.empty()) write_image(job.ids_out, index_image(w, h, x.id));
    if (job.out_dir.empty()) return;
    const std::string d = job.out_dir + "/materials";
    std::string ids_label = "ids:", methods_label = "method per pixel:";
    for (size_t s = 0; s < j.table.size(); ++s)
        ids_label += std::string(s ? "," : "") + " " + kPaletteNames[s % 8] + " " +
                     std::to_string(j.table[s].spec.id) + " " + j.table[s].spec.name;
    for (size_t k = 0; k < x.methods.size(); ++k)
        methods_label +=
            std::string(k ? "," : "") + " " + kPaletteNames[k % 8] + " " + x.methods[k]->name;
    std::vector<std::pair<std::string, Rgb8>> tiles = {
        {"the frame, each material its own method", to_srgb8(w, h, rgba)},
        {ids_label, index_image(w, h, x.id)},
        {methods_label, index_image(w, h, x.method)},
        {"uv error vs exact (log, white = 16 texels)", heat_map(w, h, j.err, 16.0f)}};
    write_image(d + "-frame.png", tiles[0].second);
    write_image(d + "-sheet.png", contact_sheet(tiles, 2));
    std::ofstream(d + ".json") << doc.dump(2) << "\n";
    std::printf("wrote %s-{frame,sheet}.png, %s.json\n", d.c_str(), d.c_str());
}

}  // namespace

int run_materials_job(const MaterialsJob& job, const ReliefOptions& relief,
                      const ShadingOptions& shading, const SceneOptions& scene) {
    check_job_options(job, relief, shading, scene);
    const std::vector<MaterialSpec> specs = read_material_table(job.table, relief.settings());
    std::vector<LoadedMaterial> table = load_materials(specs);
    JobRun j(job, scene, std::move(table), job_gbuffer(scene, shading, specs));
    if (!job.out_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(job.out_dir, ec);
        if (ec) throw Error("cannot create output folder '" + job.out_dir + "': " + ec.message());
    }
    j.rt = Runtime::create(relief.device);
    show_progress(*j.rt);
    choose_methods(j);
    j.dg = upload(*j.rt, j.gb);
    j.run = run_materials(j.rt, j.table, j.chosen, j.dg, job.tile_rows, job.repeats);
    MaterialFrame& frame = *j.run.pass;
    const std::vector<MaterialFrame::Dispatch> dispatches = frame.dispatches();  // before reruns
    const double classify_ms = j.rt->profiling() ? event_ms(frame.classify_event()) : 0.0;
    const double frame_ms = j.run.result.median_kernel_ms();
    const std::vector<cl_float4> rgba = shade_frame(j, shading);
    // The same frame with every material traced exactly: the reference.
    j.exact = run_materials_exact(j.rt, frame, j.dg);
    j.stats = material_errors(j.gb, j.run.result, j.exact, j.table, &j.err);
    std::printf(
        "materials (%s) on %s: %s %dx%d, %zu materials, tiles %dx%d, %s "
        "(classification %.3f ms)\n",
        job.table.c_str(), j.rt->device_name().c_str(), scene.describe().c_str(), j.gb.width,
        j.gb.height, j.table.size(), OM_TILE_W, job.tile_rows, kernel_time_text(frame_ms).c_str(),
        classify_ms);
    nlohmann::json doc = {{"device", j.rt->device_name()},
                          {"table", job.table},
                          {"gbuffer_source", scene.describe()},
                          {"width", j.gb.width},
                          {"height", j.gb.height},
                          {"tile", {OM_TILE_W, job.tile_rows}},
                          {"frame_ms", frame_ms},
                          {"classify_ms", classify_ms},
                          {"materials", material_rows(j)},
                          {"dispatches", dispatch_rows(*j.rt, dispatches)},
                          {"single_method", nlohmann::json()}};
    if (job.explain) explain_choices(j);
    if (job.compare_single || !job.out_dir.empty()) doc["single_method"] = single_method_section(j);
    write_job_files(j, rgba, doc);
    return 0;
}

}  // namespace offsetmap::cli
