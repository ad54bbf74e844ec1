// Every program the passes build compiles without a warning. ctest also runs this with PoCL
// compiling for an AVX2 and an AVX-512 CPU (kernel.build_clean_*): programs are only built there,
// never run, so the AVX-512 build is checked on any machine.
#include "support.hpp"

namespace omtest {
namespace {

TEST(KernelBuild, EveryProgramBuildsWithoutWarnings) {
    // A runtime of its own, so that every program is built here, not taken from the shared one.
    auto shared = runtime();
    auto rt = std::make_shared<Runtime>(shared->context(), shared->device(), shared->queue());
    for (const auto& m : methods()) {
        OffsetPass pass(rt, m.name);  // compiles the method's program
        if (m.precompute) rt->program(sampling_program_files(m.precompute->prep_file));
    }
    ShadePass shade(rt);
    rt->program({"prep/mips.cl"});
    rt->program({"prep/footprint.cl"});
    rt->program(sampling_program_files("prep/normals.cl"));
    std::string all;
    for (const auto& w : rt->build_warnings()) all += w + "\n";
    EXPECT_TRUE(rt->build_warnings().empty()) << all;
}

}  // namespace
}  // namespace omtest
