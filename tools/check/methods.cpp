// Every method on maps and views the check makes itself, against the double oracle (the exact
// walks) or the C++ peer (the rest).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <thread>

#include "check.hpp"
#include "cpu_peer.hpp"
#include "offsetmap/oracle.hpp"
#include "offsetmap/oracle_bound.hpp"

namespace offsetmap::check {
namespace {

struct Reference {
    std::vector<PreparedRay> rays;
    std::vector<ExactHit> hits;  // for traced rays
};

Reference oracle(const MapCase& c, const GBuffer& gb) {
    Reference r;
    r.rays.resize(gb.pixels());
    r.hits.resize(gb.pixels());
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
        r.rays[k] =
            prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, c.settings, c.map.width, c.map.height);
        if (r.rays[k].traced)
            r.hits[k] = exact_hit(c.map, r.rays[k].u, r.rays[k].v, r.rays[k].V, c.settings);
    }
    return r;
}

std::string flags_text(std::uint32_t f) {
    char t[16];
    std::snprintf(t, sizeof t, "0x%x", f);
    return t;
}

double texel_distance(const cl_float2& a, const cl_float2& b, const HeightMap& m) {
    return std::hypot((static_cast<double>(a.s[0]) - b.s[0]) * m.width,
                      (static_cast<double>(a.s[1]) - b.s[1]) * m.height);
}

// The exact walks: every traced ray within the per-ray float bound of the oracle's hit, or the
// other answer of a graze; flags as the input rules give them.
void against_oracle(const MapCase& c, const GBuffer& gb, const Reference& ref,
                    const OffsetResult& got, CaseResult& out) {
    out.measure = "share of the float bound";
    size_t grazes = 0;
    bool flags_wrong = false;  // reported before any distance
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const PreparedRay& pr = ref.rays[k];
        const std::uint32_t want = pr.flags & ~OM_FLAG_GRAZING,
                            have = got.flags[k] & ~OM_FLAG_GRAZING;
        if (want != have) {
            if (!flags_wrong)
                out.worst_pixel = pixel_name(k, gb.width) + ": flags " + flags_text(have) +
                                  ", the input rules give " + flags_text(want);
            out.passed = false;
            flags_wrong = true;
            continue;
        }
        if (!pr.traced) continue;
        ++out.pixels;
        const ExactHit& o = ref.hits[k];
        const HitVerdict v =
            judge_hit(c.map, pr, c.settings, o, got.uv[k].s[0], got.uv[k].s[1], got.depth[k]);
        grazes += v.graze;
        if (v.graze) continue;
        if (v.share_of_bound > out.worst) {
            out.worst = v.share_of_bound;
            char text[200];
            std::snprintf(text, sizeof text,
                          ": uv' (%.7g, %.7g) is %.3g texels from the exact hit (%.7g, %.7g), "
                          "%.3g of its bound",
                          got.uv[k].s[0], got.uv[k].s[1], v.texels, o.u, o.v, v.share_of_bound);
            if (!flags_wrong) out.worst_pixel = pixel_name(k, gb.width) + text;
        }
        if (!v.ok) out.passed = false;
    }
    char note[80];
    std::snprintf(note, sizeof note, "%zu grazes answered by the other hit", grazes);
    out.note = note;
}

// The other methods: flags and fetch counts as the C++ peer's, uv' within 1e-3 texel of it except
// on the kernel's own discontinuities (its answer jumps by more when an input moves by 2^-20 of
// its size: about the rounding two compilers' differences accumulate, tests/test_cpu_peer.cpp).
void against_peer(const std::shared_ptr<Runtime>& rt, const MapCase& c, const GBuffer& gb,
                  const Reference& ref, const MethodParams& params, const DeviceHeightField& field,
                  const OffsetResult& got, CaseResult& out) {
    const std::string& name = params.method->name;
    out.measure = "texels from the C++ peer off its discontinuities";
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    const cpu_peer::Run peer = cpu_peer::run(name, {}, gb, c.map, c.settings, 0, threads);
    const double cap = params.method->fetch_cap ? params.method->fetch_cap(params) : -1.0;
    std::vector<size_t> apart;
    bool flags_wrong = false;  // reported before any distance
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const OffsetResult& p = peer.result;
        if (got.flags[k] != p.flags[k] || (cap >= 0 && got.fetches[k] > cap)) {
            if (!flags_wrong)
                out.worst_pixel = pixel_name(k, gb.width) + ": flags " + flags_text(got.flags[k]) +
                                  " and " + std::to_string(got.fetches[k]) +
                                  " fetches; the peer's flags " + flags_text(p.flags[k]) +
                                  ", the method's cap " + std::to_string(cap);
            out.passed = false;
            flags_wrong = true;
            continue;
        }
        if (!ref.rays[k].traced) continue;
        ++out.pixels;
        const double d = texel_distance(got.uv[k], p.uv[k], c.map);
        if (d > 1e-3)
            apart.push_back(k);
        else
            out.worst = std::max(out.worst, d);
    }
    // Ten nudged copies of each pixel that disagrees, through the device's pass.
    std::vector<size_t> steady;
    if (!apart.empty()) {
        GBuffer nudged;
        nudged.resize(static_cast<int>(10 * apart.size()), 1, false, false);
        for (size_t a = 0; a < apart.size(); ++a) {
            const size_t k = apart[a];
            for (int comp = 0; comp < 5; ++comp)
                for (int side = 0; side < 2; ++side) {
                    float in[5] = {gb.uv[k].s[0], gb.uv[k].s[1], gb.view[k].s[0], gb.view[k].s[1],
                                   gb.view[k].s[2]};
                    in[comp] += (side ? 1.0f : -1.0f) *
                                std::ldexp(std::max(std::fabs(in[comp]), 1e-3f), -20);
                    const size_t n = 10 * a + 2 * comp + side;
                    nudged.uv[n] = {{in[0], in[1]}};
                    nudged.view[n] = {{in[2], in[3], in[4], 0.0f}};
                }
        }
        OffsetPass pass(rt, params);
        const OffsetResult moved = run_offset(*rt, pass, upload(*rt, nudged), field, c.settings);
        for (size_t a = 0; a < apart.size(); ++a) {
            double jump = 0.0;
            for (int n = 0; n < 10; ++n)
                jump =
                    std::max(jump, texel_distance(moved.uv[10 * a + n], got.uv[apart[a]], c.map));
            if (jump <= 1e-3) steady.push_back(apart[a]);
        }
    }
    for (size_t k : steady) {
        const double d = texel_distance(got.uv[k], peer.result.uv[k], c.map);
        if (d > out.worst) {
            out.worst = d;
            char text[160];
            std::snprintf(text, sizeof text,
                          ": uv' (%.7g, %.7g), the peer's (%.7g, %.7g), %.3g texels apart off any "
                          "discontinuity",
                          got.uv[k].s[0], got.uv[k].s[1], peer.result.uv[k].s[0],
                          peer.result.uv[k].s[1], d);
            if (!flags_wrong) out.worst_pixel = pixel_name(k, gb.width) + text;
        }
        out.passed = false;
    }
    // The method's own error against the exact hit, for the record.
    std::vector<double> errors;
    for (size_t k = 0; k < gb.pixels(); ++k)
        if (ref.rays[k].traced && traced(got.flags[k]))
            errors.push_back(std::hypot((got.uv[k].s[0] - ref.hits[k].u) * c.map.width,
                                        (got.uv[k].s[1] - ref.hits[k].v) * c.map.height));
    const ErrorStats e = error_stats(errors);
    char note[160];
    std::snprintf(note, sizeof note,
                  "%zu pixels on a discontinuity; against the exact hit mean %.3g, p95 %.3g texels",
                  apart.size() - steady.size(), e.mean, e.p95);
    out.note = note;
}

}  // namespace

float hashed(std::uint64_t seed, int i, int j) {
    std::uint64_t x = seed ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(j)) << 32 |
                              static_cast<std::uint32_t>(i));
    x *= 0x9E3779B97F4A7C15ull;
    x ^= x >> 31;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 29;
    return static_cast<float>((x >> 40) * 0x1.0p-24);
}

namespace {

template <typename F>
MapCase make_case(const std::string& relief, int w, int h, AddressMode address, bool words,
                  float scale, float reference, F height) {
    MapCase c;
    c.map.width = w;
    c.map.height = h;
    c.map.h.resize(static_cast<size_t>(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const float v = std::clamp(height(i, j), 0.0f, 1.0f);
            c.map.h[static_cast<size_t>(j) * w + i] =
                words ? std::nearbyint(v * 65535.0f) / 65535.0f : v;
        }
    c.settings.scale = scale;
    c.settings.reference_plane = reference;
    c.settings.address = address;
    c.settings.heights = words ? HeightStorage::Unorm16 : HeightStorage::Float;
    char text[160];
    std::snprintf(text, sizeof text, "%s %dx%d, %s, %s heights, s=%.2f, r=%.1f", relief.c_str(), w,
                  h, address == AddressMode::Wrap ? "wrap" : "clamp", words ? "unorm16" : "float",
                  scale, reference);
    c.name = text;
    return c;
}

}  // namespace

// Smooth relief, walls, noise and one-texel ridges.
std::vector<MapCase> map_cases(bool quick) {
    std::vector<MapCase> out;
    out.push_back(
        make_case("sines", 64, 64, AddressMode::Wrap, false, 0.05f, 1.0f, [](int i, int j) {
            const double u = (i + 0.5) / 64, v = (j + 0.5) / 64;
            return static_cast<float>(0.5 + 0.3 * std::sin(2 * M_PI * (2 * u + v)) *
                                                std::cos(2 * M_PI * 3 * v));
        }));
    out.push_back(make_case("noise", 37, 23, AddressMode::Clamp, true, 0.08f, 1.0f,
                            [](int i, int j) { return hashed(7, i, j); }));
    if (quick) return out;
    out.push_back(
        make_case("walls", 96, 80, AddressMode::Wrap, true, 0.05f, 0.6f,
                  [](int i, int j) { return hashed(11, i / 4, j / 5) < 0.5f ? 0.1f : 0.95f; }));
    out.push_back(make_case("ridges", 61, 128, AddressMode::Clamp, false, 0.1f, 1.0f,
                            [](int i, int j) { return i % 7 == 3 || j % 9 == 4 ? 1.0f : 0.05f; }));
    return out;
}

// Random views over the tile (elevations 5-90 degrees), then grazing ones (0.5-5: the grazing rule
// raises those below its minimum), then one row with an empty, a back-facing and a zero view.
GBuffer case_views(bool quick) {
    const int w = quick ? 48 : 96;
    GBuffer steep = make_scene(RandomScene{w, quick ? 24 : 48, 2027, 5.0, 90.0});
    GBuffer grazing = make_scene(RandomScene{w, quick ? 8 : 16, 2028, 0.5, 5.0});
    GBuffer gb;
    gb.resize(w, steep.height + grazing.height + 1, false, false);
    std::copy(steep.uv.begin(), steep.uv.end(), gb.uv.begin());
    std::copy(steep.view.begin(), steep.view.end(), gb.view.begin());
    std::copy(grazing.uv.begin(), grazing.uv.end(), gb.uv.begin() + steep.pixels());
    std::copy(grazing.view.begin(), grazing.view.end(), gb.view.begin() + steep.pixels());
    const size_t last = steep.pixels() + grazing.pixels();
    for (int x = 0; x < w; ++x) {
        gb.uv[last + x] = {{0.25f + 0.5f * x / w, 0.5f}};
        gb.view[last + x] = {{0.3f, 0.2f, 0.93f, 0.0f}};
    }
    gb.uv[last] = {{std::numeric_limits<float>::quiet_NaN(), 0.5f}};  // empty
    gb.view[last + 1] = {{0.3f, 0.2f, -0.5f, 0.0f}};                  // back-facing
    gb.view[last + 2] = {{0.0f, 0.0f, 0.0f, 0.0f}};                   // invalid
    return gb;
}

std::string pixel_name(size_t k, int width) {
    return "pixel (" + std::to_string(k % width) + ", " + std::to_string(k / width) + ")";
}

void check_methods(const std::shared_ptr<Runtime>& rt, const Options& o, DeviceReport& report) {
    const GBuffer gb = case_views(o.quick);
    const DeviceGBuffer g = upload(*rt, gb);
    const std::vector<const MethodInfo*> chosen = select_methods(o.methods);
    for (const MapCase& c : map_cases(o.quick)) {
        const Reference ref = oracle(c, gb);
        const DeviceHeightField field = upload(*rt, c.map, c.settings);
        for (const MethodInfo* m : chosen) {
            const MethodParams params = resolve_params(*m, {});
            CaseResult out;
            out.kernel = m->name;
            out.name = c.name;
            try {
                OffsetPass pass(rt, params);
                const OffsetResult got = run_offset(*rt, pass, g, field, c.settings);
                // The cell walks (no fetch cap but the cells a ray crosses) solve every patch
                // they enter: held to the exact hit.
                const bool exact = m->fetch_cap && m->fetch_cap(params) < 0;
                if (exact)
                    against_oracle(c, gb, ref, got, out);
                else
                    against_peer(rt, c, gb, ref, params, field, got, out);
            } catch (const std::exception& e) {
                out.passed = false;
                out.worst_pixel = std::string("no result: ") + e.what();
            }
            report.cases.push_back(out);
        }
    }
}

}  // namespace offsetmap::check
