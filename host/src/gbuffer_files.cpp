// G-buffer files: the OpenEXR contract (channels found by name) read and written.
#include <map>

#include "exr.hpp"
#include "image_read.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/image_io.hpp"

namespace offsetmap {

GBuffer load_gbuffer(const std::string& path, size_t max_bytes) {
    const std::string what = "G-buffer";
    auto in = open_image(path, what);
    const OIIO::ImageSpec& spec = in->spec();
    const std::string file = describe_file(what, path);
    std::map<std::string, int> index;
    for (int c = 0; c < spec.nchannels; ++c) index[spec.channelnames[c]] = c;
    std::string present;
    for (const auto& n : spec.channelnames) present += (present.empty() ? "" : " ") + n;
    std::string missing;
    for (const char* n : {"u", "v", "Vx", "Vy", "Vz"})
        if (!index.count(n)) missing += std::string(missing.empty() ? "" : " ") + n;
    if (!missing.empty())
        throw Error(file + " lacks channel(s) " + missing +
                    " (needs u v Vx Vy Vz, optionally Lx Ly Lz lod; it has: " + present + ")");
    int nl = static_cast<int>(index.count("Lx") + index.count("Ly") + index.count("Lz"));
    if (nl != 0 && nl != 3)
        throw Error(file + " has only some of Lx Ly Lz (it has: " + present + ")");
    // Integer channels would be scaled to [0,1] on read: vectors and uv must be stored as numbers.
    for (const char* n : {"u", "v", "Vx", "Vy", "Vz", "Lx", "Ly", "Lz", "lod"}) {
        if (!index.count(n)) continue;
        const OIIO::TypeDesc t = spec.channelformat(index[n]);
        if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT)
            throw Error(file + " stores channel '" + n + "' as " + t.c_str() +
                        "; G-buffer channels must be half or float");
    }
    check_gbuffer_size(spec.width, spec.height, file);
    // What is read (every channel as float) and what is kept (uv, view, light, lod).
    check_decode_size(
        spec, path, what,
        spec.nchannels * sizeof(float) + sizeof(cl_float2) + 2 * sizeof(cl_float4) + sizeof(float),
        max_bytes);
    std::vector<float> data = read_float_pixels(*in, path, what, 0, spec.nchannels);
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
