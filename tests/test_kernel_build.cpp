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
        if (m.precompute) rt->program(prep_program_files(*m.precompute));
    }
    ShadePass shade(rt);
    rt->program({"prep/mips.cl"});
    rt->program({"prep/unorm16.cl"});
    rt->program({"prep/footprint.cl"});
    rt->program(sampling_program_files("prep/normals.cl"));
    // The reconstruct pass's forms (its defines, as ReconstructPass::kernel writes them) and the
    // height import's.
    const std::vector<std::string> reconstruct = reconstruct_program_files();
    for (const char* lanes : {"", "#define OM_LANES 8\n", "#define OM_LANES 16\n"})
        for (const char* form :
             {"#define OM_STORAGE_DEPTH 0\n#define OM_STORAGE_FRAME 0\n#define OM_STORAGE_TANGENT "
              "0\n"
              "#define OM_STORAGE_UV 0\n#define OM_LIT\n#define OM_POINT_LIGHT\n",
              "#define OM_IMAGE_DEPTH 1\n#define OM_IMAGE_FRAME 1\n#define OM_IMAGE_UV 1\n"
              "#define OM_QUATERNION_FRAME\n#define OM_LIT\n",
              "#define OM_STORAGE_DEPTH 3\n#define OM_STORAGE_FRAME 2\n#define OM_STORAGE_TANGENT "
              "1\n"
              "#define OM_STORAGE_UV 1\n",
              "#define OM_STORAGE_DEPTH 4\n#define OM_STORAGE_FRAME 1\n#define OM_STORAGE_UV 2\n"
              "#define OM_QUATERNION_FRAME\n"})
            rt->program(reconstruct, std::string(lanes) + form);
    rt->program({"common/storage.cl", "prep/import.cl"});
    rt->program({"common/storage.cl", "prep/import.cl"}, "#define OM_IMAGE_HEIGHTS\n");
    // The material frame's classification, shading and tile entry (its entry is the same for
    // every method: one without and one with precomputed data).
    PassSettings s;
    std::vector<FrameMaterial> table(2);
    for (int k = 0; k < 2; ++k) {
        table[k].id = k + 1;
        table[k].field = upload(*rt, smooth_map(16), s);
        table[k].params = resolve_params(find_method(k ? "cone" : "pom"), {});
    }
    MaterialFrame frame(rt, table);
    std::string all;
    for (const auto& w : rt->build_warnings()) all += w + "\n";
    EXPECT_TRUE(rt->build_warnings().empty()) << all;
}

}  // namespace
}  // namespace omtest
