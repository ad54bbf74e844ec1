// Method "auto": a short calibration of every method's sweep grid on the material's own pixels,
// against the double-precision exact hit, cached on disk.
#include "offsetmap/auto_method.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "offsetmap/error.hpp"
#include "offsetmap/oracle.hpp"
#include "offsetmap/scenes.hpp"
#include "offsetmap/timing.hpp"

namespace offsetmap {

namespace {

// FNV-1a, 64 bits: a cache key, not a security hash.
struct Hash {
    std::uint64_t h = 0xcbf29ce484222325ull;
    void add(const void* data, size_t n) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 0x100000001b3ull;
    }
    template <typename T>
    void value(const T& v) {
        add(&v, sizeof v);
    }
    void text(const std::string& s) { add(s.data(), s.size()), value(s.size()); }
};

std::string cache_folder(const std::string& given) {
    if (given == "-") return "";
    if (!given.empty()) return given;
    if (const char* d = std::getenv("OFFSETMAP_CACHE_DIR"); d && *d) return d;
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d)
        return std::string(d) + "/offsetmap";
    if (const char* d = std::getenv("HOME"); d && *d) return std::string(d) + "/.cache/offsetmap";
    return "";
}

// The material's pixels of the frame, evenly taken in screen order (neighbours stay neighbours).
GBuffer calibration_views(const LoadedMaterial& m, const GBuffer& frame, size_t most) {
    std::vector<size_t> mine;
    const float id = static_cast<float>(m.spec.id);
    for (size_t k = 0; k < frame.material.size() && k < frame.pixels(); ++k)
        if (frame.material[k] == id) mine.push_back(k);
    if (mine.empty()) {
        RandomScene r;
        r.width = r.height = 128;
        r.min_elevation_deg = 10.0;
        return make_scene(r);
    }
    const size_t stride = (mine.size() + most - 1) / most;
    const size_t taken = (mine.size() + stride - 1) / stride;
    // Rows of 256 (the last partial row dropped): a G-buffer's sides are bounded.
    const int w = static_cast<int>(std::min<size_t>(taken, 256));
    const int h = static_cast<int>(taken / w);
    const size_t n = static_cast<size_t>(w) * h;
    GBuffer g;
    g.resize(w, h, false, false);
    for (size_t k = 0; k < n; ++k) {
        g.uv[k] = frame.uv[mine[k * stride]];
        g.view[k] = frame.view[mine[k * stride]];
    }
    return g;
}

// The calibration pixels repeated, in rows of 256, to at least `least` pixels: launches long
// enough that the per-launch overhead does not rank the candidates.
GBuffer repeated(const GBuffer& v, size_t least) {
    const size_t n = v.pixels();
    const size_t total = std::max(n, (least + n - 1) / n * n) / 256 * 256;
    if (total <= n || total == 0) return v;
    GBuffer g;
    g.resize(256, static_cast<int>(total / 256), false, false);
    for (size_t k = 0; k < total; ++k) {
        g.uv[k] = v.uv[k % n];
        g.view[k] = v.view[k % n];
    }
    return g;
}

std::string views_signature(const GBuffer& g) {
    // Elevations in 5-degree bins, shares rounded to percent: the same scene gives the same key.
    std::vector<size_t> bins(19, 0);
    size_t n = 0;
    for (const auto& v : g.view) {
        const double len = std::sqrt(v.s[0] * v.s[0] + v.s[1] * v.s[1] + v.s[2] * v.s[2]);
        if (!(len > 0.0) || !(v.s[2] > 0.0f)) continue;
        ++bins[std::min<size_t>(18, static_cast<size_t>(std::asin(v.s[2] / len) * 180 / M_PI / 5))];
        ++n;
    }
    std::string s;
    for (size_t b : bins) s += std::to_string(n ? (100 * b + n / 2) / n : 0) + " ";
    return s;
}

}  // namespace

bool precomputed_within_bound(const MethodInfo& info,
                              const std::map<std::string, std::string>& setting,
                              const HeightMap& map, const PassSettings& settings,
                              const AutoOptions& o) {
    if (!info.precompute) return true;
    const size_t pyramid =
        mip_pyramid_floats(map.width, map.height, mip_level_count(map.width, map.height)) *
        sizeof(float);
    const size_t most = std::max(static_cast<size_t>(o.precomputed_per_pyramid * pyramid),
                                 o.precomputed_floor_bytes);
    return info.precompute->bytes(resolve_params(info, setting), settings, map.width, map.height) <=
           most;
}

double budget_statistic(const ErrorBudget& b, const ErrorStats& e) {
    return b.statistic == ErrorBudget::Statistic::P95 ? e.p95 : e.mean;
}

const char* budget_statistic_name(const ErrorBudget& b) {
    return b.statistic == ErrorBudget::Statistic::P95 ? "p95" : "mean";
}

namespace {

using Setting = std::map<std::string, std::string>;
using Grid = std::vector<std::pair<const MethodInfo*, Setting>>;

// Every method's sweep grid (its defaults when it has none), within the precomputed data's
// bound, and the cache's key: the map, its settings, the device, the views and the kernels as
// they would be built now (a cache measured by other kernels, an older library or an edited
// kernel folder, is another key, never a stale answer).
Grid candidate_grid(Runtime& rt, const LoadedMaterial& m, const GBuffer& views,
                    const AutoOptions& o, Hash& key, size_t& skipped) {
    const PassSettings& settings = m.spec.settings;
    const HeightMap& map = m.map;
    key.add(map.h.data(), map.h.size() * sizeof(float));
    key.value(map.width), key.value(map.height);
    for (float f : {settings.scale, settings.reference_plane, settings.min_elevation_deg,
                    settings.max_offset_texels})
        key.value(f);
    key.value(settings.address), key.value(settings.grazing);
    key.text(rt.device_name());
    key.text(views_signature(views));
    key.value(views.pixels());
    Grid grid;
    for (const MethodInfo& info : methods()) {
        auto settings_of = info.sweep.empty() ? std::vector<Setting>{{}} : info.sweep;
        for (const auto& s : settings_of) {
            if (!precomputed_within_bound(info, s, map, settings, o)) {
                ++skipped;
                continue;
            }
            grid.emplace_back(&info, s);
        }
        key.text(Runtime::program_source(offset_program_files(info), "", rt.is_pocl()));
    }
    return grid;
}

// The candidates as a cache measured them; false (and none) for no cache, a stale or a damaged
// one.
bool read_cache(const std::string& file, const Grid& grid, AutoChoice& out) {
    if (file.empty()) return false;
    std::ifstream in(file);
    if (!in) return false;
    try {
        const nlohmann::json j = nlohmann::json::parse(in);
        for (const auto& [info, setting] : grid) {
            const auto& r = j.at(info->name + " " + describe_setting(setting));
            AutoCandidate c;
            c.params = resolve_params(*info, setting);
            c.setting = describe_setting(setting);
            c.error.mean = r.at("mean"), c.error.p95 = r.at("p95");
            c.error.max = r.at("max"), c.error.count = r.at("count");
            c.ns_per_pixel = r.at("ns"), c.fetches = r.at("fetches");
            out.candidates.push_back(c);
        }
        out.samples = j.at("samples");
        return true;
    } catch (const std::exception&) {  // measure again
        out.candidates.clear();
        return false;
    }
}

void write_cache(const std::string& folder, const std::string& file, const LoadedMaterial& m,
                 const AutoChoice& out) {
    nlohmann::json j;
    j["map"] = m.spec.height_map;
    j["samples"] = out.samples;
    for (const AutoCandidate& c : out.candidates)
        j[c.params.method->name + " " + c.setting] = {
            {"mean", c.error.mean},   {"p95", c.error.p95},   {"max", c.error.max},
            {"count", c.error.count}, {"ns", c.ns_per_pixel}, {"fetches", c.fetches}};
    std::error_code ec;
    std::filesystem::create_directories(folder, ec);
    std::ofstream f(file);
    if (f) f << j.dump(1) << "\n";  // a cache: a folder that cannot be written keeps none
}

// The exact hit in double precision on evenly spread samples of the calibration views, laid out
// over `timed` (the views repeated; the copies are timed, not compared).
OffsetResult exact_samples(const LoadedMaterial& m, const GBuffer& views, const GBuffer& timed,
                           const AutoOptions& o, size_t& samples) {
    const PassSettings& settings = m.spec.settings;
    const size_t n = views.pixels();
    const size_t stride = std::max<size_t>(1, (n + o.samples - 1) / std::max<size_t>(1, o.samples));
    OffsetResult exact;
    exact.width = timed.width, exact.height = timed.height;
    exact.uv.assign(timed.pixels(), {{0.0f, 0.0f}});
    exact.flags.assign(timed.pixels(), OM_FLAG_EMPTY);
    for (size_t k = 0; k < n; k += stride) {
        const double v[3] = {views.view[k].s[0], views.view[k].s[1], views.view[k].s[2]};
        const PreparedRay r =
            prepare_ray(views.uv[k].s[0], views.uv[k].s[1], v, settings, m.map.width, m.map.height);
        if (!r.traced) continue;
        const ExactHit hit = exact_hit(m.map, r.u, r.v, r.V, settings);
        exact.uv[k] = {{static_cast<float>(hit.u), static_cast<float>(hit.v)}};
        exact.flags[k] = 0;
        ++samples;
    }
    return exact;
}

// Each candidate once (its build, its JIT, its error against the exact samples), then timed in
// turns: every round runs every candidate, so a slow spell of the shared machine hits them all
// alike.
void measure(const std::shared_ptr<Runtime>& rt, const LoadedMaterial& m, const GBuffer& views,
             const Grid& grid, const AutoOptions& o, AutoChoice& out) {
    const PassSettings& settings = m.spec.settings;
    const GBuffer timed = repeated(views, o.least_timed);
    const OffsetResult exact = exact_samples(m, views, timed, o, out.samples);
    DeviceHeightField field = upload(*rt, m.map, settings, m.normals.width ? &m.normals : nullptr);
    DeviceGBuffer g = upload(*rt, timed);
    std::vector<std::unique_ptr<OffsetPass>> passes;
    for (const auto& [info, setting] : grid) {
        AutoCandidate c;
        c.params = resolve_params(*info, setting);
        c.setting = describe_setting(setting);
        passes.push_back(std::make_unique<OffsetPass>(rt, c.params));
        const OffsetResult r = run_offset(*rt, *passes.back(), g, field, settings, 1);
        c.error = uv_error(r, exact, m.map.width, m.map.height);
        c.fetches = mean_fetches(r);
        out.candidates.push_back(c);
    }
    if (!out.by_time) return;
    const size_t n_timed = timed.pixels();
    OffsetTargets t;
    auto target = [&](size_t bytes) {
        return cl::Buffer(rt->context(), CL_MEM_WRITE_ONLY, n_timed * bytes);
    };
    t.uv = target(sizeof(cl_float2)), t.depth = target(sizeof(float));
    t.fetches = target(sizeof(cl_uint)), t.flags = target(sizeof(cl_uint));
    std::vector<std::vector<double>> ms(passes.size());
    for (int round = 0; round < std::max(1, o.repeats); ++round)
        for (size_t c = 0; c < passes.size(); ++c) {
            cl::Event e = passes[c]->enqueue(g, field, settings, t);
            e.wait();
            ms[c].push_back(event_ms(e));
        }
    for (size_t c = 0; c < passes.size(); ++c)
        out.candidates[c].ns_per_pixel = median(ms[c]) * 1e6 / n_timed;
}

// The cheapest candidate within the budget, and the next; throws Error naming the material and
// the best reached when none is within it.
void pick(const LoadedMaterial& m, const AutoOptions& o, AutoChoice& out) {
    auto cost = [&](const AutoCandidate& c) { return out.by_time ? c.ns_per_pixel : c.fetches; };
    std::vector<const AutoCandidate*> within;
    const AutoCandidate* best = nullptr;
    for (const AutoCandidate& c : out.candidates) {
        if (o.admits && !o.admits(c.params)) continue;
        const double e = budget_statistic(m.spec.budget, c.error);
        if (!best || e < budget_statistic(m.spec.budget, best->error)) best = &c;
        if (e <= m.spec.budget.texels) within.push_back(&c);
    }
    const char* stat = budget_statistic_name(m.spec.budget);
    if (within.empty()) {
        std::ostringstream text;
        text << "material " << m.spec.id << " (" << m.spec.name << "): no method "
             << (o.admits_text.empty() ? "" : o.admits_text + " ") << "meets its error budget ("
             << stat << " " << m.spec.budget.texels << " texels)";
        if (best)
            text << "; the best reached is " << stat << " "
                 << budget_statistic(m.spec.budget, best->error) << " texels ("
                 << best->params.method->name << " " << best->setting << ")";
        else
            text << "; none of the " << out.candidates.size() << " candidates measured is one";
        throw Error(text.str());
    }
    std::stable_sort(
        within.begin(), within.end(),
        [&](const AutoCandidate* a, const AutoCandidate* b) { return cost(*a) < cost(*b); });
    out.chosen = *within[0];
    if (within.size() > 1) out.runner_up = *within[1];
}

}  // namespace

AutoChoice choose_method(std::shared_ptr<Runtime> rt, const LoadedMaterial& m, const GBuffer& frame,
                         const AutoOptions& o) {
    AutoChoice out;
    out.by_time = rt->profiling();
    const GBuffer views = calibration_views(m, frame, std::max<size_t>(o.pixels, 1));
    out.pixels = views.pixels();
    Hash key;
    const Grid grid = candidate_grid(*rt, m, views, o, key, out.skipped);
    char name[32];
    std::snprintf(name, sizeof name, "auto-%016llx.json", static_cast<unsigned long long>(key.h));
    const std::string folder = cache_folder(o.cache_dir);
    const std::string cache_file = folder.empty() ? "" : folder + "/" + name;
    out.cached = read_cache(cache_file, grid, out);
    if (!out.cached) {
        measure(rt, m, views, grid, o, out);
        if (!cache_file.empty()) write_cache(folder, cache_file, m, out);
    }
    pick(m, o, out);
    return out;
}

}  // namespace offsetmap
