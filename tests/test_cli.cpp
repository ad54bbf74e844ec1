// The CLI's render path end to end, read back: what `gbuffer` writes is the scene, and what
// `render` writes (uv' EXR, shaded PNG, error PNG, the printed error) is what the library computes
// for the same inputs, bit for bit.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support.hpp"

namespace omtest {
namespace {

namespace fs = std::filesystem;

std::string run_cli(const std::string& args) {
    const std::string cmd = std::string(OFFSETMAP_CLI) + " " + args + " 2>&1";
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) throw Error("cannot run " + cmd);
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
    const int rc = pclose(p);
    if (rc != 0) throw Error("'" + cmd + "' exited " + std::to_string(rc) + ":\n" + out);
    return out;
}

// An image's pixels as stored (8-bit or float), with its channel names.
template <typename T>
std::vector<T> read_image(const std::string& path, int* w, int* h,
                          std::vector<std::string>* names) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read " + path);
    const OIIO::ImageSpec& spec = in->spec();
    *w = spec.width, *h = spec.height;
    if (names) *names = spec.channelnames;
    std::vector<T> px(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
    const auto type = std::is_same_v<T, float> ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
    if (!in->read_image(0, 0, 0, spec.nchannels, type, px.data()))
        throw Error("cannot read " + path);
    return px;
}

TEST(Cli, RenderRoundTripMatchesTheLibraryBitForBit) {
    const fs::path dir = fs::temp_directory_path() / "om_cli_roundtrip";
    fs::create_directories(dir);
    const std::string g = (dir / "g.exr").string(), uv = (dir / "uv.exr").string(),
                      c = (dir / "c.png").string(), e = (dir / "e.png").string();
    const std::string map_path = std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png";
    run_cli("gbuffer --scene random --width 64 --height 32 --seed 5 -o " + g);
    const std::string out =
        run_cli("render --height-map " + map_path + " --scale 0.08 --method pom --gbuffer " + g +
                " --uv-out " + uv + " --color-out " + c + " --error-out " + e);

    // The G-buffer file holds the scene.
    GBuffer gb = load_gbuffer(g);
    GBuffer scene = make_scene(RandomScene{64, 32, 5, 5.0, 90.0});
    ASSERT_EQ(gb.pixels(), scene.pixels());
    EXPECT_EQ(std::memcmp(gb.uv.data(), scene.uv.data(), gb.uv.size() * sizeof(cl_float2)), 0);
    for (size_t k = 0; k < gb.pixels(); ++k)
        for (int a = 0; a < 3; ++a) ASSERT_EQ(gb.view[k].s[a], scene.view[k].s[a]) << k;

    // The library on the same inputs (the CLI's defaults: r = 1, wrap, clamp policy, no shadows).
    HeightMap map = load_height_map(map_path);
    PassSettings s;
    s.scale = 0.08f;
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, map, s);
    DeviceGBuffer dg = upload(*rt, gb);
    OffsetPass pass(rt, "pom");
    OffsetResult lib = run_offset(*rt, pass, dg, f, s, 1);

    int w = 0, h = 0;
    std::vector<std::string> names;
    std::vector<float> exr = read_image<float>(uv, &w, &h, &names);
    // Channels by name (EXR stores them sorted).
    auto channel = [&](const char* name) {
        auto it = std::find(names.begin(), names.end(), name);
        if (it == names.end()) throw Error(std::string("uv.exr has no channel ") + name);
        return static_cast<size_t>(it - names.begin());
    };
    const size_t nc = names.size(), cu = channel("u"), cv = channel("v"), cd = channel("depth"),
                 cf = channel("fetches"), cg = channel("flags");
    ASSERT_EQ(nc, 5u);
    ASSERT_EQ(static_cast<size_t>(w) * h, lib.uv.size());
    for (size_t k = 0; k < lib.uv.size(); ++k) {
        ASSERT_EQ(exr[nc * k + cu], lib.uv[k].s[0]) << k;
        ASSERT_EQ(exr[nc * k + cv], lib.uv[k].s[1]) << k;
        ASSERT_EQ(exr[nc * k + cd], lib.depth[k]) << k;
        ASSERT_EQ(exr[nc * k + cf], static_cast<float>(lib.fetches[k])) << k;
        ASSERT_EQ(exr[nc * k + cg], static_cast<float>(lib.flags[k])) << k;
    }

    ShadePass shade(rt);
    Rgb8 colour = to_srgb8(gb.width, gb.height,
                           run_shade(*rt, shade, lib, dg, f, nullptr, s, ShadeSettings{}));
    std::vector<uint8_t> png = read_image<uint8_t>(c, &w, &h, nullptr);
    ASSERT_EQ(w, gb.width);
    ASSERT_EQ(h, gb.height);
    EXPECT_EQ(png, colour.rgb);

    OffsetPass exact(rt, "exact");
    OffsetResult ref = run_offset(*rt, exact, dg, f, s, 1);
    std::vector<float> err;
    ErrorStats st = uv_error(lib, ref, map.width, map.height, &err);
    EXPECT_EQ(read_image<uint8_t>(e, &w, &h, nullptr),
              heat_map(gb.width, gb.height, err, 16.0f).rgb);
    // The printed mean, to its printed precision (4 decimals).
    const auto at = out.find("uv error vs exact (texels): mean ");
    ASSERT_NE(at, std::string::npos) << out;
    const double printed = std::stod(out.substr(at + 33));
    EXPECT_NEAR(printed, st.mean, 5e-5) << out;
    EXPECT_GT(st.mean, 0.0);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace omtest
