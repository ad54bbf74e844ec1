// A material frame measured against the exact hit, and as a sweep case.
#include "offsetmap/material_eval.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "offsetmap/registry.hpp"
#include "offsetmap/timing.hpp"

namespace offsetmap {

MaterialFrameRun run_materials(std::shared_ptr<Runtime> rt,
                               const std::vector<LoadedMaterial>& table,
                               const std::vector<MethodParams>& methods, const DeviceGBuffer& g,
                               int tile_rows, int repeats) {
    MaterialFrameRun run;
    run.pass =
        std::make_unique<MaterialFrame>(rt, upload_materials(*rt, table, methods), tile_rows);
    run.result = run_material_frame(*rt, *run.pass, g, repeats + 1);
    auto& ms = run.result.kernel_ms;
    if (!ms.empty()) ms.erase(ms.begin());  // the first includes PoCL's JIT
    return run;
}

OffsetResult run_materials_exact(std::shared_ptr<Runtime> rt,
                                 const std::vector<LoadedMaterial>& table, const DeviceGBuffer& g) {
    const std::vector<MethodParams> exact(table.size(), resolve_params(find_method("exact"), {}));
    return run_materials(rt, table, exact, g, kDefaultTileRows, 0).result;
}

OffsetResult run_materials_exact(std::shared_ptr<Runtime> rt, const MaterialFrame& frame,
                                 const DeviceGBuffer& g) {
    std::vector<FrameMaterial> materials = frame.materials();
    for (FrameMaterial& m : materials) m.params = resolve_params(find_method("exact"), {});
    MaterialFrame exact(rt, std::move(materials));
    return run_material_frame(*rt, exact, g, 1);
}

std::vector<MaterialError> material_errors(const GBuffer& gb, const OffsetResult& r,
                                           const OffsetResult& exact,
                                           const std::vector<LoadedMaterial>& table,
                                           std::vector<float>* per_pixel) {
    std::vector<MaterialError> out(table.size());
    if (per_pixel) per_pixel->assign(gb.pixels(), std::numeric_limits<float>::quiet_NaN());
    std::vector<float> err;
    for (size_t s = 0; s < table.size(); ++s) {
        const float id = static_cast<float>(table[s].spec.id);
        MaterialError& m = out[s];
        for (size_t k = 0; k < gb.pixels(); ++k) {
            if (gb.material[k] != id) continue;
            ++m.pixels;
            if (!traced(r.flags[k])) continue;
            ++m.traced;
            m.fetches += r.fetches[k];
        }
        if (m.traced) m.fetches /= static_cast<double>(m.traced);
        m.error = uv_error(r, exact, table[s].map.width, table[s].map.height, &err,
                           [&](size_t k) { return gb.material[k] == id; });
        if (per_pixel)
            for (size_t k = 0; k < err.size(); ++k)
                if (gb.material[k] == id) (*per_pixel)[k] = err[k];
    }
    return out;
}

std::vector<double> time_frames_in_turns(Runtime& rt, const std::vector<MaterialFrame*>& frames,
                                         const DeviceGBuffer& g, int rounds) {
    std::vector<double> out(frames.size(), 0.0);
    if (!rt.profiling()) return out;
    OffsetTargets t;
    t.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, g.pixels() * sizeof(cl_float2));
    std::vector<std::vector<double>> ms(frames.size());
    for (int r = 0; r <= std::max(1, rounds); ++r)
        for (size_t f = 0; f < frames.size(); ++f) {
            frames[f]->enqueue(g, t).wait();
            if (r == 0) continue;  // the warm-up round
            ms[f].push_back(frames[f]->kernel_ms());
        }
    for (size_t f = 0; f < frames.size(); ++f) out[f] = median(ms[f]);
    return out;
}

std::vector<double> material_ns_per_pixel(Runtime& rt, MaterialFrame& frame, const GBuffer& gb,
                                          int repeats) {
    const auto& table = frame.materials();
    std::vector<double> out(table.size(), 0.0);
    if (!rt.profiling()) return out;
    OffsetTargets t;
    t.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, gb.pixels() * sizeof(cl_float2));
    // Each material alone (every other pixel id 0), the materials timed in turns.
    std::vector<DeviceGBuffer> alone(table.size());
    std::vector<size_t> pixels(table.size(), 0);
    for (size_t s = 0; s < table.size(); ++s) {
        GBuffer only = gb;
        const float id = static_cast<float>(table[s].id);
        for (float& m : only.material) {
            if (m != id) m = 0.0f;
            pixels[s] += m == id;
        }
        if (pixels[s]) alone[s] = upload(rt, only);
    }
    std::vector<std::vector<double>> ms(table.size());
    for (int r = 0; r <= std::max(1, repeats); ++r)
        for (size_t s = 0; s < table.size(); ++s) {
            if (!pixels[s]) continue;
            frame.enqueue(alone[s], t).wait();
            if (r > 0) ms[s].push_back(event_ms(frame.dispatches().at(0).event));  // r = 0: warm-up
        }
    for (size_t s = 0; s < table.size(); ++s) {
        if (!ms[s].empty()) out[s] = median(ms[s]) * 1e6 / static_cast<double>(pixels[s]);
    }
    return out;
}

std::vector<SweepRecord> sweep_material_frame(
    std::shared_ptr<Runtime> rt, const std::vector<LoadedMaterial>& table,
    const std::vector<MethodParams>& chosen, const GBuffer& gb, const std::string& views_name,
    int repeats, const std::function<void(const std::string&)>& progress,
    const std::vector<std::string>& only, const AutoOptions* bound) {
    DeviceGBuffer g = upload(*rt, gb);
    const OffsetResult exact = run_materials_exact(rt, table, g);
    std::vector<std::pair<std::string, std::vector<MethodParams>>> cases;
    cases.emplace_back("per-material", chosen);
    for (const MethodInfo* m : select_methods(only)) {
        const MethodInfo& info = *m;
        auto grid =
            info.sweep.empty() ? std::vector<std::map<std::string, std::string>>{{}} : info.sweep;
        for (const auto& setting : grid) {
            bool within = true;
            for (const auto& t : table)
                within = within && (!bound || precomputed_within_bound(info, setting, t.map,
                                                                       t.spec.settings, *bound));
            if (!within) continue;
            cases.emplace_back(
                info.name + " " + describe_setting(setting),
                std::vector<MethodParams>(table.size(), resolve_params(info, setting)));
        }
    }
    std::vector<SweepRecord> out;
    for (size_t c = 0; c < cases.size(); ++c) {
        const auto& [name, methods_of] = cases[c];
        MaterialFrameRun run = run_materials(rt, table, methods_of, g, kDefaultTileRows, repeats);
        std::vector<float> per_pixel;
        const auto errors = material_errors(gb, run.result, exact, table, &per_pixel);
        SweepRecord rec;
        if (c == 0) {
            rec.method = "per-material";
            rec.setting = "the table's methods";
        } else {
            rec.method = methods_of[0].method->name;
            rec.setting = name.substr(rec.method.size() + 1);
        }
        rec.map = "materials";
        rec.views = views_name;
        std::vector<double> pooled;  // every material's pixels, each in its own texels
        for (float e : per_pixel)
            if (!std::isnan(e)) pooled.push_back(e);
        rec.uv = error_stats(std::move(pooled));
        for (const auto& e : errors)
            rec.worst_material_p95 = std::max(rec.worst_material_p95, e.error.p95);
        rec.fetches_mean = mean_fetches(run.result);
        rec.fetches_max = max_fetches(run.result);
        rec.kernel_ms = run.result.median_kernel_ms();
        rec.ns_per_pixel = rec.kernel_ms * 1e6 / static_cast<double>(gb.pixels());
        out.push_back(rec);
        if (progress)
            progress("[" + std::to_string(c + 1) + "/" + std::to_string(cases.size()) +
                     "] materials / " + views_name + " / " + rec.method + " " + rec.setting);
    }
    return out;
}

}  // namespace offsetmap
