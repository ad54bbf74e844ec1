// A seeded property test of the exact methods (cone, maxmip, exact): on randomized maps and rays,
// every traced ray's hit is within the per-ray float bound of the double oracle (oracle_bound.hpp),
// or is the other answer of a graze, and costs no more fetches than its walk's cap.
//
// A case draws: a map shape (one side 1-64, the other 1-64 or up to 20000, either orientation,
// odd and prime sides favoured), a relief (noise, sines, cliffs, one-texel ridges, spikes, a
// constant, crops of data/rocks.png), an address mode, a height storage (floats, or unorm16 words:
// the map rounded to multiples of 1/65535 first, which the oracle then reads too), r in
// {1, 0.6, 0}, a scale, and 64 rays from the grazing minimum (some below it, raised by the rule)
// to straight down, some along an axis, some starting on texel centres or cell edges. The beam's
// variants (`beam=1`: a work-item's rays skip the empty space together) run on 128 more rays of the
// case, drawn apart, in groups of 16 that share a work-item: neighbouring starts and near-parallel
// views as a camera's pixels have, some groups with one stray ray (an edge), some spread wide.
//
// The suite runs kDefaultCases cases from seed 1. A longer run: `./run property CASES [SEED]`, or
// the environment variables OFFSETMAP_PROPERTY_CASES and OFFSETMAP_PROPERTY_SEED. A failing case
// prints the one-case run that repeats it.
#include "oracle_bound.hpp"

namespace omtest {
namespace {

constexpr int kDefaultCases = 200;
constexpr int kRaysPerCase = 256;
constexpr int kCoherentRays = 128;

// A method and its parameters; the beam's variants trace the coherent rays.
struct Variant {
    const char* method;
    std::map<std::string, std::string> params;
    std::string label() const {
        return method + (params.empty() ? "" : " " + describe_setting(params));
    }
};
const Variant kVariants[] = {
    {"exact", {}}, {"maxmip", {}}, {"cone", {}}, {"maxmip", {{"beam", "1"}}}};

long env_long(const char* name, long fallback) {
    const char* v = std::getenv(name);
    return v && *v ? std::strtol(v, nullptr, 10) : fallback;
}

bool is_prime(int n) {
    if (n < 2) return false;
    for (int d = 2; d * d <= n; ++d)
        if (n % d == 0) return false;
    return true;
}

struct Rng {
    std::mt19937_64 gen;
    explicit Rng(std::uint64_t seed) : gen(seed) {}
    double uniform(double a = 0.0, double b = 1.0) {
        return std::uniform_real_distribution<double>(a, b)(gen);
    }
    int integer(int a, int b) { return std::uniform_int_distribution<int>(a, b)(gen); }
    bool chance(double p) { return uniform() < p; }
};

// A side: 1-64, odd or prime a third of the time each.
int short_side(Rng& rng) {
    for (;;) {
        const int n = rng.integer(1, 64);
        const double pick = rng.uniform();
        if (pick < 0.33 && !is_prime(n)) continue;
        if (pick < 0.66 && pick >= 0.33 && n % 2 == 0) continue;
        return n;
    }
}

// A long side, log-uniform up to 20000, odd or prime half of the time.
int long_side(Rng& rng) {
    int n = static_cast<int>(std::exp(rng.uniform(std::log(65.0), std::log(20000.0))));
    if (rng.chance(0.25))
        while (!is_prime(n)) ++n;
    else if (rng.chance(0.33))
        n |= 1;
    return std::min(n, 20000);
}

const HeightMap& rocks() {
    static const HeightMap m =
        load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png");
    return m;
}

struct Relief {
    std::string name;
    std::function<float(int, int)> at;
};

Relief draw_relief(Rng& rng, int w, int h) {
    switch (rng.integer(0, 6)) {
        case 0: {  // independent texels
            auto seed = rng.gen();
            return {"noise", [seed, w](int i, int j) {
                        std::uint64_t x = seed ^ (static_cast<std::uint64_t>(j) * w + i);
                        x *= 0x9E3779B97F4A7C15ull;
                        x ^= x >> 29;
                        x *= 0xBF58476D1CE4E5B9ull;
                        x ^= x >> 32;
                        return static_cast<float>((x >> 40) * 0x1.0p-24);
                    }};
        }
        case 1: {  // tiling sines, a few periods per side
            const int fu = rng.integer(0, 4), fv = rng.integer(0, 4);
            const double a = rng.uniform(0.1, 0.5), phase = rng.uniform(0.0, 6.3);
            return {"sines", [=](int i, int j) {
                        const double u = (i + 0.5) / w, v = (j + 0.5) / h;
                        return static_cast<float>(
                            0.5 + a * std::sin(2 * M_PI * (fu * u + fv * v) + phase));
                    }};
        }
        case 2: {  // blocks of two heights: walls one texel wide
            const int bx = rng.integer(1, 9), by = rng.integer(1, 9);
            const float lo = static_cast<float>(rng.uniform(0.0, 0.4)),
                        hi = static_cast<float>(rng.uniform(0.6, 1.0));
            const auto seed = rng.gen();
            return {"cliffs", [=](int i, int j) {
                        std::uint64_t x =
                            seed ^ ((static_cast<std::uint64_t>(j / by) << 32) + i / bx);
                        x *= 0x9E3779B97F4A7C15ull;
                        return (x >> 63) ? hi : lo;
                    }};
        }
        case 3: {  // one-texel ridges in u, v or both: thin features a cone step could skip
            const int pu = rng.integer(2, 17), pv = rng.integer(2, 17), axes = rng.integer(1, 3);
            return {"ridges", [=](int i, int j) {
                        const bool on = ((axes & 1) && i % pu == 0) || ((axes & 2) && j % pv == 0);
                        return on ? 1.0f : 0.05f;
                    }};
        }
        case 4: {  // sparse spikes on a low floor
            const int pu = rng.integer(3, 11), pv = rng.integer(3, 11);
            return {"spikes",
                    [=](int i, int j) { return (i % pu == 1 && j % pv == 2) ? 1.0f : 0.02f; }};
        }
        case 5: {  // a constant, the slab's planes among them
            const double pick = rng.uniform();
            const float c = pick < 0.3 ? 0.0f : pick < 0.6 ? 1.0f : static_cast<float>(pick);
            return {"constant", [c](int, int) { return c; }};
        }
        default: {  // a crop of a real map from a random corner, its rows repeated
            const HeightMap& r = rocks();
            const int i0 = rng.integer(0, r.width - 1), j0 = rng.integer(0, r.height - 1);
            return {"rocks", [&r, i0, j0](int i, int j) {
                        return r.at((i0 + i) % r.width, (j0 + j) % r.height);
                    }};
        }
    }
}

struct PropertyCase {
    std::string text;  // what it drew, for messages
    HeightMap map;     // as the passes read it (rounded under unorm16)
    PassSettings settings;
    GBuffer rays;
    GBuffer coherent;  // groups of 16 neighbouring rays, for the beam's variants
};

// A view at an elevation drawn as the rays' (from the grazing minimum, some below it) and any
// azimuth.
std::array<double, 2> draw_view(Rng& rng, double min_elev) {
    const double pick = rng.uniform();
    const double elev = pick < 0.05  ? rng.uniform(0.1, min_elev)  // raised by the rule
                        : pick < 0.1 ? min_elev
                        : pick < 0.35
                            ? rng.uniform(min_elev, 5.0)
                            : std::asin(rng.uniform(std::sin(5.0 * M_PI / 180), 1.0)) * 180 / M_PI;
    return {elev, rng.uniform(0.0, 360.0)};
}

// kCoherentRays rays in groups of 16 (one work-item's lanes, 16 x 1 in a one-row G-buffer): a
// group's starts 0-3 texels apart on a 4 x 4 grid and its views within half a degree, as a camera's
// neighbouring pixels; a quarter of the groups have one ray from elsewhere (an edge's), an eighth
// are spread over the whole map.
GBuffer draw_coherent(Rng& rng, int w, int h, double min_elev) {
    GBuffer g;
    g.resize(kCoherentRays, 1, false, false);
    for (int group = 0; group < kCoherentRays / 16; ++group) {
        const auto [elev, az] = draw_view(rng, min_elev);
        const double u0 = rng.uniform(-0.5, 1.5), v0 = rng.uniform(-0.5, 1.5);
        const double du = rng.uniform(0.0, 3.0) / w, dv = rng.uniform(0.0, 3.0) / h;
        const bool stray = rng.chance(0.25), wide = rng.chance(0.125);
        const int stray_lane = rng.integer(0, 15);
        for (int k = 0; k < 16; ++k) {
            double u = u0 + (k % 4) * du, v = v0 + (k / 4) * dv;
            double e = std::max(0.1, elev + rng.uniform(-0.5, 0.5)),
                   a = az + rng.uniform(-0.5, 0.5);
            if (wide) u = rng.uniform(-0.5, 1.5), v = rng.uniform(-0.5, 1.5);
            if (stray && k == stray_lane) {
                const auto view = draw_view(rng, min_elev);
                e = view[0], a = view[1], u = rng.uniform(-0.5, 1.5), v = rng.uniform(-0.5, 1.5);
            }
            const std::array<float, 3> V = view_dir(e, a);
            g.uv[group * 16 + k] = {{static_cast<float>(u), static_cast<float>(v)}};
            g.view[group * 16 + k] = {{V[0], V[1], V[2], 0.0f}};
        }
    }
    return g;
}

PropertyCase draw_case(std::uint64_t seed) {
    Rng rng(seed);
    PropertyCase c;
    int w = short_side(rng), h = rng.chance(0.5) ? short_side(rng) : long_side(rng);
    if (rng.chance(0.5)) std::swap(w, h);
    const Relief relief = draw_relief(rng, w, h);
    PassSettings& s = c.settings;
    s.address = rng.chance(0.5) ? AddressMode::Wrap : AddressMode::Clamp;
    const bool unorm16 = rng.chance(0.5);
    s.heights = unorm16 ? HeightStorage::Unorm16 : HeightStorage::Float;
    const float refs[] = {1.0f, 0.6f, 0.0f};
    s.reference_plane = refs[rng.integer(0, 2)];
    const float scales[] = {0.02f, 0.05f, 0.1f, 0.2f};
    s.scale = scales[rng.integer(0, 3)];
    c.map = make_map(w, h, [&](int i, int j) {
        const float v = std::clamp(relief.at(i, j), 0.0f, 1.0f);
        return unorm16 ? static_cast<float>(std::nearbyint(v * 65535.0) / 65535.0) : v;
    });

    // Rays: elevations from the grazing minimum (a few below it) up, a third under 5 degrees.
    const double min_elev = s.min_elevation_deg;
    c.rays.resize(kRaysPerCase, 1, false, false);
    for (int k = 0; k < kRaysPerCase; ++k) {
        const auto [elev, az] = draw_view(rng, min_elev);
        std::array<float, 3> V = view_dir(elev, az);
        if (rng.chance(0.1)) {  // along an axis: one component exactly zero
            const int axis = rng.integer(0, 3);
            const float xy = std::hypot(V[0], V[1]);
            V[0] = axis == 0 ? xy : axis == 2 ? -xy : 0.0f;
            V[1] = axis == 1 ? xy : axis == 3 ? -xy : 0.0f;
        }
        double u = rng.uniform(-0.5, 1.5), v = rng.uniform(-0.5, 1.5);
        const double place = rng.uniform();
        if (place < 0.1) {  // on a texel centre
            u = (rng.integer(-w, 2 * w) + 0.5) / w, v = (rng.integer(-h, 2 * h) + 0.5) / h;
        } else if (place < 0.2) {  // on a cell edge (between texel centres)
            u = rng.integer(-w, 2 * w) / static_cast<double>(w);
            v = rng.integer(-h, 2 * h) / static_cast<double>(h);
        }
        c.rays.uv[k] = {{static_cast<float>(u), static_cast<float>(v)}};
        c.rays.view[k] = {{V[0], V[1], V[2], 0.0f}};
    }
    char text[200];
    std::snprintf(text, sizeof text, "seed %llu: %s %dx%d, %s, %s heights, s=%.2f, r=%.1f",
                  static_cast<unsigned long long>(seed), relief.name.c_str(), w, h,
                  s.address == AddressMode::Wrap ? "wrap" : "clamp", unorm16 ? "unorm16" : "float",
                  s.scale, s.reference_plane);
    c.text = text;
    Rng apart(seed ^ 0x5bd1e995u);  // its own stream: the rays above stay as they were drawn
    c.coherent = draw_coherent(apart, w, h, min_elev);
    return c;
}

// llvmpipe (rusticl's device here) ends a kernel's loops after 65535 iterations in all, a guard
// against shaders that never end; a walk it stops is flagged CAPPED. Rays that cross more cells
// than that (grazing views on maps over ~10^4 texels) are counted apart there.
constexpr unsigned kLlvmpipeLoopLimit = 65535;

struct MethodStats {
    size_t rays = 0, grazes = 0, loop_limited = 0;
    double worst_texels = 0.0, worst_ratio = 0.0;
    std::string worst_case;
};

// A G-buffer's rays as the oracle prepares them, and its hits.
struct RaySet {
    std::vector<PreparedRay> prepared;
    std::vector<ExactHit> oracle;
};

RaySet prepare_rays(const HeightMap& map, const GBuffer& rays, const PassSettings& s) {
    RaySet out;
    const size_t n = rays.uv.size();
    out.prepared.resize(n);
    out.oracle.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const double V[3] = {rays.view[k].s[0], rays.view[k].s[1], rays.view[k].s[2]};
        out.prepared[k] =
            prepare_ray(rays.uv[k].s[0], rays.uv[k].s[1], V, s, map.width, map.height);
        if (out.prepared[k].traced)
            out.oracle[k] =
                exact_hit(map, out.prepared[k].u, out.prepared[k].v, out.prepared[k].V, s);
    }
    return out;
}

// One variant over one set of the case's rays: each traced ray within its bound of the oracle (or
// a graze's other answer) and within its walk's fetch cap.
void check_variant(const Variant& v, const PropertyCase& c, const DeviceHeightField& field,
                   const GBuffer& rays, const RaySet& set, bool loop_limited, MethodStats& st) {
    const PassSettings& s = c.settings;
    auto rt = runtime();
    OffsetPass pass(rt, v.method, v.params);
    const OffsetResult res = run_offset(*rt, pass, upload(*rt, rays), field, s, 1);
    int failures = 0;
    for (size_t k = 0; k < set.prepared.size() && failures < 3; ++k) {
        const PreparedRay& pr = set.prepared[k];
        const auto where = [&] { return v.label() + ", ray " + std::to_string(k); };
        // A walk whose cap allows more iterations than llvmpipe's budget may be stopped by it (the
        // method's own cap, max_cells, is never reached on these rays).
        if (pr.traced && loop_limited && (res.flags[k] & OM_FLAG_CAPPED) &&
            ray_fetch_cap(v.method, s, c.map, pr, set.oracle[k].t, v.params) > kLlvmpipeLoopLimit) {
            ++st.loop_limited;  // flagged, as a capped walk is: not a wrong answer
            continue;
        }
        EXPECT_EQ(res.flags[k] & ~OM_FLAG_GRAZING, pr.flags & ~OM_FLAG_GRAZING) << where();
        if (!pr.traced) continue;
        ++st.rays;
        const ExactHit& o = set.oracle[k];
        // The walk's cap up to the later of its hit and the oracle's (a graze's other answer lies
        // beyond the oracle's).
        const double cap =
            ray_fetch_cap(v.method, s, c.map, pr, std::max<double>(o.t, res.depth[k]), v.params);
        if (res.fetches[k] > cap) {
            ++failures;
            ADD_FAILURE() << where() << ": " << res.fetches[k] << " fetches, cap " << cap;
        }
        const HitVerdict hit =
            judge_hit(c.map, pr, s, o, res.uv[k].s[0], res.uv[k].s[1], res.depth[k]);
        if (hit.graze) {
            ++st.grazes;
            continue;
        }
        if (hit.texels > st.worst_texels) st.worst_texels = hit.texels, st.worst_case = c.text;
        st.worst_ratio = std::max(st.worst_ratio, hit.share_of_bound);
        if (!hit.ok) {
            const RayTolerance tol = ray_tolerance(c.map, pr, s, o.t);
            ++failures;
            ADD_FAILURE() << where() << ": uv' " << hit.texels << " texels (bound " << tol.texels
                          << "), t " << res.depth[k] << " vs the oracle's " << o.t << " (bound "
                          << tol.dt << "); uv " << pr.u << "," << pr.v << " V " << pr.V[0] << ","
                          << pr.V[1] << "," << pr.V[2];
        }
    }
}

TEST(ExactProperty, ExactMethodsMeetTheOracleOnRandomMapsAndRays) {
    const long cases = env_long("OFFSETMAP_PROPERTY_CASES", kDefaultCases);
    const long first = env_long("OFFSETMAP_PROPERTY_SEED", 1);
    ASSERT_GT(cases, 0) << "OFFSETMAP_PROPERTY_CASES";
    std::map<std::string, MethodStats> stats;
    const bool loop_limited = runtime()->device_name().find("llvmpipe") != std::string::npos;
    for (long n = 0; n < cases; ++n) {
        const std::uint64_t seed = static_cast<std::uint64_t>(first + n);
        const PropertyCase c = draw_case(seed);
        SCOPED_TRACE(c.text + "; repeat with OFFSETMAP_PROPERTY_SEED=" + std::to_string(seed) +
                     " OFFSETMAP_PROPERTY_CASES=1");
        const PassSettings& s = c.settings;
        const RaySet random = prepare_rays(c.map, c.rays, s),
                     coherent = prepare_rays(c.map, c.coherent, s);
        // One upload of the case's map for every variant (each pass keeps its own data).
        const DeviceHeightField field = upload(*runtime(), c.map, s);
        for (const Variant& v : kVariants)
            check_variant(v, c, field, v.params.empty() ? c.rays : c.coherent,
                          v.params.empty() ? random : coherent, loop_limited, stats[v.label()]);
    }
    for (const Variant& v : kVariants) {
        const std::string method = v.label();
        const MethodStats& st = stats[method];
        std::printf(
            "%s: %zu rays in %ld cases (seeds %ld-%ld): worst %.3g texels (%s), %.2f of its "
            "bound at most; %zu grazes answered by the other hit; %zu stopped by the driver's loop "
            "limit\n",
            method.c_str(), st.rays, cases, first, first + cases - 1, st.worst_texels,
            st.worst_case.c_str(), st.worst_ratio, st.grazes, st.loop_limited);
        if (!loop_limited) {
            EXPECT_EQ(st.loop_limited, 0u);
        }
        if (cases == kDefaultCases && first == 1) {
            if (!v.params.empty()) continue;
            record_figure(method + ".property.rays", static_cast<double>(st.rays));
            record_figure(method + ".property.worst_texels", st.worst_texels);
            record_figure(method + ".property.worst_share_of_bound", st.worst_ratio);
        }
    }
}

}  // namespace
}  // namespace omtest
