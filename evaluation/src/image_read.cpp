#include "image_read.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <new>
#include <sstream>

#include "exr_header.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/image_io.hpp"

// GCC says __SANITIZE_ADDRESS__; clang answers __has_feature.
#if defined(__SANITIZE_ADDRESS__)
#define OM_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define OM_ASAN 1
#endif
#endif
#if defined(OM_ASAN)
#include <sanitizer/lsan_interface.h>
#endif

namespace offsetmap {
namespace {

bool g_quiet_decoders = false;

// OpenImageIO 2.4's PNG reader leaks the error string it builds when libpng longjmps out of its
// read callback on a damaged file (31 bytes a file). In the sanitizer build, leak checking skips
// what OpenImageIO allocates inside these calls, and only that; a leak of ours still shows.
#if defined(OM_ASAN)
using ThirdPartyAllocations = __lsan::ScopedDisabler;
#else
struct ThirdPartyAllocations {};
#endif

// libpng writes "libpng error: ..." to the process's stderr before OpenImageIO reports the same
// text as an error; while quiet, the decoders' direct writes go to /dev/null for the call.
class QuietStderr {
  public:
    QuietStderr() {
        if (!g_quiet_decoders) return;
        lock_ = std::unique_lock<std::mutex>(mutex());
        std::fflush(stderr);
        saved_ = dup(2);
        int null = open("/dev/null", O_WRONLY);
        if (saved_ >= 0 && null >= 0) dup2(null, 2);
        if (null >= 0) close(null);
    }
    ~QuietStderr() {
        if (saved_ < 0) return;
        std::fflush(stderr);
        dup2(saved_, 2);
        close(saved_);
    }

  private:
    static std::mutex& mutex() {
        static std::mutex m;
        return m;
    }
    std::unique_lock<std::mutex> lock_;
    int saved_ = -1;
};

std::string mib(double bytes) {
    std::ostringstream s;
    s.precision(bytes >= 10.0 * 1048576.0 ? 0 : 1);
    s << std::fixed << bytes / 1048576.0 << " MiB";
    return s.str();
}

}  // namespace

void quiet_decoders(bool quiet) { g_quiet_decoders = quiet; }

std::string image_format(const std::string& path) {
    unsigned char m[12] = {};
    {
        std::ifstream in(path, std::ios::binary);
        in.read(reinterpret_cast<char*>(m), sizeof m);
    }
    auto is = [&](const char* magic, size_t at = 0) {
        return std::memcmp(m + at, magic, std::strlen(magic)) == 0;
    };
    if (is("\x89PNG")) return "png";
    if (is("\x76\x2f\x31\x01")) return "openexr";
    if (is("II*") || (is("MM") && m[2] == 0 && m[3] == 42)) return "tiff";
    if (is("\xff\xd8\xff")) return "jpeg";
    if (m[0] == 'P' && ((m[1] >= '1' && m[1] <= '6') || m[1] == 'F' || m[1] == 'f')) return "pnm";
    if (is("#?")) return "hdr";
    if (is("BM")) return "bmp";
    // Not GIF, WebP, DDS or PSD: their readers size a canvas from the header when the file is
    // opened (OpenImageIO's GIF reader throws past max_size()), before any limit can be checked.
    // No magic (Targa, for one): the reader its extension names, if any.
    std::string ext = std::filesystem::path(path).extension().string();
    if (ext.size() > 1) ext = ext.substr(1);
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext == "tga" || ext == "tpic" ? "targa" : "";
}

std::string describe_file(const std::string& what, const std::string& path) {
    return what + " '" + path + "'";
}

std::string one_line(const std::string& text) {
    // A damaged file can fail once per strip: the first three messages say what is wrong.
    constexpr int kShown = 3;
    std::istringstream in(text);
    std::string line, out, last;
    int lines = 0;
    while (std::getline(in, line)) {
        while (!line.empty() && (line.back() == ' ' || line.back() == '\r')) line.pop_back();
        if (line.empty() || line == last) continue;
        if (lines++ < kShown) out += (out.empty() ? "" : "; ") + line;
        last = line;
    }
    if (lines > kShown) out += "; and " + std::to_string(lines - kShown) + " more";
    return out;
}

std::unique_ptr<OIIO::ImageInput> open_image(const std::string& path, const std::string& what,
                                             size_t max_bytes) {
    OIIO::ImageSpec config;
    // The stored values: OpenImageIO would otherwise multiply colour (and a grey height) by alpha.
    config.attribute("oiio:UnassociatedAlpha", 1);
    check_exr_header(path, what, max_bytes);
    // One reader, named by the file's first bytes (else its extension): OpenImageIO's open tries
    // every reader it has when the first fails, and some (WebP's) allocate what a damaged header
    // declares before any check of ours can run.
    const std::string format = image_format(path);
    std::unique_ptr<OIIO::ImageInput> in;
    bool opened = false;
    try {
        QuietStderr quiet;
        [[maybe_unused]] ThirdPartyAllocations exempt;
        if (!format.empty()) in = OIIO::ImageInput::create(format, false, &config);
        if (in) {
            OIIO::ImageSpec spec;
            opened = in->open(path, spec, config);
        }
    } catch (const std::exception& e) {  // a decoder's std::length_error or std::bad_alloc
        throw Error("cannot read " + describe_file(what, path) + ": " + e.what());
    }
    if (!in || !opened) {
        std::string why = one_line(in ? in->geterror() : std::string());
        if (why.empty()) why = one_line(OIIO::geterror());
        throw Error("cannot read " + describe_file(what, path) + ": " +
                    (why.empty() ? std::string("unknown image format") : why));
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw Error(describe_file(what, path) + " is empty (" + std::to_string(spec.width) + "x" +
                    std::to_string(spec.height) + ", " + std::to_string(spec.nchannels) +
                    " channels)");
    return in;
}

void check_decode_size(const OIIO::ImageSpec& spec, const std::string& path,
                       const std::string& what, size_t kept_bytes_per_pixel, size_t max_bytes) {
    const double pixels = static_cast<double>(spec.width) * spec.height;
    // OpenImageIO reads scanline images in chunks of 256 rows, allocated whole even past the
    // image's last row.
    const double stored = std::max(
        static_cast<double>(spec.image_bytes(true)),
        spec.tile_width > 0 ? 0.0 : 256.0 * static_cast<double>(spec.scanline_bytes(true)));
    const double bytes = stored + pixels * static_cast<double>(kept_bytes_per_pixel);
    // OpenImageIO converts a scanline file through a buffer of about 64 MiB of rows, whatever the
    // image's size, rounded up to a multiple of the rows per strip a TIFF declares: a damaged one
    // declares hundreds of millions (found by the fuzzer). Its own 64 MiB are not counted against
    // the limit; what the declared strips add is.
    if (spec.tile_width <= 0) {
        const int rows_per_strip = spec.get_int_attribute("tiff:RowsPerStrip", 64);
        if (rows_per_strip <= 0)
            throw Error("cannot read " + describe_file(what, path) + ": it declares " +
                        std::to_string(rows_per_strip) + " rows per strip");
        const double line = static_cast<double>(spec.scanline_bytes(true));
        const double rows = std::max(std::max(1.0, std::floor(67108864.0 / line)), 256.0);
        const double chunk = std::ceil(rows / rows_per_strip) * rows_per_strip * line;
        if (chunk > 67108864.0 + static_cast<double>(max_bytes))
            throw Error(describe_file(what, path) + " declares " + std::to_string(rows_per_strip) +
                        " rows per strip: decoding it needs " + mib(chunk) +
                        ", above the limit of " + mib(67108864.0 + static_cast<double>(max_bytes)));
    }
    if (bytes > static_cast<double>(max_bytes))
        throw Error(describe_file(what, path) + " is " + std::to_string(spec.width) + "x" +
                    std::to_string(spec.height) + " with " + std::to_string(spec.nchannels) +
                    " channel(s) of " + std::to_string(spec.format.size()) +
                    " byte(s): reading it needs " + mib(bytes) + ", above the limit of " +
                    mib(static_cast<double>(max_bytes)));
}

std::vector<float> read_float_pixels(OIIO::ImageInput& in, const std::string& path,
                                     const std::string& what, int chbegin, int chend) {
    const OIIO::ImageSpec& spec = in.spec();
    if (spec.depth > 1)
        throw Error(describe_file(what, path) + " is a volume image (" +
                    std::to_string(spec.depth) + " slices); a map is one slice");
    const size_t row = static_cast<size_t>(spec.width) * (chend - chbegin);
    auto data = allocate<float>(row * spec.height, "the pixels of " + describe_file(what, path));
    bool ok = true;
    try {
        QuietStderr quiet;
        [[maybe_unused]] ThirdPartyAllocations exempt;
        // In bands of rows, stopping at the first that fails: OpenImageIO keeps every strip's
        // error message of one read and aborts the process past 16 MiB of them (found by the
        // fuzzer: a damaged TIFF of 393,219 rows, a strip each). A band holds whole tiles.
        const int tile = spec.tile_width > 0 ? std::max(spec.tile_height, 1) : 0;
        const int band = tile ? tile * std::max(1, 256 / tile) : 256;
        const int end = spec.y + spec.height;
        for (int y = spec.y; y < end && ok; y += band) {
            const int y1 = std::min(end, y + band);
            float* rows = data.data() + static_cast<size_t>(y - spec.y) * row;
            ok = tile ? in.read_tiles(0, 0, spec.x, spec.x + spec.width, y, y1, spec.z,
                                      spec.z + 1, chbegin, chend, OIIO::TypeDesc::FLOAT, rows)
                      : in.read_scanlines(0, 0, y, y1, spec.z, chbegin, chend,
                                          OIIO::TypeDesc::FLOAT, rows);
            // libjpeg fills a truncated file's missing rows with grey and reports success;
            // OpenImageIO records its "premature end" message as an error all the same.
            ok = ok && !in.has_error();
        }
    } catch (const std::exception& e) {
        throw Error("cannot decode " + describe_file(what, path) + ": " + e.what());
    }
    if (!ok) {
        std::string why = one_line(in.geterror());
        throw Error("cannot decode " + describe_file(what, path) + ": " +
                    (why.empty() ? std::string("corrupt or truncated data") : why));
    }
    return data;
}

template <typename T>
std::vector<T> allocate(size_t n, const std::string& what) {
    try {
        return std::vector<T>(n);
    } catch (const std::exception&) {  // std::bad_alloc, or std::length_error past max_size()
        throw Error("out of memory allocating " + mib(static_cast<double>(n) * sizeof(T)) +
                    " for " + what);
    }
}

template std::vector<float> allocate<float>(size_t, const std::string&);

}  // namespace offsetmap
