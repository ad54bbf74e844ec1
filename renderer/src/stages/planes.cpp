#include "planes.hpp"

namespace offsetmap::renderer {

GBufferPlanes::GBufferPlanes(Runtime& rt, size_t n, bool taken) {
    auto buffer = [&](size_t floats, cl_mem_flags flags) {
        return cl::Buffer(rt.context(), flags | CL_MEM_ALLOC_HOST_PTR, floats * sizeof(float));
    };
    const cl_mem_flags in = CL_MEM_READ_ONLY, written = taken ? CL_MEM_READ_WRITE : in;
    depth = buffer(n, written);
    normal = buffer(4 * n, in);
    tangent = buffer(4 * n, in);
    uv = buffer(2 * n, in);
    ids = buffer(n, written);
    density = buffer(n, written);
    curvature = buffer(4 * n, written);
    uv_metric = buffer(12 * n, written);
}

void GBufferPlanes::move_metric_from(const cl::CommandQueue& q, Raster& raster, const View& view,
                                     size_t n, const std::vector<PixelRegion>* regions) const {
    raster.draw_metric(view);
    const cl_map_flags how = regions ? CL_MAP_WRITE : CL_MAP_WRITE_INVALIDATE_REGION;
    float* p =
        static_cast<float*>(q.enqueueMapBuffer(uv_metric, CL_TRUE, how, 0, 12 * n * sizeof(float)));
    raster.read_metric_into(p, regions);
    q.enqueueUnmapMemObject(uv_metric, p);
    q.finish();
}

void GBufferPlanes::move_from(const cl::CommandQueue& q, const Raster& raster, size_t n,
                              bool with_curvature, const std::vector<PixelRegion>* regions) const {
    // With regions the rest keeps its values (a plain write map); else all is overwritten.
    const cl_map_flags how = regions ? CL_MAP_WRITE : CL_MAP_WRITE_INVALIDATE_REGION;
    auto map = [&](const cl::Buffer& b, size_t floats) {
        return static_cast<float*>(q.enqueueMapBuffer(b, CL_TRUE, how, 0, floats * sizeof(float)));
    };
    PlanePointers p;
    p.depth = map(depth, n);
    p.normal = map(normal, 4 * n);
    p.tangent = map(tangent, 4 * n);
    p.uv = map(uv, 2 * n);
    p.material = map(ids, n);
    p.density = map(density, n);
    if (with_curvature) p.curvature = map(curvature, 4 * n);
    raster.read_into(p, regions);
    if (p.curvature) q.enqueueUnmapMemObject(curvature, p.curvature);
    q.enqueueUnmapMemObject(depth, p.depth);
    q.enqueueUnmapMemObject(normal, p.normal);
    q.enqueueUnmapMemObject(tangent, p.tangent);
    q.enqueueUnmapMemObject(uv, p.uv);
    q.enqueueUnmapMemObject(ids, p.material);
    q.enqueueUnmapMemObject(density, p.density);
    q.finish();
}

EngineGBuffer GBufferPlanes::engine(int width, int height, const EngineCamera& camera,
                                    const EngineLight& light) const {
    EngineGBuffer g;
    g.width = width;
    g.height = height;
    g.camera = camera;
    g.depth.buffer = depth;
    g.normal.buffer = normal;
    g.tangent.buffer = tangent;
    g.uv.buffer = uv;
    g.light = light;
    return g;
}

EngineCamera pass_camera_of(const View& view) {
    EngineCamera c;
    c.inverse_view_projection = view.inverse_view_projection;
    c.eye = view.eye;
    c.orthographic = view.orthographic;
    c.depth = DepthConvention::GL;
    c.first_row = FirstRow::Bottom;
    return c;
}

OffsetTargets allocate_targets(Runtime& rt, size_t n) {
    auto buffer = [&](size_t bytes) { return cl::Buffer(rt.context(), CL_MEM_READ_WRITE, bytes); };
    OffsetTargets t;
    t.uv = buffer(n * sizeof(cl_float2));
    t.depth = buffer(n * sizeof(float));
    t.fetches = buffer(n * sizeof(cl_uint));
    t.flags = buffer(n * sizeof(cl_uint));
    return t;
}

}  // namespace offsetmap::renderer
