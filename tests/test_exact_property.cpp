// A seeded property test of the exact methods (cone, maxmip, exact): on randomized maps and rays,
// every traced ray's hit is within the per-ray float bound of the double oracle (oracle_bound.hpp),
// or is the other answer of a graze, and costs no more fetches than its walk's cap.
//
// A case draws: a map shape (one side 1-64, the other 1-64 or up to 20000, either orientation,
// odd and prime sides favoured), a relief (noise, sines, cliffs, one-texel ridges, spikes, a
// constant, crops of data/rocks.png), an address mode, a height storage (floats, or unorm16 words:
// the map rounded to multiples of 1/65535 first, which the oracle then reads too), r in
// {1, 0.6, 0}, a scale, and 64 rays from the grazing minimum (some below it, raised by the rule)
// to straight down, some along an axis, some starting on texel centres or cell edges.
//
// The suite runs kDefaultCases cases from seed 1. A longer run: `./run property CASES [SEED]`, or
// the environment variables OFFSETMAP_PROPERTY_CASES and OFFSETMAP_PROPERTY_SEED. A failing case
// prints the one-case run that repeats it.
#include "oracle_bound.hpp"

namespace omtest {
namespace {

constexpr int kDefaultCases = 200;
constexpr int kRaysPerCase = 256;
const char* const kMethods[] = {"exact", "maxmip", "cone"};

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
};

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
        const double pick = rng.uniform();
        const double elev =
            pick < 0.05   ? rng.uniform(0.1, min_elev)  // raised by the rule
            : pick < 0.1  ? min_elev
            : pick < 0.35 ? rng.uniform(min_elev, 5.0)
                          : std::asin(rng.uniform(std::sin(5.0 * M_PI / 180), 1.0)) * 180 / M_PI;
        double az = rng.uniform(0.0, 360.0);
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
        std::vector<PreparedRay> prepared(kRaysPerCase);
        std::vector<ExactHit> oracle(kRaysPerCase);
        for (int k = 0; k < kRaysPerCase; ++k) {
            const double V[3] = {c.rays.view[k].s[0], c.rays.view[k].s[1], c.rays.view[k].s[2]};
            prepared[k] =
                prepare_ray(c.rays.uv[k].s[0], c.rays.uv[k].s[1], V, s, c.map.width, c.map.height);
            if (prepared[k].traced)
                oracle[k] = exact_hit(c.map, prepared[k].u, prepared[k].v, prepared[k].V, s);
        }
        for (const char* method : kMethods) {
            const OffsetResult res = run(method, c.map, c.rays, s);
            MethodStats& st = stats[method];
            int failures = 0;
            for (int k = 0; k < kRaysPerCase && failures < 3; ++k) {
                const PreparedRay& pr = prepared[k];
                const auto where = [&] {
                    return std::string(method) + ", ray " + std::to_string(k);
                };
                // A walk whose cap allows more iterations than llvmpipe's budget may be stopped
                // by it (the method's own cap, max_cells, is never reached on these rays).
                if (pr.traced && loop_limited && (res.flags[k] & OM_FLAG_CAPPED) &&
                    ray_fetch_cap(method, s, c.map, pr, oracle[k].t) > kLlvmpipeLoopLimit) {
                    ++st.loop_limited;  // flagged, as a capped walk is: not a wrong answer
                    continue;
                }
                EXPECT_EQ(res.flags[k] & ~OM_FLAG_GRAZING, pr.flags & ~OM_FLAG_GRAZING) << where();
                if (!pr.traced) continue;
                ++st.rays;
                const ExactHit& o = oracle[k];
                // The walk's cap up to the later of its hit and the oracle's (a graze's other
                // answer lies beyond the oracle's).
                const double cap =
                    ray_fetch_cap(method, s, c.map, pr, std::max<double>(o.t, res.depth[k]));
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
                if (hit.texels > st.worst_texels)
                    st.worst_texels = hit.texels, st.worst_case = c.text;
                st.worst_ratio = std::max(st.worst_ratio, hit.share_of_bound);
                if (!hit.ok) {
                    const RayTolerance tol = ray_tolerance(c.map, pr, s, o.t);
                    ++failures;
                    ADD_FAILURE() << where() << ": uv' " << hit.texels << " texels (bound "
                                  << tol.texels << "), t " << res.depth[k] << " vs the oracle's "
                                  << o.t << " (bound " << tol.dt << "); uv " << pr.u << "," << pr.v
                                  << " V " << pr.V[0] << "," << pr.V[1] << "," << pr.V[2];
                }
            }
        }
    }
    for (const char* method : kMethods) {
        const MethodStats& st = stats[method];
        std::printf(
            "%s: %zu rays in %ld cases (seeds %ld-%ld): worst %.3g texels (%s), %.2f of its "
            "bound at most; %zu grazes answered by the other hit; %zu stopped by the driver's loop "
            "limit\n",
            method, st.rays, cases, first, first + cases - 1, st.worst_texels,
            st.worst_case.c_str(), st.worst_ratio, st.grazes, st.loop_limited);
        if (!loop_limited) {
            EXPECT_EQ(st.loop_limited, 0u);
        }
        if (cases == kDefaultCases && first == 1) {
            record_figure(std::string(method) + ".property.rays", static_cast<double>(st.rays));
            record_figure(std::string(method) + ".property.worst_texels", st.worst_texels);
            record_figure(std::string(method) + ".property.worst_share_of_bound", st.worst_ratio);
        }
    }
}

}  // namespace
}  // namespace omtest
