// The image readers against damaged files, files whose header lies, alpha, integer G-buffer
// channels and the size limit: an Error naming the file every time, never a crash.
#include <zlib.h>

#include <filesystem>

#include "support.hpp"

namespace omtest {
namespace {
namespace fs = std::filesystem;

using Bytes = std::string;

Bytes read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return Bytes(std::istreambuf_iterator<char>(in), {});
}

void write_bytes(const std::string& path, const Bytes& b) {
    std::ofstream(path, std::ios::binary).write(b.data(), static_cast<std::streamsize>(b.size()));
}

fs::path scratch() {
    auto dir = fs::temp_directory_path() / ("om_readers_" + std::to_string(getpid()));
    fs::create_directories(dir);
    return dir;
}

// A 64 x 48 image of `channels` channels (names given for EXR) in the format of the extension.
std::string write_valid(const fs::path& dir, const std::string& ext, int channels,
                        const std::vector<std::string>& names = {}) {
    const std::string path = (dir / ("valid." + ext)).string();
    const int w = 64, h = 48;
    OIIO::ImageSpec spec(w, h, channels,
                         ext == "exr" ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    if (!names.empty()) spec.channelnames = names;
    std::vector<float> px(static_cast<size_t>(w) * h * channels);
    for (size_t k = 0; k < px.size(); ++k) px[k] = 0.25f + 0.5f * ((k * 7919) % 97) / 97.0f;
    auto out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out && out->open(path, spec) &&
                out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close())
        << path;
    return path;
}

void put_be32(Bytes& b, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>(v >> (24 - 8 * i));
}
void put_le32(Bytes& b, size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) b[at + i] = static_cast<char>(v >> (8 * i));
}
void put_be16(Bytes& b, size_t at, uint16_t v) {
    b[at] = static_cast<char>(v >> 8);
    b[at + 1] = static_cast<char>(v);
}

// The file with its header claiming side x side pixels (the data stays what it was).
Bytes claim_size(const Bytes& file, const std::string& ext, uint32_t side) {
    Bytes b = file;
    if (ext == "png") {
        // IHDR: width and height at 16 and 20, its CRC (over type and data) at 29.
        put_be32(b, 16, side);
        put_be32(b, 20, side);
        put_be32(b, 29, crc32(0, reinterpret_cast<const Bytef*>(b.data() + 12), 17));
    } else if (ext == "jpg") {
        // The start-of-frame segment: FF C0 (baseline) or C2 (progressive), length, precision,
        // then height and width (16 bits each).
        for (size_t i = 2; i + 9 < b.size(); ++i)
            if (static_cast<unsigned char>(b[i]) == 0xFF &&
                (static_cast<unsigned char>(b[i + 1]) == 0xC0 ||
                 static_cast<unsigned char>(b[i + 1]) == 0xC2)) {
                put_be16(b, i + 5, static_cast<uint16_t>(std::min<uint32_t>(side, 65500)));
                put_be16(b, i + 7, static_cast<uint16_t>(std::min<uint32_t>(side, 65500)));
                break;
            }
    } else if (ext == "exr") {
        // Both windows: box2i = xMin yMin xMax yMax (little-endian int32) after "name\0box2i\0"
        // and the attribute's size.
        for (const char* name : {"dataWindow", "displayWindow"}) {
            size_t at = b.find(std::string(name) + '\0' + "box2i" + '\0');
            EXPECT_NE(at, Bytes::npos) << name;
            if (at == Bytes::npos) continue;
            at += std::string(name).size() + 1 + 6 + 4;
            put_le32(b, at + 8, side - 1);
            put_le32(b, at + 12, side - 1);
        }
    } else if (ext == "tif") {
        // Little-endian TIFF: the first IFD's entries ImageWidth (256) and ImageLength (257).
        EXPECT_EQ(b.substr(0, 2), "II");
        auto le = [&](size_t at, int n) {
            uint32_t v = 0;
            for (int i = n - 1; i >= 0; --i) v = v << 8 | static_cast<unsigned char>(b[at + i]);
            return v;
        };
        const size_t ifd = le(4, 4);
        const uint32_t entries = le(ifd, 2);
        for (uint32_t e = 0; e < entries; ++e) {
            const size_t at = ifd + 2 + 12 * e;
            const uint32_t tag = le(at, 2), type = le(at + 2, 2);
            if (tag != 256 && tag != 257) continue;
            if (type == 3)  // SHORT
                b[at + 8] = static_cast<char>(side & 0xFF),
                       b[at + 9] = static_cast<char>(side >> 8);
            else
                put_le32(b, at + 8, side);
        }
    }
    return b;
}

// The variants of one valid file a reader must survive.
std::vector<std::pair<std::string, Bytes>> damaged(const Bytes& file, const std::string& ext) {
    Bytes wrong_magic = file;
    for (int i = 0; i < 4; ++i) wrong_magic[i] = static_cast<char>(~wrong_magic[i]);
    return {
        {"zero-length", Bytes()},
        {"8 bytes", file.substr(0, 8)},
        {"first half", file.substr(0, file.size() / 2)},
        {"all but the last 16 bytes", file.substr(0, file.size() - 16)},
        {"wrong magic", wrong_magic},
        {"header claims 3000^2", claim_size(file, ext, 3000)},
        {"header claims 60000^2", claim_size(file, ext, 60000)},
    };
}

TEST(Readers, DamagedFilesAreErrorsNamingTheFileNeverCrashes) {
    quiet_decoders(true);  // as the CLI reads (one message per bad file)
    const fs::path dir = scratch();
    const std::vector<std::string> gbuffer_channels = {"u", "v", "Vx", "Vy", "Vz"};
    int variants = 0;
    for (const std::string ext : {"png", "jpg", "exr", "tif"}) {
        const std::string valid = ext == "exr" ? write_valid(dir, ext, 5, gbuffer_channels)
                                               : write_valid(dir, ext, ext == "jpg" ? 3 : 1);
        // The intact file reads (as a G-buffer too, for the EXR).
        EXPECT_EQ(error_of([&] { load_height_map(valid); }), "") << valid;
        if (ext == "exr") {
            EXPECT_EQ(error_of([&] { load_gbuffer(valid); }), "") << valid;
        }
        const Bytes file = read_bytes(valid);
        ASSERT_GT(file.size(), 64u) << valid;
        for (const auto& [name, bytes] : damaged(file, ext)) {
            const std::string path = (dir / ("damaged." + ext)).string();
            write_bytes(path, bytes);
            for (int reader = 0; reader < 2; ++reader) {
                const std::string what = error_of([&, p = path] {
                    if (reader == 0)
                        load_height_map(p);
                    else
                        load_gbuffer(p);
                });
                const char* kind = reader == 0 ? "height map" : "G-buffer";
                EXPECT_NE(what, "") << ext << ", " << name << ": read as a " << kind;
                if (what.empty()) continue;
                EXPECT_NE(what.find("'" + path + "'"), std::string::npos)
                    << ext << ", " << name << ": " << what;
                EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
                ++variants;
            }
        }
    }
    EXPECT_EQ(variants, 4 * 7 * 2);
    fs::remove_all(dir);
}

TEST(Readers, HeightsAreTheStoredGreyNotMultipliedByAlpha) {
    const fs::path dir = scratch();
    const std::string grey_alpha = (dir / "grey_alpha.png").string(),
                      grey = (dir / "grey.png").string();
    const int w = 16, h = 8;
    std::vector<uint8_t> ga(static_cast<size_t>(w) * h * 2), g(static_cast<size_t>(w) * h);
    for (size_t k = 0; k < g.size(); ++k) {
        g[k] = ga[2 * k] = static_cast<uint8_t>(40 + 13 * (k % 16));
        ga[2 * k + 1] = 51;  // alpha 0.2
    }
    OIIO::ImageSpec spec(w, h, 2, OIIO::TypeDesc::UINT8);
    spec.alpha_channel = 1;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // store the grey as given
    auto out = OIIO::ImageOutput::create(grey_alpha);
    ASSERT_TRUE(out->open(grey_alpha, spec) && out->write_image(OIIO::TypeDesc::UINT8, ga.data()) &&
                out->close());
    out = OIIO::ImageOutput::create(grey);
    ASSERT_TRUE(out->open(grey, OIIO::ImageSpec(w, h, 1, OIIO::TypeDesc::UINT8)) &&
                out->write_image(OIIO::TypeDesc::UINT8, g.data()) && out->close());
    HeightMap with_alpha = load_height_map(grey_alpha), plain = load_height_map(grey);
    ASSERT_EQ(with_alpha.h.size(), plain.h.size());
    for (size_t k = 0; k < g.size(); ++k) {
        EXPECT_NEAR(with_alpha.h[k], g[k] / 255.0f, 1e-7f) << k;
        EXPECT_EQ(with_alpha.h[k], plain.h[k]) << k;
    }
    // The alpha channel itself, when asked for.
    HeightMap alpha = load_height_map(grey_alpha, {1, false});
    EXPECT_NEAR(alpha.h[0], 51 / 255.0f, 1e-7f);
    fs::remove_all(dir);
}

TEST(Readers, GBufferChannelsMustBeHalfOrFloat) {
    const fs::path dir = scratch();
    const std::string path = (dir / "uint.exr").string();
    OIIO::ImageSpec spec(4, 4, 5, OIIO::TypeDesc::UINT32);
    spec.channelnames = {"u", "v", "Vx", "Vy", "Vz"};
    std::vector<uint32_t> px(4 * 4 * 5, 1);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT32, px.data()) &&
                out->close());
    EXPECT_NE(error_of([&] {
                  load_gbuffer(path);
              }).find("stores channel 'u' as uint; G-buffer channels must be half or float"),
              std::string::npos)
        << error_of([&] { load_gbuffer(path); });
    // Half channels are numbers and read as such.
    const std::string half = (dir / "half.exr").string();
    OIIO::ImageSpec hspec(4, 4, 5, OIIO::TypeDesc::HALF);
    hspec.channelnames = spec.channelnames;
    std::vector<float> hpx(4 * 4 * 5, 0.5f);
    out = OIIO::ImageOutput::create(half);
    ASSERT_TRUE(out->open(half, hspec) && out->write_image(OIIO::TypeDesc::FLOAT, hpx.data()) &&
                out->close());
    EXPECT_EQ(load_gbuffer(half).view[3].s[2], 0.5f);
    fs::remove_all(dir);
}

TEST(Readers, SizeLimitIsCheckedFromTheHeaderWithChannelsAndBytes) {
    const fs::path dir = scratch();
    // A PNG of a header and no pixels (IHDR, an empty IDAT, IEND) claiming 16384^2 RGBA at 16
    // bits: 2 GiB stored in a file of 57 bytes.
    auto chunk = [](const std::string& type, const Bytes& data) {
        Bytes c(4, '\0');
        put_be32(c, 0, static_cast<uint32_t>(data.size()));
        c += type + data + Bytes(4, '\0');
        put_be32(c, c.size() - 4,
                 crc32(0, reinterpret_cast<const Bytef*>(c.data() + 4), 4 + data.size()));
        return c;
    };
    Bytes ihdr(13, '\0');
    ihdr[8] = 16;  // bits per channel
    ihdr[9] = 6;   // RGBA
    Bytes png =
        Bytes("\x89PNG\r\n\x1a\n", 8) + chunk("IHDR", ihdr) + chunk("IDAT", "") + chunk("IEND", "");
    Bytes claimed = claim_size(png, "png", 16384);
    const std::string path = (dir / "claims.png").string();
    write_bytes(path, claimed);
    const std::string what = error_of([&] { load_height_map(path); });
    EXPECT_NE(what.find("'" + path + "' is 16384x16384 with 4 channel(s) of 2 byte(s)"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("above the limit of 2048 MiB"), std::string::npos) << what;
    // The same limit, lowered, refuses a real file by what decoding it takes.
    const std::string valid = write_valid(dir, "png", 4);
    // OpenImageIO decodes 256 rows at a time (past the last one: the fuzzers met a 555558 x 1
    // map that cost 284 MB), so what decoding takes is 256 stored rows, or the image when taller,
    // and then one float read and one kept per texel.
    HeightLoadOptions tight;
    tight.max_bytes = 256 * 64 * 4 + 64 * 48 * 8 - 1;
    EXPECT_NE(error_of([&] { load_height_map(valid, tight); }).find("above the limit"),
              std::string::npos);
    tight.max_bytes = 256 * 64 * 4 + 64 * 48 * 8;
    EXPECT_EQ(error_of([&] { load_height_map(valid, tight); }), "");
    // A G-buffer over the pixel limit, from the library and from a scene.
    EXPECT_NE(error_of([] {
                  GBuffer().resize(16384, 16384, false, false);
              }).find("above the G-buffer limit of 134217728 pixels"),
              std::string::npos);
    fs::remove_all(dir);
}

}  // namespace
}  // namespace omtest
