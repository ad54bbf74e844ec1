#include "light.hpp"

#include "offsetmap/timing.hpp"

namespace offsetmap::renderer {

namespace {

Scene light_view_of(const Scene& scene) {
    Scene lit = scene;
    const std::array<float, 3>& l = scene.light.vector;
    lit.camera = light_camera(scene, {l[0], l[1], l[2]});
    return lit;
}

}  // namespace

LightStage::LightStage(std::shared_ptr<Runtime> runtime, const Scene& scene,
                       const std::vector<FrameMaterial>& materials, int size)
    : LightStage(std::move(runtime), light_view_of(scene), materials, size, 0) {}

LightStage::LightStage(std::shared_ptr<Runtime> runtime, const Scene& lit,
                       const std::vector<FrameMaterial>& materials, int size, int)
    : rt_(std::move(runtime)),
      size_(size),
      view_(make_view(lit.camera, size, size)),
      raster_(lit, size, size),
      planes_(*rt_, static_cast<size_t>(size) * size, true),
      // No light vector: nothing in the light's view is shaded.
      dg_(allocate_gbuffer(*rt_, size, size, false, false)),
      targets_(allocate_targets(*rt_, static_cast<size_t>(size) * size)),
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
    PassTimes t;
    Stopwatch clock;
    raster_.draw(view_, nullptr, false, false, curved, curved);
    t.gbuffer = clock.lap();
    planes_.move_from(q, raster_, n, curved);
    t.to_device = clock.lap();
    EngineCamera camera = pass_camera_of(view_);
    const EngineGBuffer g = planes_.engine(size_, size_, camera, EngineLight());
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
