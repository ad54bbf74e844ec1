// Height maps, albedo and normal maps read from image files (OpenImageIO).
#include <OpenImageIO/imageio.h>

#include <cmath>

#include "offsetmap/error.hpp"
#include "offsetmap/image_io.hpp"

namespace offsetmap {
namespace {

struct Pixels {
    int width, height, channels;
    std::vector<float> data;
};

Pixels read_pixels(const std::string& path, const std::string& what) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        std::string why = OIIO::geterror();
        throw Error("cannot read " + what + " '" + path +
                    "': " + (why.empty() ? std::string("unknown image format") : why));
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw Error(what + " '" + path + "' is empty (" + std::to_string(spec.width) + "x" +
                    std::to_string(spec.height) + ")");
    if (static_cast<long long>(spec.width) * spec.height > (1ll << 28))
        throw Error(what + " '" + path + "' is too large (" + std::to_string(spec.width) + "x" +
                    std::to_string(spec.height) + ")");
    Pixels p{spec.width, spec.height, spec.nchannels, {}};
    p.data.resize(static_cast<size_t>(p.width) * p.height * p.channels);
    if (!in->read_image(0, 0, 0, p.channels, OIIO::TypeDesc::FLOAT, p.data.data())) {
        std::string why = in->geterror();
        throw Error("cannot decode " + what + " '" + path +
                    "': " + (why.empty() ? std::string("corrupt or truncated data") : why));
    }
    return p;
}

}  // namespace

HeightMap load_height_map(const std::string& path, const HeightLoadOptions& options) {
    Pixels p = read_pixels(path, "height map");
    if (options.channel < 0 || options.channel >= p.channels)
        throw Error("height map '" + path + "' has " + std::to_string(p.channels) +
                    " channel(s); channel " + std::to_string(options.channel) + " does not exist");
    HeightMap map;
    map.width = p.width;
    map.height = p.height;
    map.h.resize(static_cast<size_t>(p.width) * p.height);
    for (size_t k = 0; k < map.h.size(); ++k) {
        float v = p.data[k * p.channels + options.channel];
        if (!std::isfinite(v))
            throw Error("height map '" + path + "' holds a non-finite value at texel (" +
                        std::to_string(k % p.width) + ", " + std::to_string(k / p.width) + ")");
        if (v < 0.0f || v > 1.0f) {
            ++map.clamped;
            v = std::fmin(std::fmax(v, 0.0f), 1.0f);
        }
        map.h[k] = options.depth_map ? 1.0f - v : v;
    }
    return map;
}

Image4 load_image4(const std::string& path) {
    Pixels p = read_pixels(path, "image");
    Image4 img;
    img.width = p.width;
    img.height = p.height;
    img.texels.resize(static_cast<size_t>(p.width) * p.height);
    for (size_t k = 0; k < img.texels.size(); ++k) {
        float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int ch = 0; ch < std::min(p.channels, 4); ++ch) c[ch] = p.data[k * p.channels + ch];
        if (p.channels == 1) c[1] = c[2] = c[0];
        for (float& v : c)
            if (!std::isfinite(v)) v = 0.0f;
        img.texels[k] = {{c[0], c[1], c[2], c[3]}};
    }
    return img;
}

Image4 load_normal_map(const std::string& path, bool flip_green) {
    Image4 img = load_image4(path);
    for (auto& t : img.texels) {
        float x = 2.0f * t.s[0] - 1.0f, y = 2.0f * t.s[1] - 1.0f, z = 2.0f * t.s[2] - 1.0f;
        if (flip_green) y = -y;
        float len = std::sqrt(x * x + y * y + z * z);
        if (!(len > 1e-6f)) x = 0.0f, y = 0.0f, z = 1.0f, len = 1.0f;
        t = {{x / len, y / len, z / len, 0.0f}};
    }
    return img;
}

}  // namespace offsetmap
