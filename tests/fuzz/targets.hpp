// The readers as fuzz targets: each takes a file's bytes, writes them where a user's file would be
// and reads it as the CLI does. A target accepts two outcomes: the reader returns what it read,
// and that passes the checks a caller relies on (sizes agree, values finite and in range), or it
// throws offsetmap::Error (the clear one-line message). Anything else, another exception, a
// result that breaks those checks, is a finding: the target returns its description. A crash,
// a sanitizer report, a hang or an allocation above the read limit is one too, caught by the
// harness (libFuzzer, or the corpus test in the suite).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace omfuzz {

// The read limit every target passes to its reader (the readers check it from the header, before
// allocating a pixel); the fuzzers run with a malloc limit above it (tests/fuzz/CMakeLists.txt).
inline constexpr std::size_t kReadLimitBytes = std::size_t(64) << 20;

struct Target {
    const char* name;  // also its corpus folder, tests/fuzz/corpus/<name>
    // "" when the reader behaved, else the finding.
    std::string (*run)(const std::uint8_t* data, std::size_t size);
};

// Every target this build has (glTF only with the renderer).
const std::vector<Target>& targets();

}  // namespace omfuzz
