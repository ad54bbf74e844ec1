#pragma once
#include <string>
#include <vector>

namespace offsetmap {

// One build of a kernel program as the passes ask a driver for it: its files (under kernels/) and
// its defines.
struct ProgramVariant {
    std::string name;  // e.g. "offset/pom/lanes16-images-lod-outputs"
    std::vector<std::string> files;
    std::string defines;
    // One of the portability checks' sample (tests/portability, `./run test`): the variant a GPU
    // driver gets by default (one lane, buffers, no LOD, no optional output), one for each kernel
    // file; the sweep (`./run test --full`) takes every variant.
    bool sample = false;
};

// Every program the library, the material frame and the bench build, in every variant a device
// can be handed: each method's offset entry at 1, 8 and 16 lanes, heights from buffers and
// images, with and without LOD, with no optional output and with all three; each method's tile
// entry; the shading, reconstruction, precompute, import and bench kernels, the reconstruction
// over each input storage and form. For the portability checks (tests/portability): a driver
// that builds all of these runs every pass.
std::vector<ProgramVariant> program_variants();

}  // namespace offsetmap
