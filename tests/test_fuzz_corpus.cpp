// The fuzzers' corpus replayed through the same targets (tests/fuzz/targets.hpp) in the suite's
// build: every seed, and every input a fuzzer found (found-*), read to a clean end.
#include <filesystem>
#include <fstream>
#include <iterator>

#include "fuzz/targets.hpp"
#include "support.hpp"

namespace omtest {
namespace {

TEST(FuzzCorpus, EveryInputReadsToAResultOrAClearError) {
    namespace fs = std::filesystem;
    const fs::path root = fs::path(OFFSETMAP_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
    quiet_decoders(true);
    for (const auto& target : omfuzz::targets()) {
        size_t inputs = 0;
        for (const auto& entry : fs::directory_iterator(root / target.name)) {
            std::ifstream in(entry.path(), std::ios::binary);
            const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                                  std::istreambuf_iterator<char>());
            EXPECT_EQ(target.run(bytes.data(), bytes.size()), "") << entry.path();
            ++inputs;
        }
        EXPECT_GE(inputs, 2u) << target.name << ": its corpus has seeds";
    }
    quiet_decoders(false);
}

// The OpenEXR inputs the fuzzers found are refused by the header walk (exr_header.cpp), before
// OpenEXR allocates what they declare: the message says which check refused them.
TEST(FuzzCorpus, DamagedOpenExrHeadersStopBeforeOpenExrReadsThem) {
    namespace fs = std::filesystem;
    const fs::path root = fs::path(OFFSETMAP_SOURCE_DIR) / "tests" / "fuzz" / "corpus";
    size_t files = 0;
    for (const char* target : {"height_map", "gbuffer", "engine_gbuffer"})
        for (const auto& entry : fs::directory_iterator(root / target)) {
            const std::string name = entry.path().filename().string();
            if (name.rfind("found-exr-", 0) != 0) continue;
            ++files;
            const std::string why = error_of(
                [&] { load_engine_gbuffer(entry.path().string(), omfuzz::kReadLimitBytes); });
            EXPECT_TRUE(why.find("damaged OpenEXR header") != std::string::npos ||
                        why.find("above the limit") != std::string::npos)
                << name << ": " << why;
        }
    EXPECT_GE(files, 6u);
}

// A TIFF declaring more rows per strip than it holds: OpenImageIO's conversion buffer is a
// multiple of them, so the reader refuses it before decoding (found by the fuzzer: 2.4 GB for a
// 3 x 3 image).
TEST(FuzzCorpus, TiffRowsPerStripPastTheReadLimitAreRefused) {
    const std::string path =
        std::string(OFFSETMAP_SOURCE_DIR) +
        "/tests/fuzz/corpus/height_map/found-tiff-rows-per-strip-past-read-limit.tif";
    HeightLoadOptions options;
    options.max_bytes = omfuzz::kReadLimitBytes;
    const std::string why = error_of([&] { load_height_map(path, options); });
    EXPECT_NE(why.find("rows per strip"), std::string::npos) << why;
}

}  // namespace
}  // namespace omtest
