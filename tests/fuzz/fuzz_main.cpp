// One libFuzzer binary per target (OM_FUZZ_TARGET, a name from targets()): a finding is an abort,
// so libFuzzer keeps the input that caused it.
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "offsetmap/image_io.hpp"
#include "targets.hpp"

namespace {

const omfuzz::Target& target() {
    for (const auto& t : omfuzz::targets())
        if (std::strcmp(t.name, OM_FUZZ_TARGET) == 0) return t;
    std::fprintf(stderr, "no fuzz target %s\n", OM_FUZZ_TARGET);
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // libpng's own stderr lines, once per damaged file; a finding's report in a decoder's call
    // would go with them, so OFFSETMAP_FUZZ_LOUD=1 keeps stderr (to replay one).
    const char* loud = std::getenv("OFFSETMAP_FUZZ_LOUD");
    offsetmap::quiet_decoders(!(loud && *loud == '1'));
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const omfuzz::Target& t = target();
    const std::string finding = t.run(data, size);
    if (!finding.empty()) {
        std::fprintf(stderr, "offsetmap fuzz finding (%s): %s\n", t.name, finding.c_str());
        std::abort();
    }
    return 0;
}
