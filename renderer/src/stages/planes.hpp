// The transfer stage: the G-buffer's planes from GL's targets into OpenCL buffers in host memory
// the host maps (CL_MEM_ALLOC_HOST_PTR), so GL's read is the one copy, and the engine G-buffer
// (core's EngineGBuffer) over them, as an engine hands its own to the reconstruct pass.
#pragma once
#include <vector>

#include "../raster.hpp"
#include "offsetmap/cl.hpp"
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/offset_pass.hpp"
#include "offsetmap/runtime.hpp"

namespace offsetmap::renderer {

struct GBufferPlanes {
    // Floats a pixel: depth 1, normal 4, tangent 4, uv 2, material id 1, uv density 1 and the
    // curvature 4 (k_uu, k_uv, k_vv, stretch), rows bottom first (GL's).
    cl::Buffer depth, normal, tangent, uv, ids, density, curvature;
    // The uv metric: 12 floats a pixel, the offset pass's three planes of `pixels` each.
    cl::Buffer uv_metric;

    GBufferPlanes() = default;
    // For `pixels` pixels. With `taken` the planes a layer behind writes in place (depth, ids,
    // density, curvature) are readable and writable by the device; the rest are read-only.
    GBufferPlanes(Runtime& runtime, size_t pixels, bool taken);

    // The raster's last draw into the buffers (`regions`: only theirs), the curvature only with
    // `curvature`. Blocks until the buffers hold them.
    void move_from(const cl::CommandQueue& queue, const Raster& raster, size_t pixels,
                   bool curvature, const std::vector<PixelRegion>* regions = nullptr) const;

    // The uv metric of the raster's last draw, drawn again for it (Raster::draw_metric) and
    // read into uv_metric mapped (`regions`: only theirs). Blocks.
    void move_metric_from(const cl::CommandQueue& queue, Raster& raster, const View& view,
                          size_t pixels, const std::vector<PixelRegion>* regions = nullptr) const;

    // The engine G-buffer over these planes (buffers of floats; the normal-tangent form).
    EngineGBuffer engine(int width, int height, const EngineCamera& camera,
                         const EngineLight& light) const;
};

// The view as the device passes take GL's planes: GL's depth convention, rows bottom first.
EngineCamera pass_camera_of(const View& view);

// An offset pass's four targets for `pixels` pixels.
OffsetTargets allocate_targets(Runtime& runtime, size_t pixels);

}  // namespace offsetmap::renderer
