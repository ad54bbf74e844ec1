// The frame's order: the light's stage, the camera's raster and transfer, the reconstruct, offset
// (with the layer behind's stage), depth offset, receivers' test and shade passes, the results
// back to GL. Each pass is core's, called as an engine calls it; the stages are in stages/.
#include "offsetmap/renderer/frame.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "frame_impl.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/material_eval.hpp"
#include "offsetmap/settings.hpp"

namespace offsetmap::renderer {

std::string forward_unsupported(const MaterialSpec& material, const MethodParams& params) {
    const std::string why = forward_method_unsupported(params);
    return why.empty() ? why
                       : "material " + std::to_string(material.id) + " (" + material.name +
                             "): --forward: " + why;
}

std::string forward_method_unsupported(const MethodParams& p) {
    const MethodInfo& method = *p.method;
    if (method.glsl.empty()) {
        std::string known;
        for (const MethodInfo& m : methods())
            if (!m.glsl.empty()) known += (known.empty() ? "" : ", ") + m.name;
        return "method '" + method.name + "' has no forward (GLSL) version; forward has " + known;
    }
    for (const auto& [name, value] : method.glsl_only_with)
        if (p[name] != value) {
            std::ostringstream msg;
            msg << "forward " << method.name << " takes " << name << "=" << value << " only ("
                << name << "=" << p[name] << ")";
            return msg.str();
        }
    return "";
}

FrameRenderer::FrameRenderer(std::shared_ptr<Runtime> runtime, const Scene& scene,
                             const std::vector<LoadedMaterial>& table,
                             const std::vector<MethodParams>& methods, int width, int height,
                             const ShadeSettings& shading)
    : impl_(std::make_unique<Impl>()) {
    check_gbuffer_size(width, height, "the frame");
    Impl& m = *impl_;
    m.rt = runtime;
    m.gl = GlContext::create();
    m.width = width;
    m.height = height;
    m.table = table;
    m.methods = methods;
    m.shading = shading;
    m.light = scene.light;
    m.view = make_view(scene.camera, width, height);
    m.raster = std::make_unique<Raster>(scene, width, height);
    m.scene = scene;
    for (size_t s = 0; s < table.size(); ++s)
        m.forward.push_back(forward_material(table[s].spec.id, table[s].map, table[s].spec.settings,
                                             methods[s], table[s].spec.triplanar));
    Runtime& rt = *runtime;
    const size_t n = m.pixels();
    m.planes = GBufferPlanes(rt, n, true);
    m.dg = allocate_gbuffer(rt, width, height, scene.light.kind != LightKind::None, false);
    m.dg.material = m.planes.ids;
    m.targets = allocate_targets(rt, n);
    // Mapped by the host for GL; the depth after is also the receivers' test's input.
    const cl_mem_flags mapped = CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR;
    m.rgba = cl::Buffer(rt.context(), mapped, n * sizeof(cl_float4));
    m.depth_after = cl::Buffer(rt.context(), mapped, n * sizeof(float));
    m.depth_offset = std::make_unique<DepthOffsetPass>(runtime);
    m.frame = std::make_unique<MaterialFrame>(runtime, upload_materials(rt, table, methods));
    if (m.frame->triplanar_table().any) m.triplanar = allocate_triplanar(rt, width, height);
    m.reconstruct = std::make_unique<ReconstructPass>(runtime);
    interop_ = "host copies (the OpenCL platform offers no cl_khr_gl_sharing)";
    if (rt.device().getInfo<CL_DEVICE_EXTENSIONS>().find("cl_khr_gl_sharing") != std::string::npos)
        interop_ = "host copies (cl_khr_gl_sharing is offered; sharing is not implemented yet)";
}

// GL names are the context's own: the stages' objects are deleted with this renderer's context
// current (another's current would lose its objects of the same names).
FrameRenderer::~FrameRenderer() {
    if (!impl_ || !impl_->gl) return;
    try {
        impl_->gl->make_current();
    } catch (const Error&) {  // its objects then go with the context
    }
}

std::pair<double, double> FrameRenderer::rerun_kernels(int repeats) {
    Impl& m = *impl_;
    std::vector<double> shade, offset;
    for (int k = 0; k < repeats && m.rt->profiling(); ++k) {
        const TriplanarPlanes* tri = m.triplanar ? &*m.triplanar : nullptr;
        const cl::Event s =
            m.frame->shade(m.dg, frame_shade_inputs(m.targets, tri), m.shading, {m.rgba});
        s.wait();
        shade.push_back(event_ms(s));
        (tri ? m.frame->enqueue(m.dg, m.targets, *tri) : m.frame->enqueue(m.dg, m.targets)).wait();
        offset.push_back(m.frame->kernel_ms());
    }
    return {median(shade), median(offset)};
}

void FrameRenderer::set_shading(const ShadeSettings& shading) { impl_->shading = shading; }

void FrameRenderer::set_curvature(bool on) {
    impl_->dg.curvature = on ? impl_->planes.curvature : cl::Buffer();
}

void FrameRenderer::set_uv_metric(bool on) {
    impl_->dg.uv_metric = on ? impl_->planes.uv_metric : cl::Buffer();
    impl_->raster->set_forward_metric(on);
}

void FrameRenderer::set_layers(int layers, bool whole) {
    if (layers != 1 && layers != 2)
        throw Error("a frame has 1 or 2 G-buffer layers, not " + std::to_string(layers));
    Impl& m = *impl_;
    m.layers = layers;
    m.whole_behind = whole;
    if (layers == 1 || m.behind) return;
    m.gl->make_current();
    m.behind = std::make_unique<BehindStage>(*m.rt, m.scene, m.width, m.height,
                                             m.light.kind != LightKind::None);
}

void FrameRenderer::set_shadow_map(const std::optional<ShadowMapSettings>& settings) {
    Impl& m = *impl_;
    if (!settings) {
        m.shadows.reset();
        return;
    }
    const ShadowMapSettings& s = *settings;
    if (m.light.kind != LightKind::Directional && m.light.kind != LightKind::Spot)
        throw Error("a shadow map needs the scene's light to be directional or a spot");
    if (s.size < 16 || s.size > 8192)
        throw Error("the shadow map's size must be in [16, 8192] texels, got " +
                    std::to_string(s.size));
    if (s.pcf_radius < 0 || s.pcf_radius > 8)
        throw Error("the shadow map's filter radius must be in [0, 8] texels, got " +
                    std::to_string(s.pcf_radius));
    // The light's stage and the buffers depend on the map's size alone: another filter, or a
    // flat map for a displaced one, keeps them.
    if (m.shadows && m.shadows->light->size() == s.size) {
        m.shadows->settings = s;
        return;
    }
    m.shadows.reset();
    m.gl->make_current();
    auto sh = std::make_unique<Impl::Shadows>();
    sh->settings = s;
    sh->light = std::make_unique<LightStage>(m.rt, m.scene, m.frame->materials(), s.size);
    sh->test = std::make_unique<ShadowMaskPass>(m.rt);
    const size_t n = m.pixels();
    sh->mask = cl::Buffer(m.rt->context(), CL_MEM_READ_WRITE, n * sizeof(float));
    sh->visibility = cl::Buffer(m.rt->context(), CL_MEM_READ_WRITE, n * sizeof(float));
    m.shadows = std::move(sh);
}

std::string FrameRenderer::gl_renderer() const {
    impl_->gl->make_current();  // another renderer's context may be current, or none
    return impl_->gl->renderer();
}

std::array<float, 16> FrameRenderer::view_projection() const { return impl_->view.view_projection; }

EngineCamera FrameRenderer::pass_camera() const { return impl_->camera(); }

ShadowMapView FrameRenderer::shadow_map_view(const cl::Buffer& depth) const {
    return {impl_->width, impl_->height, pass_camera(), view_projection(), depth};
}

size_t FrameRenderer::covered_pixels() const {
    size_t c = 0;
    for (float d : engine_.depth) c += d < 1.0f;
    return c;
}

FrameRun FrameRenderer::render(FrameMode mode, bool prepass, int repeats) {
    Impl& m = *impl_;
    const bool forward = mode == FrameMode::Forward;
    // The forward shader's view is from an eye point; a light's orthographic view is deferred's.
    if (forward && m.view.orthographic)
        throw Error("the forward peer draws perspective views only; the camera is orthographic");
    for (size_t s = 0; forward && s < m.methods.size(); ++s)
        if (const std::string why = forward_unsupported(m.table[s].spec, m.methods[s]);
            !why.empty())
            throw Error(why);
    m.gl->make_current();
    FrameRun run;
    run.mode = mode;
    run.prepass = prepass;
    run.curved = m.dg.curvature() != nullptr;
    run.layers = forward ? 1 : m.layers;
    FrameScratch scratch;
    std::vector<PassTimes> times, light_times;
    for (int rep = 0; rep <= std::max(1, repeats); ++rep) {
        const PassTimes t = m.render_frame(run, prepass, scratch);
        ++run.frames;
        if (rep == 0) continue;  // the first frame warms up
        times.push_back(t);
        if (m.shadows && !forward) light_times.push_back(scratch.light);
    }
    run.light_draws = scratch.light_draws;
    run.ms = median_times(times);
    run.shadow_map_ms = median_times(light_times);
    run.offset_kernel_ms = median(scratch.offset_kernel);
    run.shade_kernel_ms = median(scratch.shade_kernel);
    if (!forward) run.offset.kernel_ms = scratch.offset_kernel;
    // Depth, normal, tangent, uv, material id and uv density (forward: and the offset plane;
    // deferred with curvature: and the curvature); the colour and the depth after the offset.
    run.to_device_bytes = m.pixels() * sizeof(float) *
                          (1 + 4 + 4 + 2 + 1 + 1 + (forward || run.curved ? 4 : 0)) *
                          (run.layers == 2 ? 2 : 1);
    run.to_gl_bytes = m.pixels() * sizeof(float) * (4 + 1);
    m.read_back(run, prepass, scratch, engine_, explicit_);
    return run;
}

PassTimes FrameRenderer::Impl::render_frame(const FrameRun& run, bool prepass, FrameScratch& s) {
    PassTimes t;
    Stopwatch clock;
    const bool forward = run.mode == FrameMode::Forward;
    if (shadows && !forward) {
        // The light's view first, as an engine draws its shadow maps: depth only.
        s.light = shadows->light->draw(*reconstruct, run.curved);
        shadows->drawn = true;
        ++s.light_draws;
        clock.lap();
    }
    draw_and_move(run, prepass, s, clock, t);
    const EngineGBuffer g = planes.engine(width, height, camera(), light);
    if (triplanar)
        reconstruct->enqueue(g, dg, frame->triplanar_table(), *triplanar);
    else
        reconstruct->enqueue(g, dg);
    rt->queue().finish();
    if (forward && triplanar) order_forward_projections(s);
    t.reconstruct = clock.lap();
    if (!forward) offset(run, g, s, clock, t);
    light_and_shade(run, s, clock, t);
    t.total = clock.total();
    return t;
}

void FrameRenderer::Impl::draw_and_move(const FrameRun& run, bool prepass, FrameScratch& s,
                                        Stopwatch& clock, PassTimes& t) {
    const bool forward = run.mode == FrameMode::Forward;
    raster->draw(view, forward ? &this->forward : nullptr, prepass, false, run.curved && !forward,
                 run.curved);
    t.gbuffer = clock.lap();
    const cl::CommandQueue& q = rt->queue();
    const size_t n = pixels();
    planes.move_from(q, *raster, n, run.curved && !forward);
    if (run.curved && !forward && dg.uv_metric()) planes.move_metric_from(q, *raster, view, n);
    if (forward) {
        s.forward_uv.resize(n);
        s.forward_fetches.resize(n);
        s.t_gl.resize(n);
        const std::vector<float> off = raster->read_offset();
        for (size_t k = 0; k < n; ++k) {
            s.forward_uv[k] = {{off[4 * k], off[4 * k + 1]}};
            s.t_gl[k] = off[4 * k + 2];
            s.forward_fetches[k] = static_cast<std::uint32_t>(off[4 * k + 3]);
        }
        q.enqueueWriteBuffer(targets.uv, CL_FALSE, 0, n * sizeof(cl_float2), s.forward_uv.data());
        q.enqueueWriteBuffer(targets.depth, CL_FALSE, 0, n * sizeof(float), s.t_gl.data());
        q.finish();
    }
    t.to_device = clock.lap();
}

void FrameRenderer::Impl::offset(const FrameRun& run, const EngineGBuffer& g, FrameScratch& s,
                                 Stopwatch& clock, PassTimes& t) {
    if (run.layers == 2) {
        // The first layer, then the second drawn, read and traced only where the first left its
        // pixels for what lies behind (its times go to those passes' columns); set_layers's
        // `whole` draws, reads and reconstructs all of it.
        frame->enqueue(dg, targets);
        behind->trace(view, {*raster, g, dg, targets, planes}, *reconstruct, *frame, run.curved,
                      run.curved && dg.uv_metric(), whole_behind, clock, t);
    } else if (triplanar) {
        frame->enqueue(dg, targets, *triplanar);
    } else {
        frame->enqueue(dg, targets);
    }
    rt->queue().finish();
    t.offset += clock.lap();
    s.offset_kernel.push_back(frame->kernel_ms());
}

void FrameRenderer::Impl::light_and_shade(const FrameRun& run, FrameScratch& s, Stopwatch& clock,
                                          PassTimes& t) {
    const bool forward = run.mode == FrameMode::Forward;
    const cl::CommandQueue& q = rt->queue();
    const size_t n = pixels();
    // The pixel depth offset, from the depth, t and the uv density already on the device: before
    // the shading, whose shadow test takes the depth it writes.
    const EngineCamera cam = camera();
    depth_offset->enqueue(
        {width, height, cam, view.view_projection, planes.depth, targets.depth, planes.density},
        {depth_after});
    q.finish();
    t.depth_offset = clock.lap();
    Shadows* sh = forward ? nullptr : shadows.get();
    if (sh) {
        ShadowMaskInputs in;
        in.width = width;
        in.height = height;
        in.camera = cam;
        in.depth = sh->settings.displaced ? depth_after : planes.depth;
        in.map = sh->light->map(sh->settings.displaced);
        in.pcf_radius = sh->settings.pcf_radius;
        sh->test->enqueue(in, {sh->mask});
        q.finish();
        t.shadow_mask = clock.lap();
    }
    FrameShadeInputs in = frame_shade_inputs(targets, triplanar ? &*triplanar : nullptr);
    if (forward) in.flags = cl::Buffer();
    if (sh) in.shadow_mask = sh->mask;
    const cl::Event shaded =
        frame->shade(dg, in, shading, {rgba, sh ? sh->visibility : cl::Buffer()});
    q.finish();
    t.shade = clock.lap();
    if (rt->profiling()) s.shade_kernel.push_back(event_ms(shaded));
    // What GL takes back: the colour and the depth, from the mapped buffers.
    const auto* color = static_cast<const float*>(
        q.enqueueMapBuffer(rgba, CL_TRUE, CL_MAP_READ, 0, n * sizeof(cl_float4)));
    const auto* after = static_cast<const float*>(
        q.enqueueMapBuffer(depth_after, CL_TRUE, CL_MAP_READ, 0, n * sizeof(float)));
    raster->write_results(color, after);
    q.enqueueUnmapMemObject(rgba, const_cast<float*>(color));
    q.enqueueUnmapMemObject(depth_after, const_cast<float*>(after));
    q.finish();
    t.to_gl = clock.lap();
}

GeometryFrame FrameRenderer::render_geometry(const Scene& scene, int repeats) {
    Impl& m = *impl_;
    m.gl->make_current();
    Raster raster(scene, m.width, m.height);
    std::vector<double> times;
    for (int k = 0; k <= repeats; ++k) {
        Stopwatch clock;
        raster.draw(m.view, nullptr, false);  // ends in glFinish
        if (k > 0) times.push_back(clock.lap());
    }
    const RasterPlanes planes = raster.read(false);
    GeometryFrame g;
    g.raster_ms = median(times);
    g.uv = flip_rows(planes.uv, m.width, m.height, 2);
    g.depth = flip_rows(planes.depth, m.width, m.height, 1);
    const size_t n = static_cast<size_t>(m.width) * m.height;
    g.material.resize(n);
    g.density.resize(n);
    g.normal.resize(3 * n);
    const std::vector<float> normals = flip_rows(planes.normal, m.width, m.height, 4);
    for (size_t k = 0; k < n; ++k)
        for (int c = 0; c < 3; ++c) g.normal[3 * k + c] = normals[4 * k + c];
    const std::vector<float> ids = flip_rows(planes.material, m.width, m.height, 2);
    for (size_t k = 0; k < n; ++k) {
        g.material[k] = ids[2 * k];
        g.density[k] = ids[2 * k + 1];
    }
    bool triplanar = false;
    for (const LoadedMaterial& t : m.table) triplanar = triplanar || t.spec.triplanar.enabled;
    if (triplanar) {
        const std::vector<float> tangents = flip_rows(planes.tangent, m.width, m.height, 4);
        g.base_point.assign(3 * n, std::nanf(""));
        for (size_t k = 0; k < n; ++k)
            for (const LoadedMaterial& t : m.table)
                if (t.spec.triplanar.enabled && g.depth[k] < 1.0f &&
                    g.material[k] == static_cast<float>(t.spec.id))
                    std::copy_n(&tangents[4 * k], 3, &g.base_point[3 * k]);
    }
    return g;
}

OffsetResult FrameRenderer::exact() const {
    // The G-buffer holds each triplanar pixel's largest projection (the split's): exact traces
    // that one, as the pass does, with the table's materials taken as uv-mapped.
    std::vector<LoadedMaterial> table = impl_->table;
    for (LoadedMaterial& m : table) m.spec.triplanar.enabled = false;
    OffsetResult r = run_materials_exact(impl_->rt, table, impl_->dg);
    flip_result(r);
    return r;
}

}  // namespace offsetmap::renderer

#include "offsetmap/image_io.hpp"

namespace offsetmap::renderer {
std::vector<float> flip_row_order(const std::vector<float>& in, int width, int height, int c) {
    return flip_rows(in, width, height, c);
}
void write_depth_exr(const std::string& path, int width, int height,
                     const std::vector<float>& depth) {
    write_float_exr(path, "depth", width, height, {"depth"}, depth, {{"offsetmap:depth", "gl"}});
}
}  // namespace offsetmap::renderer
