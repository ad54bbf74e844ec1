#include "light.hpp"

#include <algorithm>
#include <cmath>

#include "offsetmap/timing.hpp"

namespace offsetmap::renderer {

namespace {

// The scene seen from its light: a directional light's orthographic view of it, a spot's
// perspective one.
Scene light_view_of(const Scene& scene) {
    Scene lit = scene;
    const std::array<float, 3>& l = scene.light.vector;
    lit.camera = scene.light.kind == LightKind::Spot ? spot_camera(scene, scene.light)
                                                     : light_camera(scene, {l[0], l[1], l[2]});
    return lit;
}

View two_sided(View v) {
    v.two_sided = true;
    return v;
}

// The texels (GL's rows) that `scene`'s meshes can cover in `view`: their vertices' bounding box
// in the map, a texel around (a triangle lies within its vertices' hull; clipping only takes
// away), clamped to the map.
PixelRegion covered_texels(const Scene& scene, const View& view, int size) {
    float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    const std::array<float, 16>& m = view.view_projection;
    for (const Mesh& mesh : scene.meshes)
        for (const Vertex& v : mesh.vertices) {
            const Vec3& p = v.position;
            const float w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
            if (!(w > 0.0f)) return {0, 0, size, size};  // behind a spot: its box is no bound
            for (int a = 0; a < 2; ++a) {
                const float c = m[a] * p[0] + m[4 + a] * p[1] + m[8 + a] * p[2] + m[12 + a];
                const float texel = (0.5f * c / w + 0.5f) * float(size);
                lo[a] = std::min(lo[a], texel);
                hi[a] = std::max(hi[a], texel);
            }
        }
    if (!(lo[0] <= hi[0] && lo[1] <= hi[1])) return {0, 0, size, size};
    const auto clamp = [&](float t) { return std::clamp(static_cast<int>(t), 0, size); };
    const int x0 = clamp(std::floor(lo[0]) - 1), y0 = clamp(std::floor(lo[1]) - 1);
    const int x1 = clamp(std::ceil(hi[0]) + 2), y1 = clamp(std::ceil(hi[1]) + 2);
    return {x0, y0, x1 - x0, y1 - y0};
}

// What the depth offset reads of the offset: t (and uv', which every trace writes); no fetches or
// flags.
OffsetTargets light_targets(Runtime& rt, size_t n) {
    OffsetTargets t;
    t.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    t.depth = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(float));
    return t;
}

}  // namespace

LightStage::LightStage(std::shared_ptr<Runtime> runtime, const Scene& scene,
                       const std::vector<FrameMaterial>& materials, int size)
    : LightStage(std::move(runtime), light_view_of(scene), materials, size, 0) {}

LightStage::LightStage(std::shared_ptr<Runtime> runtime, const Scene& lit,
                       const std::vector<FrameMaterial>& materials, int size, int)
    : rt_(std::move(runtime)),
      size_(size),
      view_(two_sided(make_view(lit.camera, size, size))),
      covered_(covered_texels(lit, view_, size)),
      raster_(lit, size, size),
      planes_(*rt_, static_cast<size_t>(size) * size, true),
      // No light vector: nothing in the light's view is shaded.
      dg_(allocate_gbuffer(*rt_, size, size, false, false)),
      targets_(light_targets(*rt_, static_cast<size_t>(size) * size)),
      frame_(rt_, materials),
      depth_offset_(rt_),
      depth_after_(rt_->context(), CL_MEM_READ_WRITE,
                   static_cast<size_t>(size) * size * sizeof(float)) {
    dg_.material = planes_.ids;
    if (frame_.triplanar_table().any) triplanar_ = allocate_triplanar(*rt_, size, size);
}

PassTimes LightStage::draw(ReconstructPass& reconstruct, bool curved) {
    const cl::CommandQueue& q = rt_->queue();
    const size_t n = static_cast<size_t>(size_) * size_;
    dg_.curvature = curved ? planes_.curvature : cl::Buffer();
    // The whole map first, and again when the curvature plane joins (its texels outside the box
    // then hold the empty map's too).
    const bool whole = !whole_drawn_ || (curved && !whole_curved_);
    whole_drawn_ = true;
    whole_curved_ = whole_curved_ || curved;
    const std::vector<PixelRegion> box = {covered_};
    PassTimes t;
    Stopwatch clock;
    raster_.set_scissor(whole ? nullptr : &covered_);
    raster_.draw(view_, nullptr, false, false, curved, curved);
    t.gbuffer = clock.lap();
    planes_.move_from(q, raster_, n, curved, whole ? nullptr : &box);
    t.to_device = clock.lap();
    EngineCamera camera = pass_camera_of(view_);
    EngineGBuffer g = planes_.engine(size_, size_, camera, EngineLight());
    if (!whole) g.regions = box;
    if (triplanar_)
        reconstruct.enqueue(g, dg_, frame_.triplanar_table(), *triplanar_);
    else
        reconstruct.enqueue(g, dg_);
    q.finish();
    t.reconstruct = clock.lap();
    (triplanar_ ? frame_.enqueue(dg_, targets_, *triplanar_) : frame_.enqueue(dg_, targets_));
    q.finish();
    t.offset = clock.lap();
    depth_offset_.enqueue({size_, size_, camera, view_.view_projection, planes_.depth,
                           targets_.depth, planes_.density},
                          {depth_after_});
    q.finish();
    t.depth_offset = clock.lap();
    t.total = t.gbuffer + t.to_device + t.reconstruct + t.offset + t.depth_offset;
    return t;
}

ShadowMapView LightStage::map(bool displaced) const {
    return {size_, size_, pass_camera_of(view_), view_.view_projection,
            displaced ? depth_after_ : planes_.depth};
}

}  // namespace offsetmap::renderer
