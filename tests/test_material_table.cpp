// The material table file, material ids in G-buffer files and scenes, and method "auto".
#include <unistd.h>

#include <fstream>
#include <set>

#include "support.hpp"

namespace omtest {
namespace {

std::filesystem::path temp_folder(const std::string& name) {
    auto dir =
        std::filesystem::temp_directory_path() / ("om_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(MaterialTable, ReadsEntriesWithDefaultsAndPathsBesideTheFile) {
    const auto dir = temp_folder("table");
    std::ofstream(dir / "t.json") << R"([
        {"id": 3, "height_map": "maps/a.png", "method": "pom", "params": {"min_samples": 4},
         "address": "clamp", "albedo": "/abs/b.png"},
        {"id": 9, "name": "floor", "height_map": "c.png", "scale": 0.02, "reference_plane": 0.5,
         "method": "auto", "error_budget": {"mean_texels": 0.25}, "grazing": "limit",
         "tile_bounds": [0, -1, 5.5, null]}
    ])";
    PassSettings defaults;
    defaults.scale = 0.07f;
    defaults.min_elevation_deg = 3.0f;
    const auto t = read_material_table((dir / "t.json").string(), defaults);
    ASSERT_EQ(t.size(), 2u);
    EXPECT_EQ(t[0].id, 3);
    EXPECT_EQ(t[0].height_map, (dir / "maps/a.png").string());
    EXPECT_EQ(t[0].name, "a.png");
    EXPECT_EQ(t[0].settings.scale, 0.07f) << "not given: the defaults";
    EXPECT_EQ(t[0].settings.min_elevation_deg, 3.0f);
    EXPECT_EQ(t[0].settings.address, AddressMode::Clamp);
    EXPECT_EQ(t[0].params.at("min_samples"), "4");
    EXPECT_EQ(t[0].albedo, "/abs/b.png");
    EXPECT_EQ(t[1].name, "floor");
    EXPECT_EQ(t[1].settings.scale, 0.02f);
    EXPECT_EQ(t[1].settings.reference_plane, 0.5f);
    EXPECT_EQ(t[1].settings.grazing, GrazingPolicy::Limit);
    EXPECT_EQ(t[1].method, "auto");
    EXPECT_EQ(t[1].budget.statistic, ErrorBudget::Statistic::Mean);
    EXPECT_EQ(t[1].budget.texels, 0.25);
    EXPECT_FALSE(t[0].settings.out_of_tile_mask);
    EXPECT_TRUE(t[1].settings.out_of_tile_mask) << "tile bounds turn the mask on";
    const std::array<float, 4> bounds = {0.0f, -1.0f, 5.5f, INFINITY};
    EXPECT_EQ(t[1].settings.tile_bounds, bounds) << "null: an open side";
    EXPECT_EQ(kernel_tile_bounds(t[1].settings)[3], FLT_MAX);
    std::filesystem::remove_all(dir);
}

TEST(MaterialTable, ReadsATriplanarProjection) {
    const auto dir = temp_folder("triplanar_table");
    std::ofstream(dir / "t.json") << R"([{"id": 4, "height_map": "m.png", "projection":
        "triplanar", "world_scale": 0.5, "sharpness": 8, "blend_cutoff": 0.1},
        {"id": 5, "height_map": "m.png", "projection": "uv"}])";
    const std::vector<MaterialSpec> t = read_material_table((dir / "t.json").string());
    EXPECT_TRUE(t[0].triplanar.enabled);
    EXPECT_EQ(t[0].triplanar.world_scale, 0.5f);
    EXPECT_EQ(t[0].triplanar.sharpness, 8.0f);
    EXPECT_EQ(t[0].triplanar.cutoff, 0.1f);
    EXPECT_FALSE(t[1].triplanar.enabled);
    std::filesystem::remove_all(dir);
}

TEST(MaterialTable, RefusesBadEntriesNamingThem) {
    const auto dir = temp_folder("bad_table");
    auto error = [&](const std::string& json) {
        std::ofstream(dir / "t.json") << json;
        return error_of([&] { read_material_table((dir / "t.json").string()); });
    };
    const std::string map = R"("height_map": "m.png")";
    EXPECT_TRUE(contains(error("{}"), "a non-empty list of objects"));
    EXPECT_TRUE(contains(error("[{" + map + "}]"), "entry 1: has no 'id'"));
    EXPECT_TRUE(contains(error(R"([{"id": 0, )" + map + "}]"), "material 0: 'id' must be"));
    EXPECT_TRUE(contains(error(R"([{"id": 2.5, )" + map + "}]"), "'id' must be an integer"));
    EXPECT_TRUE(contains(error(R"([{"id": 1}])"), "material 1: has no 'height_map'"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "scale": "big", )" + map + "}]"),
                         "material 1: 'scale' must be a number, got \"big\""));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "scale": 2, )" + map + "}]"),
                         "material 1: scale must be in [0, 1], got 2"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "address": "mirror", )" + map + "}]"),
                         "'address' must be one of clamp, wrap, got 'mirror'"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "projection": "box", )" + map + "}]"),
                         "'projection' must be one of triplanar, uv, got 'box'"));
    EXPECT_TRUE(
        contains(error(R"([{"id": 1, "world_scale": 2, )" + map + "}]"),
                 "material 1: 'world_scale' applies to \"projection\": \"triplanar\" only"));
    const std::string tri = R"("projection": "triplanar", )";
    EXPECT_TRUE(contains(error(R"([{"id": 1, "sharpness": 100, )" + tri + map + "}]"),
                         "material 1: the triplanar projection: sharpness 100 is out of range"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "blend_cutoff": -1, )" + tri + map + "}]"),
                         "cutoff -1 is out of range"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "address": "clamp", )" + tri + map + "}]"),
                         "material 1: a triplanar projection tiles the world"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "method": "auto", )" + map + "}]"),
                         "method auto needs an 'error_budget'"));
    EXPECT_TRUE(contains(
        error(R"([{"id": 1, "method": "auto", "error_budget": {"p95_texels": 65}, )" + map + "}]"),
        "error budget p95_texels must be in (0, 64] texels, got 65"));
    EXPECT_TRUE(contains(
        error(R"([{"id": 1, "method": "pom", "error_budget": {"p95_texels": 1}, )" + map + "}]"),
        "'error_budget' applies to method auto only"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "tile_bounds": [0, 0, 1], )" + map + "}]"),
                         "material 1: 'tile_bounds' must be [u_min, v_min, u_max, v_max]"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "tile_bounds": [0, "a", 1, 1], )" + map + "}]"),
                         "'tile_bounds' holds numbers or null, got \"a\""));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "tile_bounds": [0, 2, 1, 1], )" + map + "}]"),
                         "material 1: tile bounds must have v_min < v_max"));
    EXPECT_TRUE(contains(error(R"([{"id": 1, "method": "pomm", )" + map + "}]"),
                         "material 1: unknown method 'pomm'"));
    EXPECT_TRUE(contains(
        error(R"([{"id": 4, )" + map + R"(}, {"id": 6, )" + map + R"(}, {"id": 4, )" + map + "}]"),
        "material id 4 appears twice (entries 1 and 3)"));
    std::string many = "[";
    for (int k = 1; k <= OM_MAX_MATERIALS + 1; ++k)
        many +=
            (k > 1 ? "," : "") + std::string(R"({"id": )") + std::to_string(k) + ", " + map + "}";
    EXPECT_TRUE(contains(error(many + "]"), "33 materials; a frame takes at most 32"));
    std::filesystem::remove_all(dir);
}

TEST(MaterialTable, GBufferFilesKeepMaterialIdsAndRefuseFractionalOnes) {
    const auto dir = temp_folder("ids");
    RandomScene r;
    r.width = 24;
    r.height = 10;
    GBuffer gb = make_scene(r);
    lay_out_materials(gb, {0, 4, 65535});
    const std::string file = (dir / "g.exr").string();
    save_gbuffer(file, gb);
    const GBuffer back = load_gbuffer(file);
    ASSERT_EQ(back.material, gb.material);
    gb.material[5 * 24 + 7] = 2.5f;
    save_gbuffer(file, gb);
    EXPECT_TRUE(contains(error_of([&] { load_gbuffer(file); }),
                         "channel 'material' holds 2.500000 at pixel (7, 5)"));
    std::filesystem::remove_all(dir);
}

TEST(MaterialTable, LayOutGivesEachUvTileOneIdAndEmptyPixelsNone) {
    PlaneScene p;
    p.width = 160;
    p.height = 90;
    GBuffer gb = make_scene(p);
    lay_out_materials(gb, {2, 5, 9});
    std::map<std::pair<int, int>, float> tile_id;
    std::set<float> seen;
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const float u = gb.uv[k].s[0], v = gb.uv[k].s[1];
        if (std::isnan(u)) {
            ASSERT_EQ(gb.material[k], 0.0f);
            continue;
        }
        auto [it, fresh] = tile_id.emplace(
            std::make_pair(static_cast<int>(std::floor(u)), static_cast<int>(std::floor(v))),
            gb.material[k]);
        ASSERT_EQ(it->second, gb.material[k]) << "one id per uv tile";
        seen.insert(gb.material[k]);
    }
    EXPECT_EQ(seen, (std::set<float>{2, 5, 9}));
}

// The choice meets the budget on the calibration set, nothing cheaper does, and a second call
// reads the same measurements back from the cache.
TEST(AutoMethod, PicksTheCheapestCandidateWithinTheBudget) {
    auto rt = runtime();
    const auto dir = temp_folder("auto_cache");
    LoadedMaterial m;
    m.spec.id = 2;
    m.spec.name = "smooth";
    m.spec.method = "auto";
    m.spec.budget = {ErrorBudget::Statistic::P95, 0.5};
    m.map = smooth_map(64);
    RandomScene r;
    r.width = 96;
    r.height = 64;
    r.min_elevation_deg = 15.0;
    GBuffer frame = make_scene(r);
    lay_out_materials(frame, {2});
    AutoOptions o;
    o.cache_dir = dir.string();
    o.repeats = 3;
    const AutoChoice a = choose_method(rt, m, frame, o);
    size_t grid = 0;
    for (const auto& info : methods()) grid += std::max<size_t>(1, info.sweep.size());
    ASSERT_EQ(a.candidates.size() + a.skipped, grid);
    EXPECT_EQ(a.skipped, 3u)
        << "sphere's 256^2 x 32 (two settings) and 512^2 x 64 distance maps (8 and 64 MiB)";
    EXPECT_EQ(a.pixels, 96u * 64u);
    EXPECT_GT(a.samples, 1000u);
    auto cost = [&](const AutoCandidate& c) { return a.by_time ? c.ns_per_pixel : c.fetches; };
    EXPECT_LE(a.chosen.error.p95, 0.5);
    for (const AutoCandidate& c : a.candidates) {
        if (c.error.p95 <= 0.5) {
            EXPECT_GE(cost(c), cost(a.chosen)) << c.params.method->name;
        }
        // Against the exact hit in double precision, the exact kernel is off by rounding only.
        if (c.params.method->name == "exact") {
            EXPECT_LT(c.error.max, 0.01);
        }
        if (c.params.method->name == "none") {
            EXPECT_GT(c.error.p95, 1.0);
        }
    }
    ASSERT_NE(a.runner_up.params.method, nullptr);
    EXPECT_LE(a.runner_up.error.p95, 0.5);
    EXPECT_GE(cost(a.runner_up), cost(a.chosen));
    const AutoChoice again = choose_method(rt, m, frame, o);
    EXPECT_TRUE(again.cached);
    EXPECT_EQ(again.chosen.params.method, a.chosen.params.method);
    EXPECT_EQ(again.chosen.setting, a.chosen.setting);
    // Other kernels (an edited kernel folder; a newer library's) are another key: measured anew.
    {
        const auto kernels = temp_folder("auto_kernels");
        std::filesystem::copy(std::string(OFFSETMAP_SOURCE_DIR) + "/kernels", kernels,
                              std::filesystem::copy_options::recursive);
        std::ofstream(kernels / "methods" / "pom.cl", std::ios::app) << "\n// edited\n";
        ASSERT_EQ(std::getenv("OFFSETMAP_KERNEL_DIR"), nullptr);
        setenv("OFFSETMAP_KERNEL_DIR", kernels.c_str(), 1);
        const AutoChoice edited = choose_method(rt, m, frame, o);
        unsetenv("OFFSETMAP_KERNEL_DIR");
        std::filesystem::remove_all(kernels);
        EXPECT_FALSE(edited.cached);
    }
    // A predicate narrows the choice to the cheapest admitted candidate within the budget, and
    // names itself when none is.
    AutoOptions other = o;
    const std::string chosen = a.chosen.params.method->name;
    other.admits = [&](const MethodParams& p) { return p.method->name != chosen; };
    other.admits_text = "but " + chosen;
    const AutoChoice narrowed = choose_method(rt, m, frame, other);
    EXPECT_NE(narrowed.chosen.params.method->name, chosen);
    EXPECT_LE(narrowed.chosen.error.p95, 0.5);
    for (const AutoCandidate& c : a.candidates) {
        if (c.params.method->name != chosen && c.error.p95 <= 0.5) {
            EXPECT_GE(cost(c), cost(narrowed.chosen)) << c.params.method->name;
        }
    }
    other.admits = [](const MethodParams&) { return false; };
    EXPECT_TRUE(contains(error_of([&] { choose_method(rt, m, frame, other); }),
                         "material 2 (smooth): no method but " + chosen +
                             " meets its error budget (p95 0.5 texels); none of the " +
                             std::to_string(a.candidates.size()) + " candidates measured is one"));
    m.spec.budget.texels = 1e-9;
    EXPECT_TRUE(contains(error_of([&] { choose_method(rt, m, frame, o); }),
                         "material 2 (smooth): no method meets its error budget (p95 1e-09 "
                         "texels); the best reached is p95 "));
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace omtest
