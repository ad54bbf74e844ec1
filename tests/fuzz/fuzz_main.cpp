// One libFuzzer binary per target (OM_FUZZ_TARGET, a name from targets()): a finding is an abort,
// so libFuzzer keeps the input that caused it.
#include <sanitizer/common_interface_defs.h>
#include <unistd.h>

#include <cstdint>
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

// The process's stderr as it was at start: a quiet decoder points fd 2 at /dev/null for its call,
// and a crash inside that call must still be reported.
FILE* report_stream() {
    static FILE* const f = [] {
        const int fd = dup(2);
        FILE* s = fd >= 0 ? fdopen(fd, "w") : nullptr;
        return s ? s : stderr;
    }();
    return f;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // Sanitizer reports go to the saved stream; libFuzzer's own (a signal, an exit() in a
    // decoder) keep theirs through -close_fd_mask=2, which tests/fuzz/run.sh passes.
    __sanitizer_set_report_fd(
        reinterpret_cast<void*>(static_cast<std::intptr_t>(fileno(report_stream()))));
    // libpng's own stderr lines, once per damaged file, go where the CLI sends them;
    // OFFSETMAP_FUZZ_LOUD=1 keeps them (to read what a decoder said about an input).
    const char* loud = std::getenv("OFFSETMAP_FUZZ_LOUD");
    offsetmap::quiet_decoders(!(loud && *loud == '1'));
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const omfuzz::Target& t = target();
    const std::string finding = t.run(data, size);
    if (!finding.empty()) {
        std::fprintf(report_stream(), "offsetmap fuzz finding (%s): %s\n", t.name, finding.c_str());
        std::fflush(report_stream());
        std::abort();
    }
    return 0;
}
