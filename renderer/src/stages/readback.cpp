// After a render's timed frames: the last frame's outputs read back once, rows top first, and the
// G-buffer as the engine wrote it (with the uv derivatives and the curvature, which the timed
// frames do not draw).
#include <cmath>

#include "../frame_impl.hpp"
#include "light.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

PassTimes median_times(const std::vector<PassTimes>& times) {
    PassTimes out;
    for (double PassTimes::*f :
         {&PassTimes::gbuffer, &PassTimes::to_device, &PassTimes::reconstruct, &PassTimes::offset,
          &PassTimes::shade, &PassTimes::to_gl, &PassTimes::depth_offset, &PassTimes::shadow_mask,
          &PassTimes::total}) {
        std::vector<double> v;
        for (const PassTimes& t : times) v.push_back(t.*f);
        out.*f = median(v);
    }
    return out;
}

void flip_result(OffsetResult& r) {
    r.uv = flip_rows(r.uv, r.width, r.height, 1);
    r.depth = flip_rows(r.depth, r.width, r.height, 1);
    r.fetches = flip_rows(r.fetches, r.width, r.height, 1);
    r.flags = flip_rows(r.flags, r.width, r.height, 1);
}

namespace {

template <typename T>
std::vector<T> read(const cl::CommandQueue& q, const cl::Buffer& b, size_t count) {
    std::vector<T> v(count);
    q.enqueueReadBuffer(b, CL_TRUE, 0, count * sizeof(T), v.data());
    return v;
}

// Per triplanar pixel the projections it traced (1 to 3, 0 elsewhere) and its first one.
void read_projections(const cl::CommandQueue& q, const TriplanarPlanes& tri, int w, int h,
                      FrameRun& run) {
    const size_t n = static_cast<size_t>(w) * h;
    const std::vector<cl_float4> blend = read<cl_float4>(q, tri.blend, n);
    // x = 2 c + w1 (negative: not triplanar), y = w2 (kernels/common/triplanar.cl).
    // c = p0 + 6 [the second on the first's B axis].
    run.projection_count.assign(n, 0.0f);
    run.first_projection.assign(n, -1);
    for (size_t k = 0; k < n; ++k) {
        const cl_float4& b = blend[k];
        if (!(b.s[0] >= 0.0f)) continue;
        const float c = std::floor(0.5f * b.s[0]);
        const int more = (b.s[0] > 2.0f * c) + (b.s[1] > 0.0f);
        ++run.projections[more];
        run.projection_count[k] = float(1 + more);
        run.first_projection[k] = static_cast<std::int8_t>(static_cast<int>(c) % 6);
    }
    run.projection_count = flip_rows(run.projection_count, w, h, 1);
    run.first_projection = flip_rows(run.first_projection, w, h, 1);
}

// The G-buffer as the engine wrote it (depth GL, rows top first, with ids and uv derivatives).
void engine_scene(const RasterPlanes& planes, const Raster& raster, const EngineCamera& camera,
                  const EngineLight& light, const std::vector<float>& ids, int w, int h,
                  EngineScene& engine) {
    const size_t n = static_cast<size_t>(w) * h;
    engine.width = w;
    engine.height = h;
    engine.camera = camera;
    engine.camera.first_row = FirstRow::Top;
    engine.frame = FrameForm::NormalTangent;
    engine.light = light;
    engine.depth = flip_rows(planes.depth, w, h, 1);
    engine.normal = flip_rows(planes.normal, w, h, 4);
    engine.tangent = flip_rows(planes.tangent, w, h, 4);
    engine.uv = flip_rows(planes.uv, w, h, 2);
    engine.material = flip_rows(ids, w, h, 1);
    // Per pixel right and per row down (rows now top first: GL's dFdy flips sign).
    engine.uv_derivatives = flip_rows(raster.read_uv_derivatives(), w, h, 4);
    for (size_t k = 0; k < n; ++k) {
        engine.uv_derivatives[4 * k + 2] *= -1.0f;
        engine.uv_derivatives[4 * k + 3] *= -1.0f;
    }
    const std::vector<float> curvature = flip_rows(raster.read_curvature(), w, h, 4);
    engine.curvature.resize(3 * n);
    engine.uv_stretch.resize(n);
    for (size_t k = 0; k < n; ++k) {
        std::copy_n(&curvature[4 * k], 3, &engine.curvature[3 * k]);
        engine.uv_stretch[k] = curvature[4 * k + 3];
    }
}

}  // namespace

void FrameRenderer::Impl::read_back(FrameRun& run, bool prepass, FrameScratch& s,
                                    EngineScene& engine, GBuffer& explicit_gbuffer) {
    const bool forward = run.mode == FrameMode::Forward;
    const cl::CommandQueue& q = rt->queue();
    const int w = width, h = height;
    const size_t n = pixels();
    // The same draw with the uv derivatives and the curvature kept (the G-buffer file's).
    raster->draw(view, forward ? &this->forward : nullptr, prepass, true, true, run.curved);
    const RasterPlanes drawn = raster->read(false);
    std::vector<float> ids(n);
    for (size_t k = 0; k < n; ++k) ids[k] = drawn.material[2 * k];
    run.material = run.layers == 2 ? read<float>(q, planes.ids, n) : ids;
    run.material = flip_rows(run.material, w, h, 1);
    run.color = flip_rows(read<cl_float4>(q, rgba, n), w, h, 1);
    OffsetResult& out = run.offset;
    out.width = w;
    out.height = h;
    out.depth = forward ? s.t_gl : read<float>(q, targets.depth, n);
    if (forward) {
        out.uv = std::move(s.forward_uv);
        out.fetches = std::move(s.forward_fetches);
        out.flags.assign(n, 0u);
        for (size_t k = 0; k < n; ++k)
            if (std::isnan(drawn.uv[2 * k])) out.flags[k] = OM_FLAG_EMPTY;
    } else {
        out.uv = read<cl_float2>(q, targets.uv, n);
        out.fetches = read<std::uint32_t>(q, targets.fetches, n);
        out.flags = read<std::uint32_t>(q, targets.flags, n);
    }
    flip_result(out);
    for (std::uint32_t f : out.flags) {
        run.behind_pixels += (f & OM_FLAG_BEHIND) != 0;
        run.missed_pixels += run.layers == 2 && (f & OM_FLAGS_SEE_BEHIND);
    }
    if (triplanar) read_projections(q, *triplanar, w, h, run);
    run.depth_after = flip_rows(raster->depth_after(), w, h, 1);
    if (shadows && !forward) {
        run.shadow_mask = flip_rows(read<float>(q, shadows->mask, n), w, h, 1);
        run.light_visibility = flip_rows(read<float>(q, shadows->visibility, n), w, h, 1);
    }
    run.shaded_fragments =
        raster->count_fragments(view, forward ? &this->forward : nullptr, prepass, run.curved);
    engine_scene(drawn, *raster, camera(), light, ids, w, h, engine);

    // The explicit G-buffer, as the passes saw it (rows top first).
    explicit_gbuffer.resize(w, h, dg.light(), false);
    explicit_gbuffer.uv = flip_rows(read<cl_float2>(q, dg.uv, n), w, h, 1);
    explicit_gbuffer.view = flip_rows(read<cl_float4>(q, dg.view, n), w, h, 1);
    if (dg.light()) explicit_gbuffer.light = flip_rows(read<cl_float4>(q, dg.light, n), w, h, 1);
    explicit_gbuffer.material = run.material;
}

LightMaps FrameRenderer::light_maps() const {
    const Impl& m = *impl_;
    if (!m.shadows || !m.shadows->drawn)
        throw offsetmap::Error(
            "no shadow map drawn: light_maps needs a deferred render with set_shadow_map");
    const int n = m.shadows->light->size();
    const auto rows = [&](bool displaced) {
        return flip_rows(
            read<float>(m.rt->queue(), m.shadows->light->map(displaced).depth, size_t(n) * n), n, n,
            1);
    };
    return {n, rows(false), rows(true), m.shadows->light->map(true).camera.inverse_view_projection};
}

}  // namespace offsetmap::renderer
