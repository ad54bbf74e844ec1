// Writes each method's program for the C++ peer, from its registry row: the parameter slot
// defines and the kernel files in program order, exactly what the runtime assembles for the
// OpenCL build (param_slot_defines, prelude_files, offset_program_files), and the shade pass's
// program (shade_program_files). A file is rewritten only
// when its text changes, so the peer recompiles only what a row or a file list changed.
//   offsetmap_peer_gen OUT_DIR STAMP
#include <fstream>
#include <iostream>
#include <sstream>
#include <vector>

#include "offsetmap/registry.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::cerr << "usage: offsetmap_peer_gen OUT_DIR STAMP\n";
        return 2;
    }
    const std::string dir = argv[1];
    auto write = [&dir](const std::string& stem, std::string text,
                        const std::vector<std::string>& program) {
        std::vector<std::string> files = offsetmap::prelude_files();
        files.insert(files.end(), program.begin(), program.end());
        for (const auto& f : files) text += "#include \"" + f + "\"\n";
        const std::string path = dir + "/peer_" + stem + "_program.inc";
        std::ifstream old(path);
        std::ostringstream current;
        current << old.rdbuf();
        if (!old || current.str() != text) std::ofstream(path) << text;
    };
    for (const auto& m : offsetmap::methods())
        write(m.kernel_file.substr(0, m.kernel_file.rfind('.')),
              "// Generated from the registry row of '" + m.name +
                  "' by offsetmap_peer_gen. Do not edit.\n" + offsetmap::param_slot_defines(m),
              offsetmap::offset_program_files(m));
    write("shade", "// The shade program's files, by offsetmap_peer_gen. Do not edit.\n",
          offsetmap::shade_program_files());
    std::ofstream(argv[2]) << "done\n";
    return 0;
}
