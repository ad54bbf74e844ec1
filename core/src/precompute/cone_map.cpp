// cone's cone map (kernels/prep/cone.cl): per cell its maximum height and the widest cone above it
// that holds no relief, searched over rings of OM_CONE_BLOCK^2 blocks whose maxima prune it.
#include "methods/cone_map.h"

#include <algorithm>
#include <cstddef>

#include "launch.hpp"
#include "offsetmap/passes.hpp"
#include "offsetmap/runtime.hpp"
#include "precompute/precompute.hpp"

namespace offsetmap {
namespace {

size_t cone_bytes(int w, int h) {
    return static_cast<size_t>(om_cone_words(w, h)) * sizeof(cl_uint);
}

// With `beam` on, maxmip's pyramid follows the cone map (methods/cone_map.h, om_cone_pyramid).
size_t bytes(const MethodParams& params, const PassSettings& settings, int w, int h) {
    const size_t pyramid = params["beam"] != 0 ? kMaxPyramid.bytes(params, settings, w, h) : 0;
    return cone_bytes(w, h) + pyramid;
}

// The pyramid built as maxmip's, copied in after the cone map's words.
void append_pyramid(Runtime& rt, const DeviceHeightField& f, const PassSettings& settings,
                    const MethodParams& params, PrecomputeSpec::Built& out) {
    const size_t size = kMaxPyramid.bytes(params, settings, f.width, f.height);
    if (size == 0) return;
    PrecomputeSpec::Built pyramid = kMaxPyramid.build(rt, f, settings, params);
    out.events.insert(out.events.end(), pyramid.events.begin(), pyramid.events.end());
    cl::Event copied;
    rt.queue().enqueueCopyBuffer(pyramid.data, out.data, 0, cone_bytes(f.width, f.height), size,
                                 &pyramid.events, &copied);
    out.events.push_back(copied);
}

PrecomputeSpec::Built build(Runtime& rt, const DeviceHeightField& f, const PassSettings& settings,
                            const MethodParams& params) {
    const int B = OM_CONE_BLOCK;
    const int bw = (f.width + B - 1) / B, bh = (f.height + B - 1) / B;
    cl::Program program = rt.program(prep_program_files(kConeMap));
    OmOffsetParams p = offset_params(settings, f.width, f.height);
    cl::Buffer blocks(rt.context(), CL_MEM_READ_WRITE,
                      static_cast<size_t>(bw) * bh * sizeof(float));
    PrecomputeSpec::Built out;
    out.data =
        cl::Buffer(rt.context(), CL_MEM_READ_WRITE, bytes(params, settings, f.width, f.height));
    cl::Kernel kb = rt.kernel(program, "om_cone_blocks");
    set_args(kb, p, f.heights, bw, bh, blocks);
    cl::Event e1;
    std::vector<cl::Event> after_field = field_ready(f);
    enqueue_grid(rt.queue(), kb, cl::NDRange(bw, bh), &after_field, &e1);
    // The one host round trip of a build: the global maximum bounds every cone's search.
    std::vector<float> block_max(static_cast<size_t>(bw) * bh);
    std::vector<cl::Event> after_blocks = {e1};
    rt.queue().enqueueReadBuffer(blocks, CL_TRUE, 0, block_max.size() * sizeof(float),
                                 block_max.data(), &after_blocks);
    const float global_max = *std::max_element(block_max.begin(), block_max.end());
    // Wrapped block indices name the same cells only when blocks tile the map.
    const int blocks_valid =
        settings.address == AddressMode::Clamp || (f.width % B == 0 && f.height % B == 0);
    cl::Kernel kc = rt.kernel(program, "om_cone_map");
    set_args(kc, p, f.heights, blocks, bw, bh, blocks_valid, global_max, params["max_ratio"],
             out.data);
    out.events = enqueue_with_progress(
        rt, kc, cl::NDRange(f.width, f.height),
        "cone: cone map " + std::to_string(f.width) + "x" + std::to_string(f.height));
    out.events.push_back(e1);
    if (params["beam"] != 0) append_pyramid(rt, f, settings, params, out);
    return out;
}

}  // namespace

const PrecomputeSpec kConeMap = {
    "cone map: a 32-bit word per cell (cell maximum rounded up, cone ratio rounded down; 16 bits "
    "each) in 32 x 32 tiles, about 4 W H bytes, built by a kernel per height map with 8 x 8 block "
    "maxima to prune the search",
    "prep/cone.cl", "methods/cone_map.h", bytes, build};

}  // namespace offsetmap
