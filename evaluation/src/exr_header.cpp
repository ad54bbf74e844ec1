#include "exr_header.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <vector>

#include "image_read.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap {
namespace {

// The OpenEXR file layout (openexr.com, "OpenEXR File Layout"): magic, version word (flags:
// 0x200 tiled single part, 0x800 deep, 0x1000 multi-part), then headers, each a list of
// attributes (name, type name, int32 size, value) ended by an empty name; multi-part files end
// their headers with one more empty name.
constexpr std::uint32_t kMagic = 20000630;
constexpr std::uint32_t kTiled = 0x200, kLongNames = 0x400, kMultiPart = 0x1000;

// The bytes OpenEXR reads for a value of each type it knows (it reads that many, whatever the
// attribute declares); 0 for the types whose values it reads by the declared size; -1 for
// chlist and preview, checked apart.
int known_size(const std::string& type) {
    static const std::pair<const char*, int> sizes[] = {{"box2i", 16},
                                                        {"box2f", 16},
                                                        {"v2i", 8},
                                                        {"v2f", 8},
                                                        {"v2d", 16},
                                                        {"v3i", 12},
                                                        {"v3f", 12},
                                                        {"v3d", 24},
                                                        {"int", 4},
                                                        {"float", 4},
                                                        {"double", 8},
                                                        {"compression", 1},
                                                        {"lineOrder", 1},
                                                        {"envmap", 1},
                                                        {"deepImageState", 1},
                                                        {"m33f", 36},
                                                        {"m33d", 72},
                                                        {"m44f", 64},
                                                        {"m44d", 128},
                                                        {"chromaticities", 32},
                                                        {"keycode", 28},
                                                        {"timecode", 8},
                                                        {"rational", 8},
                                                        {"tiledesc", 9},
                                                        {"chlist", -1},
                                                        {"preview", -1}};
    for (const auto& [name, n] : sizes)
        if (type == name) return n;
    return 0;
}

struct Reader {
    const std::vector<char>& b;
    size_t p = 0;
    bool ok = true;
    size_t longest = 255;  // 31 unless the version word's long-names flag is set
    std::string name() {   // a null-terminated string of at most `longest` characters
        const size_t start = p;
        while (p < b.size() && b[p] != '\0' && p - start <= longest) ++p;
        if (p - start > longest) {
            ok = false;
            return "";
        }
        if (p >= b.size() || b[p] != '\0') {
            ok = false;
            return "";
        }
        return std::string(b.data() + start, b.data() + p++);
    }
    std::int32_t i32(size_t at) const {
        std::int32_t v;
        std::memcpy(&v, b.data() + at, 4);
        return v;
    }
};

// Lines a chunk holds for each compression (the "compression" attribute's value).
int lines_per_chunk(int compression) {
    switch (compression) {
        case 3:
            return 16;  // ZIP
        case 4:
        case 7:
        case 6:
        case 8:
            return 32;  // PIZ, B44, B44A, DWAA
        case 5:
            return 16;  // PXR24
        case 9:
            return 256;  // DWAB
        default:
            return 1;  // none, RLE, ZIPS
    }
}

}  // namespace

void check_exr_header(const std::string& path, const std::string& what, size_t max_bytes) {
    std::ifstream in(path, std::ios::binary | std::ios::ate);
    if (!in) return;  // open_image names the file it cannot read
    const std::streamoff size = in.tellg();
    if (size < 8) return;
    in.seekg(0);
    // The header lies at the file's start; its attributes are few and short: 1 MiB holds it,
    // and what lies past that is bounded by the file's size below.
    std::vector<char> b(static_cast<size_t>(std::min<std::streamoff>(size, 1 << 20)));
    in.read(b.data(), static_cast<std::streamsize>(b.size()));
    std::uint32_t magic, version;
    std::memcpy(&magic, b.data(), 4);
    std::memcpy(&version, b.data() + 4, 4);
    if (magic != kMagic) return;
    const std::string file = describe_file(what, path);
    auto damaged = [&](const std::string& why) {
        throw Error("cannot read " + file + ": damaged OpenEXR header: " + why);
    };
    // Each channel: name, int32 pixel type (0 uint, 1 half, 2 float), 4 bytes (pLinear,
    // reserved), int32 x and y sampling; OpenEXR sizes its buffers by the types and samplings.
    // The list must end, with its empty name, exactly where the attribute does. Returns the bytes
    // a pixel stores (each channel's size over its sampling; no channel is sampled below 1).
    auto check_channels = [&](size_t at, std::int32_t n, const std::string& attr,
                              auto&& fail) -> double {
        double bytes = 0.0;
        Reader c{b, at};
        const size_t end = at + static_cast<size_t>(n);
        if (n < 1 || b[end - 1] != '\0') fail("attribute '" + attr + "' does not end its list");
        while (c.p < end - 1) {
            const std::string channel = c.name();
            if (!c.ok || c.p + 16 > end) fail("attribute '" + attr + "' is cut off");
            const std::int32_t type = c.i32(c.p), xs = c.i32(c.p + 8), ys = c.i32(c.p + 12);
            if (type < 0 || type > 2 || xs < 1 || ys < 1 || xs > 65536 || ys > 65536)
                fail("channel '" + channel + "' has pixel type " + std::to_string(type) +
                     " and sampling " + std::to_string(xs) + "x" + std::to_string(ys));
            bytes += (type == 1 ? 2.0 : 4.0) / (double(xs) * ys);
            c.p += 16;
        }
        if (c.p != end - 1) fail("attribute '" + attr + "' does not end its list");
        return bytes;
    };
    Reader r{b, 8};
    r.longest = version & kLongNames ? 255 : 31;
    const bool multi = version & kMultiPart;
    for (int part = 0;; ++part) {
        if (multi && r.p < b.size() && b[r.p] == '\0') break;  // the empty header ends the list
        double chunks = -1.0;
        std::int32_t window[4] = {0, 0, -1, -1}, tile[2] = {0, 0};
        // A header without a (well-named) compression attribute keeps OpenEXR's default, ZIP:
        // 16-line chunks (the fuzzer found a misspelt name reaching a 560 MiB line buffer).
        int compression = 3;
        double pixel_bytes = 0.0;
        bool tiled = !multi && (version & kTiled);
        for (;;) {
            const std::string name = r.name();
            if (!r.ok) damaged("an attribute name runs past the header");
            if (name.empty()) break;
            const std::string type = r.name();
            if (!r.ok || r.p + 4 > b.size()) damaged("attribute '" + name + "' is cut off");
            const std::int32_t n = r.i32(r.p);
            r.p += 4;
            if (n < 0 || static_cast<std::streamoff>(r.p) + n > size)
                damaged("attribute '" + name + "' declares " + std::to_string(n) +
                        " bytes, more than the file holds after it");
            if (r.p + n > b.size()) damaged("attribute '" + name + "' runs past 1 MiB");
            const int expected = known_size(type);
            if (expected > 0 && n != expected)
                damaged("attribute '" + name + "' of type " + type + " declares " +
                        std::to_string(n) + " bytes, not " + std::to_string(expected));
            if (type == "chlist") pixel_bytes = check_channels(r.p, n, name, damaged);
            if (type == "preview" &&
                (n < 8 || double(std::uint32_t(r.i32(r.p))) * std::uint32_t(r.i32(r.p + 4)) * 4.0 !=
                              n - 8.0))
                damaged("attribute '" + name + "' (a preview) does not hold its pixels");
            if (name == "dataWindow" && type == "box2i" && n == 16)
                for (int k = 0; k < 4; ++k) window[k] = r.i32(r.p + 4 * k);
            if (name == "compression" && n == 1) compression = static_cast<unsigned char>(b[r.p]);
            if (name == "chunkCount" && n == 4) chunks = r.i32(r.p);
            if (name == "tiles" && n >= 8) tile[0] = r.i32(r.p), tile[1] = r.i32(r.p + 4);
            if (name == "type" && n > 0)
                tiled = std::string(b.data() + r.p, n).find("tiled") != std::string::npos;
            r.p += n;
        }
        const double w = double(window[2]) - window[0] + 1.0,
                     h = double(window[3]) - window[1] + 1.0;
        // OpenEXR's decompressors hold a whole chunk twice (its stored and decoded bytes): a
        // chunk is lines_per_chunk rows (even past the image's height) or a tile.
        const double chunk_pixels = tiled && tile[0] > 0 && tile[1] > 0
                                        ? double(tile[0]) * tile[1]
                                        : w * std::max<double>(lines_per_chunk(compression), 1.0);
        const double needs = std::max(w * h, 2.0 * chunk_pixels) * pixel_bytes;
        if (w >= 1.0 && h >= 1.0 && needs > static_cast<double>(max_bytes))
            throw Error(file + " is " + std::to_string(static_cast<long long>(w)) + "x" +
                        std::to_string(static_cast<long long>(h)) + ": reading it needs " +
                        std::to_string(static_cast<long long>(needs / 1048576.0)) +
                        " MiB, above the limit of " + std::to_string(max_bytes / 1048576) + " MiB");
        if (chunks < 0.0 && w >= 1.0 && h >= 1.0) {
            // Level 0's chunks: a lower bound of what the offset table holds.
            chunks = tiled && tile[0] > 0 && tile[1] > 0
                         ? std::ceil(w / tile[0]) * std::ceil(h / tile[1])
                         : std::ceil(h / lines_per_chunk(compression));
        }
        if (chunks > static_cast<double>(size) / 8.0)
            damaged("part " + std::to_string(part) + " declares " +
                    std::to_string(static_cast<long long>(chunks)) +
                    " chunks, more offsets than the file's " + std::to_string(size) +
                    " bytes hold");
        if (!multi) break;
        if (part > 1024) damaged("more than 1024 parts");
    }
}

}  // namespace offsetmap
