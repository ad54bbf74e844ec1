// The exact kernel (float) against the independent double-precision host oracle, held to the
// per-ray bound of oracle_bound.hpp.
#include "methods/cone_map.h"
#include "oracle_bound.hpp"

namespace omtest {
namespace {

struct Case {
    const char* name;
    HeightMap map;
};

struct OracleStats {
    double worst = 0.0;        // texels
    double worst_ratio = 0.0;  // of the ray's tolerance, uv' or depth
    size_t grazes = 0;         // rays whose kernel hit is the graze's other answer
};

OracleStats compare_with_oracle(const HeightMap& map, const char* name, float scale, float ref,
                                double min_elev, AddressMode address,
                                const std::string& method = "exact", double max_elev = 90.0) {
    PassSettings s;
    s.scale = scale;
    s.reference_plane = ref;
    s.address = address;
    s.min_elevation_deg = static_cast<float>(std::min(1.0, 0.8 * min_elev));  // none raised
    GBuffer gb = make_scene(RandomScene{64, 32, 2024, min_elev, max_elev});
    OffsetResult res = run(method, map, gb, s);
    OracleStats st;
    size_t worst_k = 0;
    for (size_t k = 0; k < gb.pixels(); ++k) {
        EXPECT_EQ(res.flags[k] & ~OM_FLAG_GRAZING, 0u) << k;
        double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
        PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s);
        ExactHit o = exact_hit(map, pr.u, pr.v, pr.V, s);
        RayTolerance tol = ray_tolerance(map, pr, s, o.t);
        double e =
            std::hypot((res.uv[k].s[0] - o.u) * map.width, (res.uv[k].s[1] - o.v) * map.height);
        const double ratio = std::max(e / tol.texels, std::fabs(res.depth[k] - o.t) / tol.dt);
        if (ratio > 1.0 && other_answer_of_a_graze(map, pr, s, o.t, res.depth[k], res.uv[k].s[0],
                                                   res.uv[k].s[1])) {
            ++st.grazes;
            continue;
        }
        if (e > st.worst) st.worst = e, worst_k = k;
        st.worst_ratio = std::max(st.worst_ratio, ratio);
        EXPECT_LE(e, tol.texels) << method << " " << name << " s=" << scale << " r=" << ref
                                 << " pixel " << k;
        EXPECT_LE(std::fabs(res.depth[k] - o.t), tol.dt)
            << method << " " << name << " depth, pixel " << k;
    }
    std::printf(
        "%s vs oracle, %s s=%.2f r=%.1f, %g-%g deg: worst %.2e texel (pixel %zu), %.2f of "
        "its tolerance at most; %zu grazes answered by the other hit\n",
        method.c_str(), name, scale, ref, min_elev, max_elev, st.worst, worst_k, st.worst_ratio,
        st.grazes);
    return st;
}

// 48 x 20: non-square, not a power of two, 20 not a multiple of 8.
HeightMap nonsquare_map() {
    return make_map(48, 20, [](int i, int j) {
        return static_cast<float>(0.5 + 0.45 * std::sin(0.7 * i) * std::cos(0.9 * j));
    });
}

// The worst disagreement and its share of the per-ray tolerance over several comparisons.
struct Worst {
    double texels = 0.0, ratio = 0.0;
    size_t rays = 0;
    void add(const OracleStats& s) {
        texels = std::max(texels, s.worst);
        ratio = std::max(ratio, s.worst_ratio);
        rays += 64 * 32;
    }
    void record(const std::string& key) const {
        record_figure(key + ".worst_texels", texels);
        record_figure(key + ".worst_share_of_tolerance", ratio);
        record_figure(key + ".rays", static_cast<double>(rays));
    }
};

// A method that ends in exact's patch solve (maxmip, cone), held to exact's bound: smooth, noisy
// and cliff maps at both scales and reference planes, plus `extra` maps, wrapped; the non-square
// map wrapped and clamped.
void agrees_like_exact(const std::string& method, std::vector<Case> extra = {}) {
    std::vector<Case> cases = {{"smooth", smooth_map(64)},
                               {"noisy", noisy_map(64)},
                               {"cliffs", cliff_map(64)},
                               {"noisy-256", noisy_map(256, 9)}};
    for (auto& c : extra) cases.push_back(std::move(c));
    Worst worst;
    for (const auto& c : cases)
        for (float scale : {0.05f, 0.2f})
            for (float ref : {1.0f, 0.6f})
                worst.add(
                    compare_with_oracle(c.map, c.name, scale, ref, 5.0, AddressMode::Wrap, method));
    HeightMap m = nonsquare_map();
    worst.add(compare_with_oracle(m, "nonsquare-wrap", 0.1f, 0.8f, 5.0, AddressMode::Wrap, method));
    worst.add(
        compare_with_oracle(m, "nonsquare-clamp", 0.1f, 1.0f, 5.0, AddressMode::Clamp, method));
    worst.record(method + ".oracle");
}

TEST(ExactOracle, AgreesOnRandomRaysDownTo5Degrees) {
    std::vector<Case> cases = {{"smooth", smooth_map(64)},
                               {"noisy", noisy_map(64)},
                               {"cliffs", cliff_map(64)},
                               {"noisy-256", noisy_map(256, 9)}};
    Worst worst;
    for (const auto& c : cases)
        for (float scale : {0.05f, 0.2f})
            for (float ref : {1.0f, 0.6f})
                worst.add(compare_with_oracle(c.map, c.name, scale, ref, 5.0, AddressMode::Wrap));
    worst.record("exact.oracle.5to90");
}

TEST(ExactOracle, AgreesAtGrazingViewsDownToHalfADegree) {
    // The grazing tables (docs/conventions.md) use exact as the truth down to 1 degree: rays from 0.5 to 5
    // degrees (the grazing rule set to 0.5 degrees, so none is raised), long walks of up to
    // s / sin(0.5 deg) = 5.7 uv (370 cells of a 64^2 map at s = 0.05).
    std::vector<Case> cases = {
        {"smooth", smooth_map(64)}, {"noisy", noisy_map(64)}, {"cliffs", cliff_map(64)}};
    Worst worst;
    for (const auto& c : cases)
        for (float ref : {1.0f, 0.6f})
            for (AddressMode address : {AddressMode::Wrap, AddressMode::Clamp})
                worst.add(
                    compare_with_oracle(c.map, c.name, 0.05f, ref, 0.5, address, "exact", 5.0));
    worst.record("exact.oracle.grazing");
}

TEST(ExactOracle, AgreesWithClampAddressingAndNonSquareMaps) {
    HeightMap m = nonsquare_map();
    compare_with_oracle(m, "nonsquare-clamp", 0.1f, 1.0f, 5.0, AddressMode::Clamp);
    compare_with_oracle(m, "nonsquare-wrap", 0.1f, 0.8f, 5.0, AddressMode::Wrap);
}

// A map cropped to w x h (odd sizes: blocks cut at the tile's edges, a padded pyramid).
HeightMap cropped(const HeightMap& m, int w, int h) {
    return make_map(w, h, [&](int i, int j) { return m.h[static_cast<size_t>(j) * m.width + i]; });
}

TEST(MaxMip, AgreesWithTheOracleLikeExact) {
    // The same bound as exact: maxmip ends in the same patch solve; its skips are exact decisions.
    // 48 x 20 has two levels, wrapped and clamped.
    agrees_like_exact("maxmip");
}

// Odd, uneven, tall and thin sizes under both address modes, at grazing views where rays cross
// several tiles (thin maps: hundreds): the oracle's bound, as exact's. Sizes that are not
// multiples of 8 leave cone's block maxima untiled and maxmip's pyramid padded; the thin map is
// narrower than one of either's blocks; the tall one walks cells far from the origin.
void agrees_on_odd_maps(const std::string& method) {
    const HeightMap tall_noise = noisy_map(1024, 17);
    const std::vector<Case> cases = {{"smooth-63x61", cropped(smooth_map(64), 63, 61)},
                                     {"cliffs-61x63", cropped(cliff_map(64), 61, 63)},
                                     {"noisy-65x9", cropped(noisy_map(256, 3), 65, 9)},
                                     {"thin-4x1024", cropped(tall_noise, 4, 1024)},
                                     {"tall-24x1000", cropped(tall_noise, 24, 1000)}};
    Worst worst;
    size_t grazes = 0;
    for (const auto& c : cases)
        for (AddressMode address : {AddressMode::Wrap, AddressMode::Clamp})
            for (float ref : {1.0f, 0.6f}) {
                for (auto st :
                     {compare_with_oracle(c.map, c.name, 0.1f, ref, 5.0, address, method),
                      compare_with_oracle(c.map, c.name, 0.05f, ref, 1.0, address, method, 5.0)}) {
                    worst.add(st);
                    grazes += st.grazes;
                }
            }
    worst.record(method + ".oracle.odd");
    record_figure(method + ".oracle.odd.grazes", static_cast<double>(grazes));
}

// A 4 x 16384 map (the rows of data/rocks.png repeated 64 times, then its first 4 columns) under
// the camera plane at its defaults, every third pixel: rays cross thousands of cells in v, where a
// cell position rounded at the size of v itself (0.002 of a cell) let cone and maxmip, which solve
// a cell from the middle after a jump, find a root where the ray passes the relief by 1e-5 (13
// texels off the oracle's hit). Held to the per-ray bound with no graze excused.
TEST(Cone, ExactOnAThinMapThousandsOfCellsTall) {
    const HeightMap rocks = load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png");
    HeightMap map =
        make_map(4, 64 * rocks.height, [&](int i, int j) { return rocks.at(i, j % rocks.height); });
    PlaneScene p;
    p.width = 960;
    p.height = 540;
    const GBuffer gb = make_scene(p);
    PassSettings s;
    s.scale = 0.05f;
    for (const char* method : {"cone", "maxmip", "exact"}) {
        const OffsetResult res = run(method, map, gb, s);
        double worst = 0.0;
        for (size_t k = 0; k < gb.pixels(); k += 3) {
            const double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
            const PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s);
            if (!pr.traced) continue;
            const ExactHit o = exact_hit(map, pr.u, pr.v, pr.V, s);
            const RayTolerance tol = ray_tolerance(map, pr, s, o.t);
            const double e =
                std::hypot((res.uv[k].s[0] - o.u) * map.width, (res.uv[k].s[1] - o.v) * map.height);
            worst = std::max(worst, e);
            ASSERT_LE(e, tol.texels)
                << method << " pixel " << k << ": t " << res.depth[k] << ", the oracle's " << o.t;
        }
        std::printf("%s on the 4 x 16384 map: worst %.4f texels from the oracle\n", method, worst);
    }
}

// maxmip: the pyramid padded, blocks cut at tile edges; clamp: outside the tile the edge blocks
// bound the extruded relief.
TEST(MaxMip, AgreesWithTheOracleOnOddSizesAndClampAddressing) { agrees_on_odd_maps("maxmip"); }

// The beam (common/beam.cl) under cone, whose pyramid lies after the cone map's tiles: a camera's
// neighbouring pixels skip together, then walk on; every pixel of a 320 x 180 plane frame within
// its bound of the oracle (or a graze's other answer), on maps of one and several cone tiles a side
// (the pyramid's offset), a rocks crop, cliffs and spikes, both address modes, r 1 and 0.6. The
// beam's own steps show in the fetches: it ran. (maxmip's beam: the property test's coherent rays.)
TEST(Cone, WithTheBeamMeetsTheOracleOnACameraFrame) {
    const HeightMap rocks = load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png");
    const std::vector<Case> cases = {
        {"rocks-96x64", cropped(rocks, 96, 64)},
        {"cliffs-64", cliff_map(64)},
        {"spikes-32x128", make_map(32, 128, [](int i, int j) {
             return (i % 5 == 1 && j % 7 == 2) ? 1.0f : 0.02f;
         })}};
    PlaneScene p;
    p.width = 320;
    p.height = 180;
    const GBuffer gb = make_scene(p);
    for (const auto& c : cases)
        for (AddressMode address : {AddressMode::Wrap, AddressMode::Clamp})
            for (float ref : {1.0f, 0.6f}) {
                PassSettings s;
                s.scale = 0.1f;
                s.reference_plane = ref;
                s.address = address;
                const OffsetResult with = run("cone", c.map, gb, s, {{"beam", "1"}});
                const OffsetResult without = run("cone", c.map, gb, s);
                size_t grazes = 0, traced = 0;
                for (size_t k = 0; k < gb.pixels(); ++k) {
                    const double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
                    const PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s,
                                                       c.map.width, c.map.height);
                    if (!pr.traced) continue;
                    ++traced;
                    const ExactHit o = exact_hit(c.map, pr.u, pr.v, pr.V, s);
                    const HitVerdict hit = judge_hit(c.map, pr, s, o, with.uv[k].s[0],
                                                     with.uv[k].s[1], with.depth[k]);
                    grazes += hit.graze;
                    ASSERT_TRUE(hit.ok || hit.graze)
                        << c.name << " pixel " << k << ": " << hit.texels << " texels, t "
                        << with.depth[k] << ", the oracle's " << o.t;
                }
                EXPECT_LT(grazes, traced / 100) << c.name;
                EXPECT_NE(mean_fetches(with), mean_fetches(without)) << c.name;
            }
}

TEST(MaxMip, LevelZeroIsExactAndTheHierarchySavesFetchesOnLongRays) {
    // Long traversals (smooth relief, grazing views, large s) are where a max pyramid pays: blocks
    // above the ray are skipped whole. On noise every block's maximum is near 1 and rays hit
    // within a few cells, so the walk costs a little more than exact's DDA (reported, not
    // asserted).
    PassSettings s;
    s.scale = 0.1f;
    GBuffer grazing = make_scene(RandomScene{64, 64, 31, 5.0, 30.0});
    auto fetches = [&](const HeightMap& m, const std::string& method,
                       const std::map<std::string, std::string>& p = {}) {
        OffsetResult r = run(method, m, grazing, s, p);
        double sum = 0;
        for (auto f : r.fetches) sum += f;
        return std::make_pair(r, sum / grazing.pixels());
    };
    HeightMap smooth = smooth_map(256), noise = noisy_map(256, 4);
    auto [ex, fe] = fetches(smooth, "exact");
    auto [flat, ff] = fetches(smooth, "maxmip", {{"max_level", "0"}});
    auto [mm, fm] = fetches(smooth, "maxmip");
    for (size_t k = 0; k < grazing.pixels(); ++k)
        ASSERT_EQ(std::memcmp(&flat.uv[k], &ex.uv[k], sizeof(cl_float2)), 0)
            << "level 0 is exact, pixel " << k;
    EXPECT_EQ(ff, fe);
    std::printf("fetches per pixel, 256^2 smooth map, 5-30 deg, s = 0.1: exact %.1f, maxmip %.1f\n",
                fe, fm);
    EXPECT_LT(fm, 0.5 * fe);
    auto [nex, nfe] = fetches(noise, "exact");
    auto [nmm, nfm] = fetches(noise, "maxmip");
    std::printf("fetches per pixel, 256^2 noise (worst case): exact %.1f, maxmip %.1f\n", nfe, nfm);
    // An odd size and clamp addressing keep the hierarchy (they used to fall back to exact's walk).
    const HeightMap odd = cropped(smooth_map(256), 255, 251);
    const double fo = fetches(odd, "exact").second, fmo = fetches(odd, "maxmip").second;
    s.address = AddressMode::Clamp;
    const double fc = fetches(smooth, "exact").second, fmc = fetches(smooth, "maxmip").second;
    std::printf(
        "255 x 251 wrapped: exact %.1f, maxmip %.1f; 256^2 clamped: exact %.1f, maxmip %.1f\n", fo,
        fmo, fc, fmc);
    EXPECT_LT(fmo, 0.5 * fo);
    EXPECT_LT(fmc, 0.5 * fc);
}

TEST(Cone, AgreesWithTheOracleLikeExact) {
    // The same bound as exact: cone ends in the same patch solve, and its cone steps never cross
    // relief, so a skipped thin feature would show up here as a wrong hit. On 48 x 20 (wrap) block
    // maxima do not tile (20 % 8), so the build visits every cell in reach.
    agrees_like_exact("cone", {{"spikes", make_map(64, 64, [](int i, int j) {
                                    return (i % 7 == 3 && j % 5 == 1) ? 1.0f : 0.05f;
                                })}});
}

// cone: block maxima that do not tile the map (every cell in reach visited instead), cones wider
// than a thin map (the search wraps around it many times), and clamp (no cones off the map).
TEST(Cone, AgreesWithTheOracleOnOddTallAndThinMaps) { agrees_on_odd_maps("cone"); }

// sphere with cells (its default): the distance map skips empty space, the cells of every voxel
// that comes near the proxy are solved as exact solves them, so at its defaults (res 256, 64
// steps) it is held to exact's per-ray bound, on maps coarser and finer than its voxel grid
// (1025^2: four texels a voxel, where stopping at the proxy, Donnelly's end, is texels off).
TEST(Sphere, CellsMakeItExactAtItsDefaults) {
    const std::vector<Case> cases = {{"smooth-1025", smooth_map(1025)},
                                     {"cliffs-1024", cliff_map(1024)},
                                     {"noisy-256", noisy_map(256, 9)},
                                     {"cliffs", cliff_map(64)}};
    // One scale: the distance map's build grows with s (5 s a map at s = 0.2 here).
    Worst worst;
    for (const auto& c : cases)
        for (float ref : {1.0f, 0.6f})
            if (c.map.width <= 256 || ref == 1.0f)
                worst.add(compare_with_oracle(c.map, c.name, 0.05f, ref, 5.0, AddressMode::Wrap,
                                              "sphere"));
    worst.record("sphere.oracle");
    // Donnelly's end on the same rays, for scale (mean texels from the oracle's hit).
    PassSettings s;
    s.scale = 0.05f;
    GBuffer gb = make_scene(RandomScene{64, 32, 2024, 5.0, 90.0});
    for (const Case* c : {&cases[0], &cases[1]}) {
        double sum = 0.0;
        OffsetResult r = run("sphere", c->map, gb, s, {{"cells", "0"}});
        for (size_t k = 0; k < gb.pixels(); ++k) {
            double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
            PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s);
            ExactHit o = exact_hit(c->map, pr.u, pr.v, pr.V, s);
            sum += std::hypot((r.uv[k].s[0] - o.u) * c->map.width,
                              (r.uv[k].s[1] - o.v) * c->map.height);
        }
        std::printf("sphere without cells, %s s=0.05: mean %.3f texels\n", c->name,
                    sum / gb.pixels());
        record_figure(std::string("sphere.nocells.") + c->name + ".mean", sum / gb.pixels());
    }
}

// The bilinear relief of `map` at texel-space point (x, y) (integer = texel centre), wrapped.
double bilinear_wrap(const HeightMap& map, double x, double y) {
    double fx = std::floor(x), fy = std::floor(y), a = x - fx, b = y - fy;
    auto at = [&](long i, long j) {
        i = ((i % map.width) + map.width) % map.width;
        j = ((j % map.height) + map.height) % map.height;
        return static_cast<double>(map.h[j * map.width + i]);
    };
    long i = static_cast<long>(fx), j = static_cast<long>(fy);
    return (1 - b) * ((1 - a) * at(i, j) + a * at(i + 1, j)) +
           b * ((1 - a) * at(i, j + 1) + a * at(i + 1, j + 1));
}

TEST(Cone, MapHoldsNoReliefInsideAnyCellConeAndIsNotLooser) {
    // Straight from the definition, on the words as the method decodes them: for every cell C and
    // relief points q sampled 5 x 5 per cell (corners and edges included) around it,
    // dist(q, C) >= c (H(q) - Hc), and Hc bounds C's patch (the corners exactly: the packing
    // rounds Hc up). max_ratio 12 bounds the cones, so points beyond 12 + sqrt 2 texels cannot
    // matter. And not looser than the cell discretisation: a cone below max_ratio is set by a cell
    // D at gap delta whose highest corner (sampled) lies within delta + sqrt 2 of C (for touching
    // cells: 1 for delta = 1, sqrt 2 for delta = 1/sqrt 2), so the samples' bound is <= 2.42 c;
    // rounding c down to 16 bits adds at most 2 / (2047 sqrt c), under 0.3 % here (c > 0.2).
    // 40 x 36 cells: two tiles across and down, the second ones partly padding.
    const int nx = 40, ny = 36, reach = 15;
    HeightMap map = noisy_map(nx, 21);
    map.height = ny;
    map.h.resize(static_cast<size_t>(nx) * ny);
    PassSettings s;
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, map, s);
    OffsetPass pass(rt, "cone", {{"max_ratio", "12"}});
    pass.prepare(f, s);
    const int tiles_x = om_cone_tiles(nx);
    const size_t words =
        static_cast<size_t>(tiles_x) * om_cone_tiles(ny) * OM_CONE_TILE * OM_CONE_TILE;
    EXPECT_EQ(pass.precomputed().bytes, words * sizeof(cl_uint));
    std::vector<cl_uint> cone(words);
    rt->queue().enqueueReadBuffer(pass.precomputed_buffer(), CL_TRUE, 0,
                                  cone.size() * sizeof(cl_uint), cone.data());
    double loosest = 0.0;
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const cl_uint q = cone[OM_CONE_INDEX(i, j, tiles_x)];
            const double hc = om_cone_hc(q), c = om_cone_ratio(q);
            ASSERT_GT(c, 0.0);
            ASSERT_LE(c, 12.0);
            double worst = 1e9;
            for (int sy = 4 * (j - reach); sy <= 4 * (j + reach + 1); ++sy) {
                for (int sx = 4 * (i - reach); sx <= 4 * (i + reach + 1); ++sx) {
                    const double x = sx / 4.0, y = sy / 4.0, h = bilinear_wrap(map, x, y);
                    const double gx = std::max({i - x, x - (i + 1), 0.0}),
                                 gy = std::max({j - y, y - (j + 1), 0.0});
                    if (gx == 0.0 && gy == 0.0) {
                        ASSERT_LE(h, hc + 1e-12) << "cell " << i << "," << j;
                        continue;
                    }
                    if (h > hc) worst = std::min(worst, std::hypot(gx, gy) / (h - hc));
                }
            }
            ASSERT_GE(worst, c * (1 - 1e-5)) << "cell " << i << "," << j << " cone " << c;
            if (c < 11.9) {
                EXPECT_LE(worst, 2.42 * 1.003 * c) << "cell " << i << "," << j << " cone " << c;
                loosest = std::max(loosest, worst / c);
            }
        }
    }
    std::printf("cone map 40 x 36 noise: sampled bound / stored cone at most %.2f\n", loosest);
    record_figure("cone.map.loosest", loosest);
}

TEST(Cone, SavesFetchesOverExactOnLongRays) {
    PassSettings s;
    s.scale = 0.1f;
    GBuffer grazing = make_scene(RandomScene{64, 64, 31, 5.0, 30.0});
    auto fetches = [&](const HeightMap& m, const std::string& method) {
        OffsetResult r = run(method, m, grazing, s);
        double sum = 0;
        for (auto f : r.fetches) sum += f;
        return sum / grazing.pixels();
    };
    HeightMap smooth = smooth_map(256), noise = noisy_map(256, 4);
    const double fe = fetches(smooth, "exact"), fm = fetches(smooth, "maxmip"),
                 fc = fetches(smooth, "cone");
    std::printf(
        "fetches per pixel, 256^2 smooth map, 5-30 deg, s = 0.1: exact %.1f, maxmip %.1f, cone "
        "%.1f\n",
        fe, fm, fc);
    record_figure("longrays.exact.fetches", fe);
    record_figure("longrays.maxmip.fetches", fm);
    record_figure("longrays.cone.fetches", fc);
    EXPECT_LT(fc, 0.5 * fe);
    std::printf("fetches per pixel, 256^2 noise: exact %.1f, maxmip %.1f, cone %.1f\n",
                fetches(noise, "exact"), fetches(noise, "maxmip"), fetches(noise, "cone"));
}

TEST(ExactOracle, OracleMatchesBruteForceMarch) {
    // The oracle itself against a fine march with bisection (independent of its segment logic),
    // from the top plane (t < 0 when r < 1) to the bottom, on noise, cliffs and a smooth map,
    // wrapped and clamped, r = 1, 0.6 and 0.
    struct Setup {
        const char* name;
        HeightMap map;
        float scale, ref;
        AddressMode address;
    };
    const std::vector<Setup> setups = {
        {"noisy-wrap", noisy_map(32, 3), 0.15f, 1.0f, AddressMode::Wrap},
        {"noisy-clamp", noisy_map(32, 3), 0.15f, 0.6f, AddressMode::Clamp},
        {"cliffs-wrap", cliff_map(32, 7), 0.1f, 0.6f, AddressMode::Wrap},
        {"cliffs-clamp", cliff_map(32, 7), 0.2f, 1.0f, AddressMode::Clamp},
        {"smooth-r0", smooth_map(32), 0.1f, 0.0f, AddressMode::Wrap},
    };
    for (const auto& c : setups) {
        PassSettings s;
        s.scale = c.scale;
        s.reference_plane = c.ref;
        s.address = c.address;
        GBuffer gb = make_scene(RandomScene{32, 8, 77, 10.0, 90.0});
        size_t above_polygon = 0;
        for (size_t k = 0; k < gb.pixels(); ++k) {
            double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
            PreparedRay pr = prepare_ray(gb.uv[k].s[0], gb.uv[k].s[1], V, s);
            ExactHit o = exact_hit(c.map, pr.u, pr.v, pr.V, s);
            auto gap = [&](double t) {
                return -t * pr.V[2] - s.scale * (bilinear_height(c.map, pr.u - t * pr.V[0],
                                                                 pr.v - t * pr.V[1], s.address) -
                                                 s.reference_plane);
            };
            const double t0 = -s.scale * (1.0 - s.reference_plane) / pr.V[2];
            const double t1 = s.scale * s.reference_plane / pr.V[2];
            double dt = (t1 - t0) / 20000, t = t0;
            if (gap(t0) > 0) {
                while (t < t1 && gap(t + dt) > 0) t += dt;
            }
            double lo = t, hi = gap(t0) > 0 ? std::min(t + dt, t1) : t0;
            for (int it = 0; it < 60 && hi > lo; ++it) {
                double mid = 0.5 * (lo + hi);
                (gap(mid) > 0 ? lo : hi) = mid;
            }
            // A march of 20000 steps can only miss a dip shallower than its step; none here is.
            EXPECT_NEAR(o.t, hi, 1e-9 + 1e-6 * (t1 - t0)) << c.name << " " << k;
            EXPECT_NEAR(o.u, pr.u - hi * pr.V[0], 1e-9 + 1e-6 * (t1 - t0)) << c.name << " " << k;
            above_polygon += o.t < 0;
        }
        if (c.ref < 1.0f) {
            EXPECT_GT(above_polygon, 0u) << c.name << ": t < 0 is exercised";
        }
    }
}

}  // namespace
}  // namespace omtest
