#include "offsetmap/temporal.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "offsetmap/error.hpp"
#include "offsetmap/evaluate.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {

std::vector<TemporalRecord> run_temporal(std::shared_ptr<Runtime> rt, const HeightMap& map,
                                         const TemporalOptions& o) {
    if (o.frames < 2) throw Error("the temporal test needs at least 2 frames");
    std::vector<std::string> names;
    for (const auto* m : select_methods(o.methods)) names.push_back(m->name);
    DeviceHeightField field = upload(*rt, map, o.settings);
    std::vector<OffsetPass> passes;
    for (const auto& n : names) passes.emplace_back(rt, n);
    OffsetPass exact_pass(rt, "exact");

    std::vector<OffsetResult> prev(names.size());
    OffsetResult prev_exact;
    std::vector<TemporalRecord> out;
    for (int f = 0; f < o.frames; ++f) {
        PlaneScene cam = o.start;
        double yaw = (cam.yaw_deg + f * o.yaw_step_deg) * M_PI / 180.0;
        cam.yaw_deg += f * o.yaw_step_deg;
        cam.camera_x += f * o.step * std::cos(yaw);
        cam.camera_y += f * o.step * std::sin(yaw);
        DeviceGBuffer g = upload(*rt, make_scene(cam));
        OffsetResult exact = run_offset(*rt, exact_pass, g, field, o.settings, 1);
        for (size_t m = 0; m < names.size(); ++m) {
            OffsetResult r = run_offset(*rt, passes[m], g, field, o.settings, 1);
            if (f > 0) {
                std::vector<double> e;
                for (size_t k = 0; k < r.uv.size(); ++k) {
                    if (!traced(r.flags[k]) || !traced(prev[m].flags[k]) ||
                        !traced(exact.flags[k]) || !traced(prev_exact.flags[k]))
                        continue;
                    double du = (r.uv[k].s[0] - prev[m].uv[k].s[0]) -
                                (exact.uv[k].s[0] - prev_exact.uv[k].s[0]);
                    double dv = (r.uv[k].s[1] - prev[m].uv[k].s[1]) -
                                (exact.uv[k].s[1] - prev_exact.uv[k].s[1]);
                    e.push_back(std::hypot(du * map.width, dv * map.height));
                }
                TemporalRecord rec;
                rec.method = names[m];
                rec.frame = f - 1;
                if (!e.empty()) {
                    for (double x : e)
                        rec.mean += x / e.size(), rec.pop_share += (x > 1.0) / double(e.size());
                    size_t p = static_cast<size_t>(std::ceil(0.95 * e.size())) - 1;
                    std::nth_element(e.begin(), e.begin() + p, e.end());
                    rec.p95 = e[p];
                }
                out.push_back(rec);
            }
            prev[m] = std::move(r);
        }
        prev_exact = std::move(exact);
        if (o.progress)
            o.progress("temporal: frame " + std::to_string(f + 1) + "/" + std::to_string(o.frames));
    }
    return out;
}

void write_temporal_csv(const std::string& path, const std::vector<TemporalRecord>& records) {
    std::ofstream out(path);
    if (!out) throw Error("cannot write '" + path + "'");
    out << "method,frame,mean,p95,pop_share\n";
    for (const auto& r : records)
        out << r.method << "," << r.frame << "," << r.mean << "," << r.p95 << "," << r.pop_share
            << "\n";
}

}  // namespace offsetmap
