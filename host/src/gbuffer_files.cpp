// G-buffer files: the OpenEXR contract (channels found by name) read and written.
#include <OpenImageIO/imageio.h>

#include <map>

#include "exr.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/image_io.hpp"

namespace offsetmap {

GBuffer load_gbuffer(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw Error("cannot read G-buffer '" + path + "': " + OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0) throw Error("G-buffer '" + path + "' is empty");
    std::map<std::string, int> index;
    for (int c = 0; c < spec.nchannels; ++c) index[spec.channelnames[c]] = c;
    std::string present;
    for (const auto& n : spec.channelnames) present += (present.empty() ? "" : " ") + n;
    std::string missing;
    for (const char* n : {"u", "v", "Vx", "Vy", "Vz"})
        if (!index.count(n)) missing += std::string(missing.empty() ? "" : " ") + n;
    if (!missing.empty())
        throw Error("G-buffer '" + path + "' lacks channel(s) " + missing +
                    " (needs u v Vx Vy Vz, optionally Lx Ly Lz lod; it has: " + present + ")");
    int nl = static_cast<int>(index.count("Lx") + index.count("Ly") + index.count("Lz"));
    if (nl != 0 && nl != 3)
        throw Error("G-buffer '" + path + "' has only some of Lx Ly Lz (it has: " + present + ")");
    std::vector<float> data(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data()))
        throw Error("cannot decode G-buffer '" + path + "': " + in->geterror());
    GBuffer gb;
    gb.resize(spec.width, spec.height, nl == 3, index.count("lod") != 0);
    const int nc = spec.nchannels;
    auto ch = [&](size_t k, const char* name) { return data[k * nc + index[name]]; };
    for (size_t k = 0; k < gb.pixels(); ++k) {
        gb.uv[k] = {{ch(k, "u"), ch(k, "v")}};
        gb.view[k] = {{ch(k, "Vx"), ch(k, "Vy"), ch(k, "Vz"), 0.0f}};
        if (gb.has_light()) gb.light[k] = {{ch(k, "Lx"), ch(k, "Ly"), ch(k, "Lz"), 0.0f}};
        if (gb.has_lod()) gb.lod[k] = ch(k, "lod");
    }
    return gb;
}

void save_gbuffer(const std::string& path, const GBuffer& gb) {
    std::vector<std::string> names = {"u", "v", "Vx", "Vy", "Vz"};
    if (gb.has_light()) names.insert(names.end(), {"Lx", "Ly", "Lz"});
    if (gb.has_lod()) names.push_back("lod");
    const int nc = static_cast<int>(names.size());
    std::vector<float> data(gb.pixels() * nc);
    for (size_t k = 0; k < gb.pixels(); ++k) {
        float* px = &data[k * nc];
        int c = 0;
        px[c++] = gb.uv[k].s[0];
        px[c++] = gb.uv[k].s[1];
        for (int a = 0; a < 3; ++a) px[c++] = gb.view[k].s[a];
        if (gb.has_light())
            for (int a = 0; a < 3; ++a) px[c++] = gb.light[k].s[a];
        if (gb.has_lod()) px[c++] = gb.lod[k];
    }
    write_float_exr(path, "G-buffer", gb.width, gb.height, names, data);
}

}  // namespace offsetmap
