#include "offsetmap/image_io.hpp"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "offsetmap/error.hpp"

namespace offsetmap {
namespace {

std::uint8_t srgb8(float linear) {
    float c = std::clamp(std::isfinite(linear) ? linear : 0.0f, 0.0f, 1.0f);
    float s = c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
    return static_cast<std::uint8_t>(std::lround(s * 255.0f));
}

}  // namespace

Rgb8 to_srgb8(int width, int height, const std::vector<cl_float4>& linear) {
    Rgb8 img{width, height, std::vector<std::uint8_t>(static_cast<size_t>(width) * height * 3)};
    for (size_t k = 0; k < linear.size() && k * 3 < img.rgb.size(); ++k)
        for (int c = 0; c < 3; ++c) img.rgb[k * 3 + c] = srgb8(linear[k].s[c]);
    return img;
}

Rgb8 heat_map(int width, int height, const std::vector<float>& values, float vmax) {
    static const std::array<std::array<float, 3>, 5> stops = {{{0.00f, 0.00f, 0.02f},
                                                               {0.32f, 0.06f, 0.45f},
                                                               {0.74f, 0.22f, 0.33f},
                                                               {0.98f, 0.56f, 0.04f},
                                                               {0.99f, 0.99f, 0.75f}}};
    Rgb8 img{width, height, std::vector<std::uint8_t>(static_cast<size_t>(width) * height * 3)};
    const float denom = std::log1p(std::max(vmax, 1e-6f));
    for (size_t k = 0; k < values.size() && k * 3 < img.rgb.size(); ++k) {
        float v = values[k];
        std::array<float, 3> c = {0.22f, 0.22f, 0.24f};
        if (std::isfinite(v)) {
            float x = std::clamp(std::log1p(std::max(v, 0.0f)) / denom, 0.0f, 1.0f) * 4.0f;
            int i = std::min(static_cast<int>(x), 3);
            float f = x - i;
            for (int ch = 0; ch < 3; ++ch)
                c[ch] = stops[i][ch] + f * (stops[i + 1][ch] - stops[i][ch]);
        }
        for (int ch = 0; ch < 3; ++ch)
            img.rgb[k * 3 + ch] = static_cast<std::uint8_t>(std::lround(c[ch] * 255.0f));
    }
    return img;
}

Rgb8 contact_sheet(const std::vector<std::pair<std::string, Rgb8>>& tiles, int columns) {
    if (tiles.empty()) return {};
    const int label_h = 28, pad = 6;
    int tw = 0, th = 0;
    for (const auto& t : tiles)
        tw = std::max(tw, t.second.width), th = std::max(th, t.second.height);
    // Small frames are enlarged (whole pixels, no filtering) so that a label fits above its tile.
    const int min_tile_w = 560, zoom = tw > 0 && tw < min_tile_w ? (min_tile_w + tw - 1) / tw : 1;
    tw *= zoom;
    th *= zoom;
    const int cols = std::max(1, std::min(columns, static_cast<int>(tiles.size())));
    const int rows = (static_cast<int>(tiles.size()) + cols - 1) / cols;
    const int cw = tw + pad, ch = th + label_h + pad;
    OIIO::ImageBuf sheet(
        OIIO::ImageSpec(cols * cw + pad, rows * ch + pad, 3, OIIO::TypeDesc::FLOAT));
    const float bg[3] = {0.08f, 0.08f, 0.09f};
    OIIO::ImageBufAlgo::fill(sheet, bg);
    for (size_t n = 0; n < tiles.size(); ++n) {
        const Rgb8& img = tiles[n].second;
        int x0 = pad + static_cast<int>(n % cols) * cw, y0 = pad + static_cast<int>(n / cols) * ch;
        OIIO::ImageBuf tile(OIIO::ImageSpec(img.width, img.height, 3, OIIO::TypeDesc::UINT8),
                            const_cast<std::uint8_t*>(img.rgb.data()));
        if (zoom > 1) {
            OIIO::ImageBuf big(
                OIIO::ImageSpec(img.width * zoom, img.height * zoom, 3, OIIO::TypeDesc::UINT8));
            OIIO::ImageBufAlgo::resample(big, tile, false);
            tile.swap(big);
        }
        OIIO::ImageBufAlgo::paste(sheet, x0, y0 + label_h, 0, 0, tile);
        const float white[3] = {0.92f, 0.92f, 0.92f};
        // A long label is set smaller until it fits its tile, rather than run into the next one.
        // A missing font only loses the label, never the sheet.
        auto fits = [&](int size) {
            const OIIO::ROI r = OIIO::ImageBufAlgo::text_size(tiles[n].first, size, "DejaVuSans");
            return !r.defined() || r.width() <= tw - 8;
        };
        int size = 20;
        while (size > 10 && !fits(size)) --size;
        OIIO::ImageBufAlgo::render_text(sheet, x0 + 4, y0 + label_h - 8, tiles[n].first, size,
                                        "DejaVuSans", white);
        (void)OIIO::geterror();
    }
    Rgb8 out{sheet.spec().width, sheet.spec().height, {}};
    out.rgb.resize(static_cast<size_t>(out.width) * out.height * 3);
    std::vector<float> px(out.rgb.size());
    sheet.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, px.data());
    for (size_t k = 0; k < px.size(); ++k)
        out.rgb[k] = static_cast<std::uint8_t>(std::lround(std::clamp(px[k], 0.0f, 1.0f) * 255.0f));
    return out;
}

void write_image(const std::string& path, const Rgb8& image) {
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(image.width, image.height, 3, OIIO::TypeDesc::UINT8);
    if (!out || !out->open(path, spec) ||
        !out->write_image(OIIO::TypeDesc::UINT8, image.rgb.data()) || !out->close())
        throw Error("cannot write image '" + path +
                    "': " + (out ? out->geterror() : OIIO::geterror()));
}

void write_uv_exr(const std::string& path, const OffsetResult& r) {
    const size_t n = r.uv.size();
    std::vector<float> data(n * 5);
    for (size_t k = 0; k < n; ++k) {
        data[k * 5 + 0] = r.uv[k].s[0];
        data[k * 5 + 1] = r.uv[k].s[1];
        data[k * 5 + 2] = r.depth.empty() ? 0.0f : r.depth[k];
        data[k * 5 + 3] = r.fetches.empty() ? 0.0f : static_cast<float>(r.fetches[k]);
        data[k * 5 + 4] = r.flags.empty() ? 0.0f : static_cast<float>(r.flags[k]);
    }
    write_float_exr(path, "uv output", r.width, r.height, {"u", "v", "depth", "fetches", "flags"},
                    data);
}

void write_float_exr(const std::string& path, const std::string& what, int width, int height,
                     const std::vector<std::string>& channels, const std::vector<float>& data,
                     const std::map<std::string, std::string>& attributes) {
    OIIO::ImageSpec spec(width, height, static_cast<int>(channels.size()), OIIO::TypeDesc::FLOAT);
    spec.channelnames = channels;
    spec.attribute("compression", "zip");
    for (const auto& [name, value] : attributes) spec.attribute(name, value);
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, data.data()) ||
        !out->close())
        throw Error("cannot write " + what + " '" + path +
                    "': " + (out ? out->geterror() : OIIO::geterror()));
}

}  // namespace offsetmap
