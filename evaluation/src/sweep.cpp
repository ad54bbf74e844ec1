#include "offsetmap/sweep.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "offsetmap/error.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {
namespace {

double srgb(float linear) {
    double c = std::clamp(std::isfinite(linear) ? static_cast<double>(linear) : 0.0, 0.0, 1.0);
    return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

SweepRecord measure(Runtime& rt, OffsetPass& pass, ShadePass& shade, const DeviceGBuffer& g,
                    const DeviceHeightField& f, const PassSettings& settings, int repeats,
                    const OffsetResult& exact, const std::vector<cl_float4>& exact_rgb,
                    const HeightMap& map) {
    OffsetResult r = run_offset(rt, pass, g, f, settings, repeats + 1);
    if (!r.kernel_ms.empty()) r.kernel_ms.erase(r.kernel_ms.begin());  // warm-up (JIT, caches)
    SweepRecord rec;
    rec.uv = uv_error(r, exact, map.width, map.height);
    size_t n = 0;
    for (size_t k = 0; k < r.flags.size(); ++k) {
        if (!traced(r.flags[k]) || !traced(exact.flags[k])) continue;
        ++n;
        rec.depth_error += std::fabs(static_cast<double>(r.depth[k]) - exact.depth[k]) * map.width;
    }
    if (n) rec.depth_error /= n;
    rec.fetches_mean = mean_fetches(r);
    rec.fetches_max = max_fetches(r);
    rec.kernel_ms = r.median_kernel_ms();
    rec.ns_per_pixel = rec.kernel_ms * 1e6 / static_cast<double>(g.pixels());
    rec.psnr_db =
        psnr_srgb(run_shade(rt, shade, r, g, f, nullptr, settings, ShadeSettings{}), exact_rgb);
    rec.precomputed_bytes = pass.precomputed().bytes;
    rec.precompute_ms = pass.precomputed().build_ms;
    return rec;
}

}  // namespace

double psnr_srgb(const std::vector<cl_float4>& image, const std::vector<cl_float4>& reference) {
    double se = 0;
    size_t n = 0;
    for (size_t k = 0; k < reference.size() && k < image.size(); ++k) {
        if (!(reference[k].s[3] > 0.0f)) continue;
        for (int c = 0; c < 3; ++c) {
            double d = srgb(image[k].s[c]) - srgb(reference[k].s[c]);
            se += d * d;
        }
        n += 3;
    }
    if (n == 0 || se == 0) return 99.0;
    return std::min(99.0, 10.0 * std::log10(static_cast<double>(n) / se));
}

std::vector<SweepRecord> run_sweep(std::shared_ptr<Runtime> rt, const std::vector<NamedMap>& maps,
                                   const std::vector<NamedViews>& views, const SweepOptions& o) {
    std::vector<const MethodInfo*> chosen = select_methods(o.methods);
    ShadePass shade(rt);
    std::vector<SweepRecord> out;
    size_t total = 0, done = 0;
    for (const auto* m : chosen)
        total += (o.defaults_only || m->sweep.empty()) ? 1 : m->sweep.size();
    total *= maps.size() * views.size();
    for (const auto& nm : maps) {
        DeviceHeightField field = upload(*rt, nm.map, o.settings);
        for (const auto& nv : views) {
            DeviceGBuffer g = upload(*rt, nv.gbuffer);
            OffsetPass exact_pass(rt, "exact");
            OffsetResult exact = run_offset(*rt, exact_pass, g, field, o.settings, 1);
            auto exact_rgb =
                run_shade(*rt, shade, exact, g, field, nullptr, o.settings, ShadeSettings{});
            for (const auto* m : chosen) {
                std::vector<std::map<std::string, std::string>> grid = m->sweep;
                if (o.defaults_only || grid.empty()) grid = {{}};
                for (const auto& setting : grid) {
                    OffsetPass pass(rt, m->name, setting);
                    SweepRecord rec = measure(*rt, pass, shade, g, field, o.settings, o.repeats,
                                              exact, exact_rgb, nm.map);
                    rec.method = m->name;
                    rec.setting = describe_setting(setting);
                    rec.map = nm.name;
                    rec.views = nv.name;
                    out.push_back(rec);
                    ++done;
                    if (o.progress) {
                        std::ostringstream line;
                        line << "[" << done << "/" << total << "] " << nm.name << " / " << nv.name
                             << " / " << m->name << " " << rec.setting << ": " << rec.uv.mean
                             << " texels, " << rec.ns_per_pixel << " ns/pixel";
                        o.progress(line.str());
                    }
                }
            }
        }
    }
    return out;
}

void write_sweep_csv(const std::string& path, const std::vector<SweepRecord>& records) {
    std::ofstream out(path);
    if (!out) throw Error("cannot write '" + path + "'");
    out << "method,setting,map,views,uv_mean,uv_p95,uv_max,wrong_share,depth_error,psnr_db,"
           "fetches_mean,fetches_max,ns_per_pixel,kernel_ms,precomputed_bytes,precompute_ms,"
           "worst_material_p95\n";
    for (const auto& r : records)
        out << r.method << ",\"" << r.setting << "\"," << r.map << "," << r.views << ","
            << r.uv.mean << "," << r.uv.p95 << "," << r.uv.max << "," << r.uv.wrong_share << ","
            << r.depth_error << "," << r.psnr_db << "," << r.fetches_mean << "," << r.fetches_max
            << "," << r.ns_per_pixel << "," << r.kernel_ms << "," << r.precomputed_bytes << ","
            << r.precompute_ms << "," << r.worst_material_p95 << "\n";
}

void write_sweep_json(const std::string& path, const std::vector<SweepRecord>& records,
                      const std::string& device, const PassSettings& settings) {
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& r : records)
        rows.push_back({{"method", r.method},
                        {"setting", r.setting},
                        {"map", r.map},
                        {"views", r.views},
                        {"uv_mean", r.uv.mean},
                        {"uv_p95", r.uv.p95},
                        {"uv_max", r.uv.max},
                        {"wrong_share", r.uv.wrong_share},
                        {"depth_error", r.depth_error},
                        {"psnr_db", r.psnr_db},
                        {"fetches_mean", r.fetches_mean},
                        {"fetches_max", r.fetches_max},
                        {"ns_per_pixel", r.ns_per_pixel},
                        {"kernel_ms", r.kernel_ms},
                        {"precomputed_bytes", r.precomputed_bytes},
                        {"precompute_ms", r.precompute_ms},
                        {"worst_material_p95", r.worst_material_p95}});
    nlohmann::json doc = {{"device", device},
                          {"scale", settings.scale},
                          {"reference_plane", settings.reference_plane},
                          {"min_elevation_deg", settings.min_elevation_deg},
                          {"records", rows}};
    std::ofstream out(path);
    if (!out) throw Error("cannot write '" + path + "'");
    out << doc.dump(1) << "\n";
}

}  // namespace offsetmap
