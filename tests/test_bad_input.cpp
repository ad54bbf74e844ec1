// Bad input never crashes and never poisons a frame (docs/design.md, "Bad input and grazing views").
#include <filesystem>
#include <fstream>
#include <limits>

#include "support.hpp"

namespace omtest {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

struct BadPixel {
    std::array<float, 5> px;
    uint32_t must_have;  // flags that must be set
    bool passes_through;
};

std::vector<BadPixel> bad_pixels() {
    const float den = std::numeric_limits<float>::denorm_min();
    return {
        {{kNaN, 0.5f, 0, 0, 1}, OM_FLAG_EMPTY, true},
        {{0.5f, kNaN, 0, 0, 1}, OM_FLAG_EMPTY, true},
        {{kInf, 0.5f, 0, 0, 1}, OM_FLAG_INVALID, true},
        {{0.5f, -kInf, 0, 0, 1}, OM_FLAG_INVALID, true},
        {{0.5f, 0.5f, kNaN, 0, 1}, OM_FLAG_INVALID, true},
        {{0.5f, 0.5f, 0, kInf, 1}, OM_FLAG_INVALID, true},
        {{0.5f, 0.5f, 0, 0, -kInf}, OM_FLAG_INVALID, true},
        {{0.5f, 0.5f, 0, 0, 0}, OM_FLAG_INVALID, true},
        {{0.5f, 0.5f, 0.6f, 0, -0.8f}, OM_FLAG_BACKFACING, true},
        {{0.5f, 0.5f, 1, 0, 0}, OM_FLAG_BACKFACING, true},
        {{0.5f, 0.5f, 0, 0, -0.0f}, OM_FLAG_INVALID, true},  // a zero vector
        {{0.5f, 0.5f, 0.5f, 0, -0.0f}, OM_FLAG_BACKFACING, true},
        {{0.5f, 0.5f, 1, 0, 1e-30f}, OM_FLAG_GRAZING, false},
        {{0.5f, 0.5f, 1, 1, den}, OM_FLAG_GRAZING, false},
        {{0.5f, 0.5f, den, 0, den}, OM_FLAG_RENORMALIZED, false},
        {{0.5f, 0.5f, 3e38f, 0, 3e38f}, OM_FLAG_RENORMALIZED, false},
        {{0.5f, 0.5f, 6, 0, 8}, OM_FLAG_RENORMALIZED, false},
        {{1e6f, -1e6f, 0.6f, 0, 0.8f}, 0, false},
        {{-3e38f, 3e38f, 0.6f, 0, 0.8f}, 0, false},
    };
}

TEST(BadInput, EveryMethodPassesThroughFlagsAndStaysFinite) {
    auto bad = bad_pixels();
    std::vector<std::array<float, 5>> px;
    for (auto& b : bad) px.push_back(b.px);
    GBuffer gb = row_gbuffer(px);
    for (AddressMode address : {AddressMode::Wrap, AddressMode::Clamp}) {
        PassSettings s;
        s.scale = 0.2f;
        s.address = address;
        HeightMap m = noisy_map(32);
        // The cap every march obeys (grazing_rule): (s / min_vz)(W + H) + 4 cells.
        double cap = std::ceil(s.scale / std::sin(s.min_elevation_deg * M_PI / 180) * 64) + 4;
        for (const auto& name : method_names()) {
            OffsetResult r = run(name, m, gb, s);
            for (size_t k = 0; k < bad.size(); ++k) {
                SCOPED_TRACE(name + " pixel " + std::to_string(k));
                EXPECT_EQ(r.flags[k] & bad[k].must_have, bad[k].must_have);
                EXPECT_TRUE(std::isfinite(r.depth[k]));
                EXPECT_LE(r.fetches[k], cap);
                if (bad[k].passes_through) {
                    // Bitwise pass-through (NaN stays NaN: the caller's empty marker survives).
                    EXPECT_EQ(std::memcmp(&r.uv[k], &gb.uv[k], sizeof(cl_float2)), 0);
                    EXPECT_EQ(r.fetches[k], 0u);
                    EXPECT_EQ(r.depth[k], 0.0f);
                } else {
                    EXPECT_TRUE(std::isfinite(r.uv[k].s[0]) && std::isfinite(r.uv[k].s[1]));
                }
            }
        }
    }
}

TEST(BadInput, NonUnitViewIsNormalised) {
    // |V| != 1 is flagged and traced as the unit vector: the result equals the unit input's.
    HeightMap m = smooth_map(32);
    PassSettings s;
    s.scale = 0.1f;
    auto V = view_dir(35, 60);
    GBuffer gb = row_gbuffer({{0.3f, 0.7f, V[0], V[1], V[2]},
                              {0.3f, 0.7f, 7 * V[0], 7 * V[1], 7 * V[2]},
                              {0.3f, 0.7f, 1e-3f * V[0], 1e-3f * V[1], 1e-3f * V[2]}});
    for (const auto& name : method_names()) {
        OffsetResult r = run(name, m, gb, s);
        EXPECT_EQ(r.flags[0], 0u);
        for (int k : {1, 2}) {
            EXPECT_EQ(r.flags[k], OM_FLAG_RENORMALIZED) << name;
            EXPECT_NEAR(r.uv[k].s[0], r.uv[0].s[0], 1e-5f) << name;
            EXPECT_NEAR(r.uv[k].s[1], r.uv[0].s[1], 1e-5f) << name;
        }
    }
}

TEST(BadInput, GrazingRuleRaisesViewToMinimumElevation) {
    // Any V below the minimum elevation is traced as V at that elevation and the same azimuth,
    // for every method; the loop count stays under the cap however close V.z is to 0.
    // Every method moves uv along -V.xy, at most the march length s cot(min elevation) (r = 1):
    // an unraised V.z = 1e-20 would throw uv' 1e19 away. Methods continuous in V (no search)
    // must also land where V at the minimum lands: the raised V equals it to a few float ulps
    // (1e-6 relative), which the march length |uv' - uv| (up to s / sin 0.1 deg = 57 uv)
    // multiplies. A search is discontinuous in V (an ulp can move a sample across the relief),
    // so for searches only the direction and the bound are checked.
    HeightMap m = noisy_map(64);
    for (float min_elev : {1.0f, 0.1f}) {
        PassSettings s;
        s.scale = 0.1f;
        s.min_elevation_deg = min_elev;
        auto at_min = view_dir(min_elev, 30);
        auto az = view_dir(0, 30);
        GBuffer gb = row_gbuffer({{0.2f, 0.4f, at_min[0], at_min[1], at_min[2]},
                                  {0.2f, 0.4f, az[0], az[1], 1e-7f},
                                  {0.2f, 0.4f, az[0], az[1], 1e-20f},
                                  {0.2f, 0.4f, az[0], az[1], 0.5f * at_min[2]}});
        const double reach = s.scale / std::tan(min_elev * M_PI / 180);
        for (const auto& name : method_names()) {
            OffsetResult r = run(name, m, gb, s);
            const bool continuous = name == "none" || name == "parallax" ||
                                    name == "parallax-limited" || name == "parallax-slope";
            for (int k = 1; k < 4; ++k) {
                SCOPED_TRACE(name + " pixel " + std::to_string(k));
                EXPECT_TRUE(r.flags[k] & OM_FLAG_GRAZING);
                EXPECT_FALSE(r.flags[k] & OM_FLAG_CAPPED);
                const double du = r.uv[k].s[0] - 0.2, dv = r.uv[k].s[1] - 0.4;
                const double len = std::hypot(du, dv);
                EXPECT_LE(len, reach * (1 + 1e-5) + 1e-6);
                // Along -V.xy: the cross product with the azimuth vanishes, the dot is <= 0.
                EXPECT_NEAR(du * az[1] - dv * az[0], 0.0, 1e-5 * (1 + len));
                EXPECT_LE(du * az[0] + dv * az[1], 1e-6);
                if (continuous) {
                    float tol = 2e-5f + 2e-6f * std::fabs(r.uv[0].s[0] - 0.2f) +
                                2e-6f * std::fabs(r.uv[0].s[1] - 0.4f);
                    EXPECT_NEAR(r.uv[k].s[0], r.uv[0].s[0], tol);
                    EXPECT_NEAR(r.uv[k].s[1], r.uv[0].s[1], tol);
                }
            }
        }
    }
}

TEST(BadInput, HugeUvKeepsTheOffsetOfItsTile) {
    // Tracing in the tile's local frame (wrap mode): uv = k + f traces exactly as f, and only the
    // final uv' = k + (f + offset) rounds, to the nearest float: within half the float spacing at
    // k of the offset of uv = f. Tiles 10^3 and 10^6 (spacing 6.1e-5 and 0.0625 uv) and negative.
    HeightMap m = noisy_map(32);
    PassSettings s;
    s.scale = 0.1f;
    auto V = view_dir(30, 200);
    const float f0 = 0.25f, f1 = 0.5f;
    for (float tile : {1000.0f, 1.0e6f}) {
        GBuffer gb = row_gbuffer({{f0, f1, V[0], V[1], V[2]},
                                  {tile + f0, -tile + f1, V[0], V[1], V[2]},
                                  {-tile + f0, tile + f1, V[0], V[1], V[2]}});
        ASSERT_EQ(gb.uv[1].s[0] - tile, f0);  // the inputs are exact
        ASSERT_EQ(gb.uv[1].s[1] + tile, f1);
        const float half_ulp = 0.5f * (std::nextafter(tile, 2 * tile) - tile);
        for (const auto& name : method_names()) {
            OffsetResult r = run(name, m, gb, s);
            EXPECT_NEAR(r.uv[1].s[0] - tile, r.uv[0].s[0], half_ulp) << name << " at " << tile;
            EXPECT_NEAR(r.uv[1].s[1] + tile, r.uv[0].s[1], half_ulp) << name << " at " << tile;
            EXPECT_NEAR(r.uv[2].s[0] + tile, r.uv[0].s[0], half_ulp) << name << " at -" << tile;
            EXPECT_NEAR(r.uv[2].s[1] - tile, r.uv[0].s[1], half_ulp) << name << " at -" << tile;
            EXPECT_EQ(r.depth[1], r.depth[0]) << name << ": the same ray in the local frame";
            EXPECT_EQ(r.depth[2], r.depth[0]) << name;
        }
    }
}

TEST(BadInput, FilesGiveClearErrors) {
    namespace fs = std::filesystem;
    auto dir = fs::temp_directory_path();
    auto expect_error = [](const std::function<void()>& f, const std::string& needle) {
        try {
            f();
            ADD_FAILURE() << "no error; expected one containing: " << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expect_error([] { load_height_map("/no/such/file.png"); }, "'/no/such/file.png'");
    auto corrupt = (dir / "om_corrupt.png").string();
    {
        std::ofstream f(corrupt, std::ios::binary);
        f << "\x89PNG\r\n\x1a\n this is not a png";
    }
    expect_error([&] { load_height_map(corrupt); }, corrupt);
    auto text = (dir / "om_text.png").string();
    std::ofstream(text) << "hello";
    expect_error([&] { load_height_map(text); }, text);
    expect_error([&] { load_gbuffer("/no/such/gbuffer.exr"); }, "/no/such/gbuffer.exr");
    expect_error([&] { load_gbuffer(corrupt); }, corrupt);
    // Wrong channels: an RGB EXR.
    auto rgb = (dir / "om_rgb.exr").string();
    {
        auto out = OIIO::ImageOutput::create(rgb);
        std::vector<float> px(4 * 4 * 3, 0.5f);
        ASSERT_TRUE(out->open(rgb, OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT)));
        out->write_image(OIIO::TypeDesc::FLOAT, px.data());
        out->close();
    }
    expect_error([&] { load_gbuffer(rgb); }, "lacks channel(s) u v Vx Vy Vz");
    // Empty height map and out-of-range settings.
    HeightMap empty;
    expect_error([&] { upload(*runtime(), empty, PassSettings{}); }, "empty");
    PassSettings bad;
    bad.reference_plane = 1.5f;
    expect_error([&] { validate(bad); }, "reference plane must be in [0, 1], got 1.5");
    bad = PassSettings{};
    bad.scale = std::numeric_limits<float>::quiet_NaN();
    expect_error([&] { validate(bad); }, "scale must be in");
    expect_error([] { Runtime::create("no-such-device-anywhere"); }, "no OpenCL device matches");
    fs::remove(corrupt);
    fs::remove(text);
    fs::remove(rgb);
}

TEST(BadInput, KernelBuildFailureCarriesTheBuildLog) {
    // A broken kernel directory: the error names the file and includes the compiler's log.
    namespace fs = std::filesystem;
    auto dir = fs::temp_directory_path() / "om_broken_kernels";
    fs::remove_all(dir);
    fs::copy(OFFSETMAP_SOURCE_DIR "/kernels", dir, fs::copy_options::recursive);
    std::ofstream(dir / "methods/parallax.cl") << "void om_trace( this is not C";
    setenv("OFFSETMAP_KERNEL_DIR", dir.c_str(), 1);
    // A fresh runtime: the shared one has the good program cached.
    auto rt =
        std::make_shared<Runtime>(runtime()->context(), runtime()->device(), runtime()->queue());
    try {
        OffsetPass pass(rt, "parallax");
        ADD_FAILURE() << "broken kernel built";
    } catch (const Error& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("kernel build failed for"), std::string::npos) << what;
        EXPECT_NE(what.find("methods/parallax.cl"), std::string::npos) << what;
        EXPECT_NE(what.find("error"), std::string::npos) << what;  // the compiler's own words
    }
    unsetenv("OFFSETMAP_KERNEL_DIR");
    // The same folder given to one runtime (offsetmap_bench --ab): its programs read it, and
    // clearing it restores the embedded kernels.
    auto own =
        std::make_shared<Runtime>(runtime()->context(), runtime()->device(), runtime()->queue());
    own->set_kernel_dir(dir.string());
    try {
        OffsetPass pass(own, "parallax");
        ADD_FAILURE() << "broken kernel built from the runtime's kernel folder";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("methods/parallax.cl"), std::string::npos) << e.what();
    }
    own->set_kernel_dir("");
    EXPECT_NO_THROW(OffsetPass(own, "parallax"));
    fs::remove_all(dir);
}

}  // namespace
}  // namespace omtest
