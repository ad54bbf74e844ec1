// Height maps, albedo and normal maps read from image files (OpenImageIO).
#include <cmath>

#include "image_read.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/image_io.hpp"

namespace offsetmap {
namespace {

void check_texels(const OIIO::ImageSpec& spec, const std::string& path, const std::string& what) {
    if (static_cast<long long>(spec.width) * spec.height > kMaxHeightTexels)
        throw Error(describe_file(what, path) + " is too large (" + std::to_string(spec.width) +
                    "x" + std::to_string(spec.height) + "; at most " +
                    std::to_string(kMaxHeightTexels) + " texels)");
}

}  // namespace

HeightMap load_height_map(const std::string& path, const HeightLoadOptions& options) {
    const std::string what = "height map";
    auto in = open_image(path, what, options.max_bytes);
    const OIIO::ImageSpec& spec = in->spec();
    check_texels(spec, path, what);
    if (options.channel < 0 || options.channel >= spec.nchannels)
        throw Error(describe_file(what, path) + " has " + std::to_string(spec.nchannels) +
                    " channel(s); channel " + std::to_string(options.channel) + " does not exist");
    // One float read and one float kept per texel.
    check_decode_size(spec, path, what, 2 * sizeof(float), options.max_bytes);
    std::vector<float> data =
        read_float_pixels(*in, path, what, options.channel, options.channel + 1);
    HeightMap map;
    map.width = spec.width;
    map.height = spec.height;
    map.h = allocate<float>(data.size(), "the heights of " + describe_file(what, path));
    for (size_t k = 0; k < map.h.size(); ++k) {
        float v = data[k];
        if (!std::isfinite(v))
            throw Error(describe_file(what, path) + " holds a non-finite value at texel (" +
                        std::to_string(k % map.width) + ", " + std::to_string(k / map.width) + ")");
        if (v < 0.0f || v > 1.0f) {
            ++map.clamped;
            v = std::fmin(std::fmax(v, 0.0f), 1.0f);
        }
        map.h[k] = options.depth_map ? 1.0f - v : v;
    }
    return map;
}

Image4 load_image4(const std::string& path, size_t max_bytes) {
    const std::string what = "image";
    auto in = open_image(path, what, max_bytes);
    const OIIO::ImageSpec& spec = in->spec();
    check_texels(spec, path, what);
    check_decode_size(spec, path, what, spec.nchannels * sizeof(float) + sizeof(cl_float4),
                      max_bytes);
    const int nc = spec.nchannels;
    std::vector<float> data = read_float_pixels(*in, path, what, 0, nc);
    Image4 img;
    img.width = spec.width;
    img.height = spec.height;
    img.texels.resize(static_cast<size_t>(img.width) * img.height);
    for (size_t k = 0; k < img.texels.size(); ++k) {
        float c[4] = {0.0f, 0.0f, 0.0f, 1.0f};
        for (int ch = 0; ch < std::min(nc, 4); ++ch) c[ch] = data[k * nc + ch];
        if (nc == 1) c[1] = c[2] = c[0];
        for (float& v : c)
            if (!std::isfinite(v)) v = 0.0f;
        img.texels[k] = {{c[0], c[1], c[2], c[3]}};
    }
    return img;
}

Image4 load_normal_map(const std::string& path, bool flip_green, size_t max_bytes) {
    Image4 img = load_image4(path, max_bytes);
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
