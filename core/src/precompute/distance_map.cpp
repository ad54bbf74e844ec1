// sphere's distance map (kernels/prep/distance.cl): per voxel of a res x res x layers grid over
// the tile and the slab, the distance from the voxel's box to a column proxy of the relief.
#include <cstddef>

#include "launch.hpp"
#include "offsetmap/passes.hpp"
#include "offsetmap/runtime.hpp"
#include "precompute/precompute.hpp"

namespace offsetmap {
namespace {

size_t voxels(const MethodParams& p) {
    const size_t res = static_cast<size_t>(p["res"]);
    return res * res * static_cast<size_t>(p["layers"]);
}

size_t bytes(const MethodParams& p, const PassSettings&, int, int) {
    return voxels(p) * sizeof(float);
}

PrecomputeSpec::Built build(Runtime& rt, const DeviceHeightField& f, const PassSettings& settings,
                            const MethodParams& params) {
    const int res = static_cast<int>(params["res"]), layers = static_cast<int>(params["layers"]);
    OmOffsetParams p = offset_params(settings, f.width, f.height);
    cl::Program program = rt.program(prep_program_files(kDistanceMap));
    // The column maxima are a step of the build, freed with it.
    cl::Buffer colmax(rt.context(), CL_MEM_READ_WRITE,
                      static_cast<size_t>(res) * res * sizeof(float));
    PrecomputeSpec::Built out;
    out.data = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, voxels(params) * sizeof(float));
    cl::Kernel kc = rt.kernel(program, "om_column_max");
    set_args(kc, p, f.heights, res, colmax);
    cl::Kernel kd = rt.kernel(program, "om_distance_map");
    set_args(kd, p, colmax, res, layers, out.data);
    cl::Event e1;
    std::vector<cl::Event> after_field = field_ready(f);
    enqueue_grid(rt.queue(), kc, cl::NDRange(res, res), &after_field, &e1);
    out.events = enqueue_with_progress(
        rt, kd, cl::NDRange(res, res, layers),
        "sphere: distance map " + std::to_string(res) + "^2 x " + std::to_string(layers), {e1});
    out.events.push_back(e1);
    return out;
}

}  // namespace

const PrecomputeSpec kDistanceMap = {
    "distance map: res x res x layers floats (4 res^2 layers bytes), built by a kernel per height "
    "map, scale and address mode",
    "prep/distance.cl", nullptr, bytes, build};

}  // namespace offsetmap
