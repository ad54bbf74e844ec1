#include "offsetmap/failure_map.hpp"

#include <cmath>
#include <fstream>
#include <random>

#include "offsetmap/error.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {

std::vector<FailureCell> run_failure_map(std::shared_ptr<Runtime> rt, const HeightMap& map,
                                         const FailureMapOptions& o) {
    if (o.elevations_deg.empty() || o.scales.empty() || o.samples < 1)
        throw Error("failure map needs elevations, scales and at least one sample per cell");
    for (double e : o.elevations_deg)
        if (!(e > 0.0 && e <= 90.0)) throw Error("failure-map elevations must be in (0, 90]");
    // One G-buffer row per elevation: random uv and azimuth, the same for every method and scale.
    const int n = o.samples, rows = static_cast<int>(o.elevations_deg.size());
    GBuffer gb;
    gb.resize(n, rows, false, false);
    std::mt19937_64 rng(o.seed);
    auto uniform = [&rng]() { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    for (int r = 0; r < rows; ++r) {
        double e = o.elevations_deg[r] * M_PI / 180.0;
        for (int k = 0; k < n; ++k) {
            double az = 2.0 * M_PI * uniform();
            size_t idx = static_cast<size_t>(r) * n + k;
            gb.uv[idx] = {{static_cast<float>(uniform()), static_cast<float>(uniform())}};
            gb.view[idx] = {{static_cast<float>(std::cos(e) * std::cos(az)),
                             static_cast<float>(std::cos(e) * std::sin(az)),
                             static_cast<float>(std::sin(e)), 0.0f}};
        }
    }
    std::vector<std::string> names;
    for (const auto* m : select_methods(o.methods)) names.push_back(m->name);

    DeviceHeightField field = upload(*rt, map, o.settings);
    DeviceGBuffer g = upload(*rt, gb);
    std::vector<FailureCell> out;
    OffsetPass exact_pass(rt, "exact");
    for (double scale : o.scales) {
        PassSettings s = o.settings;
        s.scale = static_cast<float>(scale);
        validate(s);
        // The reference is the true hit: exact under the plain clamp rule, whatever policy the
        // methods run with, so the map shows a policy's bias as well as a method's error.
        PassSettings truth = s;
        truth.grazing = GrazingPolicy::Clamp;
        OffsetResult exact = run_offset(*rt, exact_pass, g, field, truth, 1);
        for (const auto& name : names) {
            OffsetPass pass(rt, name);
            OffsetResult r = run_offset(*rt, pass, g, field, s, 1);
            for (int row = 0; row < rows; ++row) {
                // Split the row out of both results (uv_error compares whole results).
                OffsetResult a, b;
                for (OffsetResult* dst : {&a, &b}) dst->width = n, dst->height = 1;
                size_t begin = static_cast<size_t>(row) * n, end = begin + n;
                a.uv.assign(r.uv.begin() + begin, r.uv.begin() + end);
                a.flags.assign(r.flags.begin() + begin, r.flags.begin() + end);
                b.uv.assign(exact.uv.begin() + begin, exact.uv.begin() + end);
                b.flags.assign(exact.flags.begin() + begin, exact.flags.begin() + end);
                FailureCell c;
                c.method = name;
                c.elevation_deg = o.elevations_deg[row];
                c.scale = scale;
                c.uv = uv_error(a, b, map.width, map.height);
                for (size_t k = begin; k < end; ++k) c.fetches_mean += r.fetches[k];
                c.fetches_mean /= n;
                out.push_back(c);
            }
            if (o.progress) o.progress("failure map: s = " + std::to_string(scale) + ", " + name);
        }
    }
    return out;
}

void write_failure_csv(const std::string& path, const std::vector<FailureCell>& cells) {
    std::ofstream out(path);
    if (!out) throw Error("cannot write '" + path + "'");
    out << "method,elevation_deg,scale,uv_mean,uv_p95,uv_max,wrong_share,fetches_mean\n";
    for (const auto& c : cells)
        out << c.method << "," << c.elevation_deg << "," << c.scale << "," << c.uv.mean << ","
            << c.uv.p95 << "," << c.uv.max << "," << c.uv.wrong_share << "," << c.fetches_mean
            << "\n";
}

}  // namespace offsetmap
