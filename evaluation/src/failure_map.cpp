#include "offsetmap/failure_map.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
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
    // One G-buffer row per elevation: random uv and azimuth, or a rendered frame's pixels nearest
    // that elevation; the same for every method and scale. Unfilled slots are empty (NaN uv).
    const int n = o.samples, rows = static_cast<int>(o.elevations_deg.size());
    GBuffer gb;
    gb.resize(n, rows, false, false);
    std::mt19937_64 rng(o.seed);
    auto uniform = [&rng]() { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    if (o.views) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        for (auto& uv : gb.uv) uv = {{nan, nan}};
        for (auto& v : gb.view) v = {{0.0f, 0.0f, 1.0f, 0.0f}};
        std::vector<std::vector<size_t>> bins(rows);
        const GBuffer& src = *o.views;
        for (size_t k = 0; k < src.pixels(); ++k) {
            const cl_float4 v = src.view[k];
            const double len = std::sqrt(double(v.s[0]) * v.s[0] + double(v.s[1]) * v.s[1] +
                                         double(v.s[2]) * v.s[2]);
            if (std::isnan(src.uv[k].s[0]) || std::isnan(src.uv[k].s[1]) || !(len > 0.0) ||
                !std::isfinite(len) || !(v.s[2] > 0.0f))
                continue;
            const double e = std::asin(std::min(1.0, v.s[2] / len)) * 180.0 / M_PI;
            int best = 0;
            for (int r = 1; r < rows; ++r)
                if (std::abs(o.elevations_deg[r] - e) < std::abs(o.elevations_deg[best] - e))
                    best = r;
            bins[best].push_back(k);
        }
        for (int r = 0; r < rows; ++r) {
            std::shuffle(bins[r].begin(), bins[r].end(), rng);
            for (size_t j = 0; j < bins[r].size() && j < size_t(n); ++j) {
                gb.uv[size_t(r) * n + j] = src.uv[bins[r][j]];
                gb.view[size_t(r) * n + j] = src.view[bins[r][j]];
            }
        }
    } else {
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
                if (c.uv.count == 0) continue;  // a rendered frame with no view near this row
                size_t counted = 0;
                for (size_t k = begin; k < end; ++k)
                    if (traced(r.flags[k])) c.fetches_mean += r.fetches[k], ++counted;
                c.fetches_mean /= std::max<size_t>(counted, 1);
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
    out << "method,elevation_deg,scale,uv_mean,uv_p95,uv_max,wrong_share,fetches_mean,samples\n";
    for (const auto& c : cells)
        out << c.method << "," << c.elevation_deg << "," << c.scale << "," << c.uv.mean << ","
            << c.uv.p95 << "," << c.uv.max << "," << c.uv.wrong_share << "," << c.fetches_mean
            << "," << c.uv.count << "\n";
}

}  // namespace offsetmap
