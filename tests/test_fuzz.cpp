// Robustness: every method on adversarial G-buffers and height maps must return finite outputs,
// respect its fetch cap and never crash; and the grazing rule must hold down to 0.1 degrees.
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <limits>

#include "support.hpp"

namespace omtest {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Adversarial height maps: constant 0 and 1, 1x1, non-square, non-power-of-two, a 16-bit
// file, and a float file with values outside [0,1] (clamped on load).
std::vector<std::pair<std::string, HeightMap>> fuzz_maps() {
    namespace fs = std::filesystem;
    std::vector<std::pair<std::string, HeightMap>> maps = {
        {"zero", constant_map(0.0f, 8, 8)},
        {"one", constant_map(1.0f, 8, 8)},
        {"1x1", constant_map(0.6f, 1, 1)},
        {"37x11",
         make_map(37, 11,
                  [](int i, int j) { return 0.5f + 0.5f * std::sin(1.3f * i + 0.7f * j); })},
        {"npot", noisy_map(100, 5)},
    };
    auto dir = fs::temp_directory_path();
    std::string png16 = (dir / "om_fuzz16.png").string(),
                exr = (dir / "om_fuzz_float.exr").string();
    {
        std::vector<uint16_t> px(24 * 20);
        for (size_t k = 0; k < px.size(); ++k) px[k] = static_cast<uint16_t>((k * 7919) % 65536);
        auto out = OIIO::ImageOutput::create(png16);
        out->open(png16, OIIO::ImageSpec(24, 20, 1, OIIO::TypeDesc::UINT16));
        out->write_image(OIIO::TypeDesc::UINT16, px.data());
        out->close();
    }
    {
        std::vector<float> px(16 * 12);
        for (size_t k = 0; k < px.size(); ++k) px[k] = -2.0f + 5.0f * ((k * 37) % 101) / 100.0f;
        auto out = OIIO::ImageOutput::create(exr);
        out->open(exr, OIIO::ImageSpec(16, 12, 1, OIIO::TypeDesc::FLOAT));
        out->write_image(OIIO::TypeDesc::FLOAT, px.data());
        out->close();
    }
    maps.emplace_back("16-bit", load_height_map(png16));
    HeightMap f = load_height_map(exr);
    EXPECT_GT(f.clamped, 0);
    maps.emplace_back("float-out-of-range", f);
    fs::remove(png16);
    fs::remove(exr);
    return maps;
}

// Random uv and V with one pixel in four replaced by a special value in one component; with
// `lod`, a mip level per pixel in [-2, 18] (one in eight special).
GBuffer fuzz_gbuffer(int w, int h, uint64_t seed, bool lod) {
    const float den = std::numeric_limits<float>::denorm_min();
    const float specials[] = {kNaN,   kInf,  -kInf,  0.0f,  -0.0f, den,   -den,
                              1e-30f, 1e30f, -1e30f, 3e38f, 1e6f,  -1e6f, 1e-7f};
    GBuffer gb;
    gb.resize(w, h, false, lod);
    std::mt19937_64 rng(seed);
    auto uni = [&rng](double lo, double hi) {
        return lo + (hi - lo) * ((rng() >> 11) * 0x1.0p-53);
    };
    for (size_t k = 0; k < gb.pixels(); ++k) {
        float c[5] = {static_cast<float>(uni(-2, 3)), static_cast<float>(uni(-2, 3)),
                      static_cast<float>(uni(-1, 1)), static_cast<float>(uni(-1, 1)),
                      static_cast<float>(uni(-0.2, 1))};
        double len = uni(0, 1) < 0.1 ? uni(1e-3, 1e3) : 1.0;  // |V| far from 1 sometimes
        float n = std::sqrt(c[2] * c[2] + c[3] * c[3] + c[4] * c[4]);
        for (int a = 2; a < 5; ++a) c[a] = static_cast<float>(c[a] / n * len);
        if (rng() % 4 == 0) c[rng() % 5] = specials[rng() % (sizeof specials / sizeof *specials)];
        gb.uv[k] = {{c[0], c[1]}};
        gb.view[k] = {{c[2], c[3], c[4], 0.0f}};
        if (lod) gb.lod[k] = rng() % 8 == 0 ? specials[rng() % 4] : static_cast<float>(uni(-2, 18));
    }
    return gb;
}

// The input-classification flags, as prepare_ray (the double-precision reference) sets them.
constexpr uint32_t kInputFlags =
    OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING | OM_FLAG_GRAZING | OM_FLAG_RENORMALIZED;

// Settings per fuzz map: every address mode, grazing policy, a spread of scales and reference
// planes (r < 1 puts the ray's start above the polygon, t < 0), and the LOD system off, on with
// the G-buffer's level, in footprint mode, and in footprint mode from the pre-pass (no level in
// the G-buffer: neighbouring pixels of a random G-buffer are far apart, so levels run high).
PassSettings fuzz_settings(size_t mi, bool* lod_channel) {
    const float scales[] = {0.1f, 0.02f, 0.2f, 0.05f, 0.5f, 0.1f, 0.01f};
    const float refs[] = {1.0f, 0.6f, 0.0f, 0.35f, 1.0f, 0.8f, 0.5f};
    PassSettings s;
    s.scale = scales[mi % 7];
    s.reference_plane = refs[mi % 7];
    s.address = mi % 2 ? AddressMode::Clamp : AddressMode::Wrap;
    s.grazing = mi % 3 == 0   ? GrazingPolicy::Clamp
                : mi % 3 == 1 ? GrazingPolicy::Limit
                              : GrazingPolicy::Cap;
    s.lod.enabled = mi % 4 != 0;
    s.lod.footprint = mi % 4 >= 2;
    *lod_channel = mi % 4 == 1 || mi % 4 == 2;
    return s;
}

TEST(Fuzz, EveryMethodStaysFiniteAndWithinItsCap) {
    // 10^7 pixels in all, split evenly across methods and maps. Per pixel: the input flags as the
    // double-precision reference classifies the input (but for values within float rounding of
    // a threshold), rejected pixels passed through untouched, traced ones finite and within the
    // method's fetch cap for that ray, never CAPPED.
    auto maps = fuzz_maps();
    const auto names = method_names();
    const size_t per_run = 10'000'000 / (names.size() * maps.size()) + 1;
    const int w = 1024, h = static_cast<int>((per_run + w - 1) / w);
    std::map<uint32_t, size_t> seen;  // pixels per flag bit, over every run
    for (size_t mi = 0; mi < maps.size(); ++mi) {
        const auto& [map_name, map] = maps[mi];
        bool lod_channel = false;
        PassSettings s = fuzz_settings(mi, &lod_channel);
        GBuffer gb = fuzz_gbuffer(w, h, 1000 + mi, lod_channel);
        auto rt = runtime();
        DeviceHeightField f = upload(*rt, map, s);
        DeviceGBuffer g = upload(*rt, gb);
        const double grazing_vz = grazing_rule(s, map.width, map.height).min_vz;
        for (const auto& name : names) {
            // sphere: a small distance map keeps the build quick on every map.
            std::map<std::string, std::string> params;
            if (name == "sphere") params = {{"res", "32"}, {"layers", "8"}};
            OffsetPass pass(rt, name, params);
            OffsetResult r = run_offset(*rt, pass, g, f, s, 1);
            size_t bad = 0;
            for (size_t k = 0; k < gb.pixels(); ++k) {
                const double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
                PreparedRay pr =
                    prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s, map.width, map.height);
                uint32_t differ = (r.flags[k] ^ pr.flags) & kInputFlags;
                // Within float rounding of a threshold either side is right.
                const double len = std::sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
                if (std::fabs(std::fabs(len - 1.0) - 1e-3) < 1e-6) differ &= ~OM_FLAG_RENORMALIZED;
                if (std::fabs(V[2] / len - grazing_vz) < 1e-6) differ &= ~OM_FLAG_GRAZING;
                // A V.z that normalises to below the smallest normal float is 0 on the device:
                // back-facing there, grazing in double.
                if (std::fabs(V[2] / len) < std::numeric_limits<float>::min())
                    differ &= ~(OM_FLAG_GRAZING | OM_FLAG_BACKFACING);
                const bool rejected =
                    r.flags[k] & (OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING);
                bool ok =
                    differ == 0 && std::isfinite(r.depth[k]) && !(r.flags[k] & OM_FLAG_CAPPED);
                if (rejected) {
                    ok = ok && std::memcmp(&r.uv[k], &gb.uv[k], sizeof(cl_float2)) == 0 &&
                         r.depth[k] == 0.0f && r.fetches[k] == 0;
                } else {
                    const double t_end =
                        s.lod.enabled ? s.scale * s.reference_plane / pr.V[2] : r.depth[k];
                    ok = ok && std::isfinite(r.uv[k].s[0]) && std::isfinite(r.uv[k].s[1]) &&
                         r.fetches[k] <= ray_fetch_cap(name, s, map, pr, t_end, params);
                    // exact visits every cell up to its hit (one fewer per axis for rounding).
                    if (name == "exact" && !s.lod.enabled) {
                        const double t_enter = -s.scale * (1.0 - s.reference_plane) / pr.V[2];
                        ok = ok && r.fetches[k] + 2.0 >=
                                       cells_crossed(pr, s, map.width, map.height, t_enter, t_end);
                    }
                }
                for (uint32_t bit = 1; bit <= OM_FLAG_OUT_OF_TILE; bit <<= 1)
                    if (r.flags[k] & bit) ++seen[bit];
                seen[0] += !rejected;
                if (!ok && bad++ < 3)
                    ADD_FAILURE() << name << " on " << map_name << " pixel " << k << ": uv ("
                                  << gb.uv[k].s[0] << ", " << gb.uv[k].s[1] << ") V (" << V[0]
                                  << ", " << V[1] << ", " << V[2] << ") -> uv' (" << r.uv[k].s[0]
                                  << ", " << r.uv[k].s[1] << ") depth " << r.depth[k] << " fetches "
                                  << r.fetches[k] << " flags " << r.flags[k] << " (reference "
                                  << pr.flags << ")";
            }
            EXPECT_EQ(bad, 0u) << name << " on " << map_name;
        }
    }
    // Every input class and the LOD fade were met (the fuzzer reaches what it claims to test).
    for (uint32_t bit : {OM_FLAG_EMPTY, OM_FLAG_INVALID, OM_FLAG_BACKFACING, OM_FLAG_GRAZING,
                         OM_FLAG_RENORMALIZED, OM_FLAG_LOD_FADED})
        EXPECT_GT(seen[bit], 1000u) << "flag " << bit;
    std::printf(
        "fuzzed %zu traced pixels; flags seen: empty %zu, invalid %zu, back-facing %zu, "
        "grazing %zu, renormalised %zu, LOD-faded %zu\n",
        seen[0], seen[OM_FLAG_EMPTY], seen[OM_FLAG_INVALID], seen[OM_FLAG_BACKFACING],
        seen[OM_FLAG_GRAZING], seen[OM_FLAG_RENORMALIZED], seen[OM_FLAG_LOD_FADED]);
}

TEST(Fuzz, GrazingRuleHoldsDownToATenthOfADegree) {
    // With the minimum elevation at 0.1 degrees, every method at views from 10 degrees down to 0:
    // flagged GRAZING exactly below the minimum, finite, within its cap, never CAPPED.
    HeightMap m = noisy_map(64, 21);
    PassSettings s;
    s.scale = 0.05f;
    s.min_elevation_deg = 0.1f;
    std::vector<double> elevs = {10, 5, 2, 1, 0.5, 0.2, 0.15, 0.1001, 0.0999, 0.05, 0.01, 0.001, 0};
    std::vector<std::array<float, 5>> px;
    for (double e : elevs)
        for (int a = 0; a < 16; ++a) {
            auto V = view_dir(e, 22.5 * a);
            px.push_back({static_cast<float>(0.05 * a), 0.3f, V[0], V[1], V[2]});
        }
    GBuffer gb = row_gbuffer(px);
    for (const auto& name : method_names()) {
        OffsetResult r = run(name, m, gb, s);
        for (size_t k = 0; k < px.size(); ++k) {
            const double V[3] = {px[k][2], px[k][3], px[k][4]};
            PreparedRay pr = prepare_ray(px[k][0], px[k][1], V, s);
            const double cap = ray_fetch_cap(name, s, m, pr, r.depth[k]);
            double e = elevs[k / 16];
            SCOPED_TRACE(name + " at " + std::to_string(e) + " deg");
            if (e == 0) {
                EXPECT_TRUE(r.flags[k] & OM_FLAG_BACKFACING);  // V.z = 0 is not front-facing
                continue;
            }
            EXPECT_EQ((r.flags[k] & OM_FLAG_GRAZING) != 0, e < 0.1);
            EXPECT_FALSE(r.flags[k] & OM_FLAG_CAPPED);
            EXPECT_LE(r.fetches[k], cap);
            EXPECT_TRUE(std::isfinite(r.uv[k].s[0]) && std::isfinite(r.uv[k].s[1]) &&
                        std::isfinite(r.depth[k]));
            // The march spans at most s / sin(0.1 deg) = 28.6 uv.
            EXPECT_LE(std::fabs(r.depth[k]), s.scale / std::sin(0.1 * M_PI / 180) * 1.0001);
        }
    }
}

}  // namespace
}  // namespace omtest

namespace omtest {
namespace {

TEST(GrazingPolicy, LimitIsOffsetLimitingForEveryMethod) {
    // Under the limit policy rays run along normalize(V.x, V.y, 1): parallax then computes
    // uv - s (r - H) V.xy, which is parallax-limited's formula, and exact meets the relief along
    // that ray (checked against the oracle with the same policy).
    HeightMap m = smooth_map(64);
    PassSettings limit;
    limit.scale = 0.1f;
    limit.grazing = GrazingPolicy::Limit;
    PassSettings clamp = limit;
    clamp.grazing = GrazingPolicy::Clamp;
    GBuffer gb = make_scene(RandomScene{64, 16, 5, 2.0, 90.0});
    OffsetResult par = run("parallax", m, gb, limit), lim = run("parallax-limited", m, gb, clamp);
    OffsetResult ex = run("exact", m, gb, limit);
    for (size_t k = 0; k < gb.pixels(); ++k) {
        for (int a = 0; a < 2; ++a) EXPECT_NEAR(par.uv[k].s[a], lim.uv[k].s[a], 2e-6) << k;
        double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
        PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, limit, m.width, m.height);
        ExactHit o = exact_hit(m, pr.u, pr.v, pr.V, limit);
        EXPECT_LE(std::hypot((ex.uv[k].s[0] - o.u) * m.width, (ex.uv[k].s[1] - o.v) * m.height),
                  1e-3)
            << k;
        // No offset exceeds the slab depth s (in uv) under offset limiting.
        EXPECT_LE(std::hypot(ex.uv[k].s[0] - gb.uv[k].s[0], ex.uv[k].s[1] - gb.uv[k].s[1]),
                  0.1 + 1e-6);
    }
}

TEST(GrazingPolicy, CapBoundsEveryFootprintAndSparesSteeperViews) {
    // Cap at 16 texels: every method's uv' stays within 16 texels of uv (a ray's whole footprint),
    // down to 0.5 degrees; views steep enough to stay under the cap trace exactly as under clamp.
    HeightMap m = noisy_map(64, 8);
    PassSettings cap;
    cap.scale = 0.1f;
    cap.min_elevation_deg = 0.5f;
    cap.grazing = GrazingPolicy::Cap;
    cap.max_offset_texels = 16.0f;
    PassSettings clamp = cap;
    clamp.grazing = GrazingPolicy::Clamp;
    GBuffer gb = make_scene(RandomScene{64, 16, 6, 0.5, 90.0});
    const double steep_enough = std::atan(0.1 * 64 / 16.0) * 180 / M_PI;  // 21.8 degrees
    for (const auto& name : method_names()) {
        OffsetResult c = run(name, m, gb, cap), f = run(name, m, gb, clamp);
        for (size_t k = 0; k < gb.pixels(); ++k) {
            double foot = std::hypot((c.uv[k].s[0] - gb.uv[k].s[0]) * 64,
                                     (c.uv[k].s[1] - gb.uv[k].s[1]) * 64);
            EXPECT_LE(foot, 16.0 + 1e-3) << name << " " << k;
            double elev = std::asin(gb.view[k].s[2]) * 180 / M_PI;
            if (elev > steep_enough + 0.01) {
                EXPECT_EQ(c.uv[k].s[0], f.uv[k].s[0]) << name << " " << k;
                EXPECT_EQ(c.uv[k].s[1], f.uv[k].s[1]) << name << " " << k;
            }
        }
    }
}

}  // namespace
}  // namespace omtest
