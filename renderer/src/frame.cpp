#include "offsetmap/renderer/frame.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "offsetmap/error.hpp"
#include "offsetmap/material_eval.hpp"
#include "offsetmap/renderer/context.hpp"
#include "offsetmap/renderer/depth_offset.hpp"
#include "offsetmap/renderer/shadow_mask.hpp"
#include "offsetmap/settings.hpp"
#include "raster.hpp"

namespace offsetmap::renderer {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Rows bottom first (GL) to top first, `c` values per pixel (an empty plane stays empty).
template <typename T>
std::vector<T> flip_rows(const std::vector<T>& in, int width, int height, int c) {
    std::vector<T> out(in.size());
    const size_t row = static_cast<size_t>(width) * c;
    if (in.empty()) return out;
    for (int y = 0; y < height; ++y)
        std::copy_n(in.begin() + row * (height - 1 - y), row, out.begin() + row * y);
    return out;
}

// The pixels whose first layer leaves them to the one behind (`needed`, in order), and the
// rectangles the second layer's planes are read from: in each band of kBand rows, runs of kBand
// columns that hold such pixels, joined across gaps of at most kGap columns.
std::vector<PixelRegion> needed_behind(const std::vector<std::uint32_t>& flags, int width,
                                       int height, std::vector<std::uint32_t>& needed) {
    constexpr int kBand = 16, kGap = 32;
    needed.clear();
    std::vector<PixelRegion> regions;
    std::vector<std::uint8_t> used((width + kBand - 1) / kBand);
    for (int band = 0; band < height; band += kBand) {
        const int rows = std::min(kBand, height - band);
        std::fill(used.begin(), used.end(), 0);
        for (int y = band; y < band + rows; ++y)
            for (int x = 0; x < width; ++x) {
                const size_t k = static_cast<size_t>(y) * width + x;
                if (!(flags[k] & OM_FLAGS_SEE_BEHIND)) continue;
                needed.push_back(static_cast<std::uint32_t>(k));
                used[x / kBand] = 1;
            }
        for (int c = 0; c < static_cast<int>(used.size()); ++c) {
            if (!used[c]) continue;
            int end = c + 1;  // one past the run's last column of kBand
            for (int next = end;
                 next < static_cast<int>(used.size()) && (next - end) * kBand <= kGap; ++next)
                if (used[next]) end = next + 1;
            const int x = c * kBand;
            regions.push_back({x, band, std::min(end * kBand, width) - x, rows});
            c = end - 1;
        }
    }
    return regions;
}

void flip_result(OffsetResult& r) {
    r.uv = flip_rows(r.uv, r.width, r.height, 1);
    r.depth = flip_rows(r.depth, r.width, r.height, 1);
    r.fetches = flip_rows(r.fetches, r.width, r.height, 1);
    r.flags = flip_rows(r.flags, r.width, r.height, 1);
}

}  // namespace

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

struct FrameRenderer::Impl {
    std::shared_ptr<Runtime> rt;
    std::unique_ptr<GlContext> gl;
    std::unique_ptr<Raster> raster;
    View view;
    EngineLight light;
    int width = 0, height = 0;
    std::vector<LoadedMaterial> table;
    std::vector<MethodParams> methods;
    std::vector<ForwardMaterial> forward;
    std::unique_ptr<MaterialFrame> frame;
    std::unique_ptr<ReconstructPass> reconstruct;
    ShadeSettings shading;
    // Device buffers: the engine G-buffer's planes with the uv density, the explicit G-buffer, the
    // outputs. The ones GL writes or reads are in host memory the host maps
    // (CL_MEM_ALLOC_HOST_PTR): GL reads its planes into them, and takes the colour and depth from
    // them, one copy each way.
    cl::Buffer depth, normal, tangent, uv, ids, density, curvature;
    DeviceGBuffer dg;  // its curvature bound only while set_curvature is on
    OffsetTargets targets;
    // A table with triplanar materials: their pixels' other projections, weights and normals.
    std::optional<TriplanarPlanes> triplanar;
    // The second layer (set_layers(2)): its raster, planes, G-buffer and targets, made at first
    // use.
    Scene scene;
    int layers = 1;
    bool whole_behind = false;  // set_layers's `whole`
    struct Behind {
        std::unique_ptr<Raster> raster;
        cl::Buffer depth, normal, tangent, uv, ids, density, curvature;
        DeviceGBuffer dg;
        OffsetTargets targets;
    };
    std::unique_ptr<Behind> behind;
    cl::Buffer rgba, depth_after;
    std::unique_ptr<DepthOffsetPass> depth_offset;
    OmDepthOffsetParams depth_params{};
    // The shadow map (set_shadow_map): the light's own frame, whose device depth is the map, the
    // receivers' test and its per-pixel outputs.
    struct Shadows {
        ShadowMapSettings settings;
        std::unique_ptr<FrameRenderer> light;
        std::unique_ptr<ShadowMaskPass> test;
        OmShadowMaskParams params{};
        cl::Buffer mask, visibility;
    };
    std::unique_ptr<Shadows> shadows;
};

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
    const size_t n = static_cast<size_t>(width) * height;
    auto buffer = [&](size_t bytes, cl_mem_flags flags) {
        return cl::Buffer(rt.context(), flags, bytes);
    };
    // Read-write: with a layer behind, its pixels take that layer's depth, ids, uv density and
    // curvature in place.
    const cl_mem_flags in = CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR;
    const cl_mem_flags taken = CL_MEM_READ_WRITE | CL_MEM_ALLOC_HOST_PTR;
    m.depth = buffer(n * sizeof(float), taken);
    m.normal = buffer(4 * n * sizeof(float), in);
    m.tangent = buffer(4 * n * sizeof(float), in);
    m.uv = buffer(2 * n * sizeof(float), in);
    m.ids = buffer(n * sizeof(float), taken);
    m.density = buffer(n * sizeof(float), taken);
    m.curvature = buffer(4 * n * sizeof(float), taken);
    m.dg = allocate_gbuffer(rt, width, height, scene.light.kind != LightKind::None, false);
    m.dg.material = m.ids;
    m.targets.uv = buffer(n * sizeof(cl_float2), CL_MEM_READ_WRITE);
    m.targets.depth = buffer(n * sizeof(float), CL_MEM_READ_WRITE);
    m.targets.fetches = buffer(n * sizeof(cl_uint), CL_MEM_READ_WRITE);
    m.targets.flags = buffer(n * sizeof(cl_uint), CL_MEM_READ_WRITE);
    m.rgba = buffer(n * sizeof(cl_float4), CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR);
    m.depth_after = buffer(n * sizeof(float), CL_MEM_WRITE_ONLY | CL_MEM_ALLOC_HOST_PTR);
    m.depth_offset = std::make_unique<DepthOffsetPass>(rt);
    m.depth_params = depth_offset_params(m.view.view_projection, m.view.inverse_view_projection,
                                         m.view.eye, width, height, m.view.orthographic);
    m.frame = std::make_unique<MaterialFrame>(runtime, upload_materials(rt, table, methods));
    if (m.frame->triplanar_table().any) m.triplanar = allocate_triplanar(rt, width, height);
    m.reconstruct = std::make_unique<ReconstructPass>(runtime);
    interop_ = "host copies (the OpenCL platform offers no cl_khr_gl_sharing)";
    if (rt.device().getInfo<CL_DEVICE_EXTENSIONS>().find("cl_khr_gl_sharing") != std::string::npos)
        interop_ = "host copies (cl_khr_gl_sharing is offered; sharing is not implemented yet)";
}

// GL names are the context's own: each renderer's objects are deleted with its context current
// (another's current would lose its objects of the same names), the light's renderer first.
FrameRenderer::~FrameRenderer() {
    if (!impl_ || !impl_->gl) return;
    impl_->shadows.reset();
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
        const cl::Event s = m.frame->shade(m.targets.uv, m.targets.flags, m.dg, m.shading, m.rgba,
                                           cl::Buffer(), cl::Buffer(), tri);
        s.wait();
        shade.push_back(event_ms(s));
        (tri ? m.frame->enqueue(m.dg, m.targets, *tri) : m.frame->enqueue(m.dg, m.targets)).wait();
        offset.push_back(m.frame->kernel_ms());
    }
    return {median(shade), median(offset)};
}

void FrameRenderer::set_shading(const ShadeSettings& shading) { impl_->shading = shading; }

void FrameRenderer::set_curvature(bool on) {
    impl_->dg.curvature = on ? impl_->curvature : cl::Buffer();
    // The light's view traces over the same curved base.
    if (impl_->shadows) impl_->shadows->light->set_curvature(on);
}

void FrameRenderer::set_layers(int layers, bool whole) {
    if (layers != 1 && layers != 2)
        throw Error("a frame has 1 or 2 G-buffer layers, not " + std::to_string(layers));
    Impl& m = *impl_;
    m.layers = layers;
    m.whole_behind = whole;
    if (layers == 1 || m.behind) return;
    m.gl->make_current();
    auto b = std::make_unique<Impl::Behind>();
    b->raster = std::make_unique<Raster>(m.scene, m.width, m.height);
    Runtime& rt = *m.rt;
    const size_t n = static_cast<size_t>(m.width) * m.height;
    auto buffer = [&](size_t floats, cl_mem_flags flags) {
        return cl::Buffer(rt.context(), flags, floats * sizeof(float));
    };
    const cl_mem_flags in = CL_MEM_READ_ONLY | CL_MEM_ALLOC_HOST_PTR;
    b->depth = buffer(n, in);
    b->normal = buffer(4 * n, in);
    b->tangent = buffer(4 * n, in);
    b->uv = buffer(2 * n, in);
    b->ids = buffer(n, in);
    b->density = buffer(n, in);
    b->curvature = buffer(4 * n, in);
    b->dg = allocate_gbuffer(rt, m.width, m.height, m.light.kind != LightKind::None, false);
    b->dg.material = b->ids;
    b->targets.uv = buffer(2 * n, CL_MEM_READ_WRITE);
    b->targets.depth = buffer(n, CL_MEM_READ_WRITE);
    b->targets.fetches = buffer(n, CL_MEM_READ_WRITE);
    b->targets.flags = buffer(n, CL_MEM_READ_WRITE);
    m.behind = std::move(b);
}

void FrameRenderer::set_shadow_map(const std::optional<ShadowMapSettings>& settings) {
    Impl& m = *impl_;
    if (!settings) {
        m.shadows.reset();
        return;
    }
    const ShadowMapSettings& s = *settings;
    if (m.light.kind != LightKind::Directional)
        throw Error("a shadow map needs the scene's light to be directional");
    if (s.size < 16 || s.size > 8192)
        throw Error("the shadow map's size must be in [16, 8192] texels, got " +
                    std::to_string(s.size));
    if (s.pcf_radius < 0 || s.pcf_radius > 8)
        throw Error("the shadow map's filter radius must be in [0, 8] texels, got " +
                    std::to_string(s.pcf_radius));
    // The light's renderer and the buffers depend on the map's size alone: another filter, or a
    // flat map for a displaced one, keeps them.
    if (m.shadows && m.shadows->settings.size == s.size) {
        m.shadows->settings = s;
        m.shadows->params.pcf_radius = s.pcf_radius;
        return;
    }
    m.shadows.reset();
    auto sh = std::make_unique<Impl::Shadows>();
    sh->settings = s;
    Scene lit = m.scene;
    const std::array<float, 3>& l = m.light.vector;
    lit.camera = light_camera(m.scene, {l[0], l[1], l[2]});
    ShadeSettings unshaded = m.shading;  // the light's colour is not used: no march for it
    unshaded.shadow = ShadowMode::None;
    sh->light =
        std::make_unique<FrameRenderer>(m.rt, lit, m.table, m.methods, s.size, s.size, unshaded);
    sh->light->set_curvature(m.dg.curvature() != nullptr);
    sh->test = std::make_unique<ShadowMaskPass>(*m.rt);
    sh->params = shadow_mask_params(m.view.inverse_view_projection, m.width, m.height,
                                    sh->light->view_projection(), s.size, s.size, s.pcf_radius);
    const size_t n = static_cast<size_t>(m.width) * m.height;
    sh->mask = cl::Buffer(m.rt->context(), CL_MEM_READ_WRITE, n * sizeof(float));
    sh->visibility = cl::Buffer(m.rt->context(), CL_MEM_READ_WRITE, n * sizeof(float));
    m.shadows = std::move(sh);
}

std::string FrameRenderer::gl_renderer() const {
    impl_->gl->make_current();  // another renderer's context may be current, or none
    return impl_->gl->renderer();
}

std::array<float, 16> FrameRenderer::view_projection() const { return impl_->view.view_projection; }

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
    Runtime& rt = *m.rt;
    const cl::CommandQueue& q = rt.queue();
    const int w = m.width, h = m.height;
    const size_t n = static_cast<size_t>(w) * h;
    // The device passes take GL's rows as they are (bottom first, as the reconstruct pass allows);
    // the outputs are flipped to top first once, after the timed frames.
    EngineCamera gl_camera;
    gl_camera.inverse_view_projection = m.view.inverse_view_projection;
    gl_camera.eye = m.view.eye;
    gl_camera.orthographic = m.view.orthographic;
    gl_camera.depth = DepthConvention::GL;
    gl_camera.first_row = FirstRow::Bottom;
    FrameRun run;
    run.mode = mode;
    run.prepass = prepass;
    run.curved = m.dg.curvature() != nullptr;
    run.layers = forward ? 1 : m.layers;
    Impl::Behind* behind = run.layers == 2 ? m.behind.get() : nullptr;
    if (behind) behind->dg.curvature = run.curved ? behind->curvature : cl::Buffer();
    RasterPlanes planes;
    std::vector<float> ids(n), t_gl(n);
    std::vector<cl_float2> forward_uv;
    std::vector<std::uint32_t> forward_fetches;
    std::vector<PassTimes> times;
    std::vector<double> kernel, shade_kernel;
    std::vector<std::uint32_t> flags(behind ? n : 0), needed;
    // The shadow map, once for the frames below (the light's view does not move with the
    // camera): the light's device depth after its offset, or its base depth for a flat map.
    Impl::Shadows* shadows = forward ? nullptr : m.shadows.get();
    cl::Buffer shadow_map;
    if (shadows) {
        Impl& l = *shadows->light->impl_;
        const FrameRun lr = shadows->light->render(FrameMode::Deferred, false, repeats);
        run.shadow_map_ms = lr.ms;
        run.shadow_map_ms.shade = run.shadow_map_ms.to_gl = 0;
        const PassTimes& t = run.shadow_map_ms;
        run.shadow_map_ms.total =
            t.gbuffer + t.to_device + t.reconstruct + t.offset + t.depth_offset;
        shadow_map = shadows->settings.displaced ? l.depth_after : l.depth;
        m.gl->make_current();
    }
    for (int rep = 0; rep <= std::max(1, repeats); ++rep) {
        PassTimes t;
        const auto start = Clock::now();
        auto t0 = start;
        m.raster->draw(m.view, forward ? &m.forward : nullptr, prepass, false,
                       run.curved && !forward, run.curved);
        t.gbuffer = ms_since(t0);

        t0 = Clock::now();
        // The planes straight into the mapped buffers: GL's read is the one copy.
        auto move_planes = [&](const Raster& raster, const cl::Buffer& depth,
                               const cl::Buffer& normal, const cl::Buffer& tangent,
                               const cl::Buffer& uv, const cl::Buffer& ids,
                               const cl::Buffer& density, const cl::Buffer& curvature,
                               const std::vector<PixelRegion>* regions = nullptr) {
            auto map = [&](const cl::Buffer& b, size_t floats) {
                return static_cast<float*>(q.enqueueMapBuffer(
                    b, CL_TRUE, CL_MAP_WRITE_INVALIDATE_REGION, 0, floats * sizeof(float)));
            };
            PlanePointers p;
            p.depth = map(depth, n);
            p.normal = map(normal, 4 * n);
            p.tangent = map(tangent, 4 * n);
            p.uv = map(uv, 2 * n);
            p.material = map(ids, n);
            p.density = map(density, n);
            if (run.curved && !forward) p.curvature = map(curvature, 4 * n);
            raster.read_into(p, regions);
            if (p.curvature) q.enqueueUnmapMemObject(curvature, p.curvature);
            q.enqueueUnmapMemObject(depth, p.depth);
            q.enqueueUnmapMemObject(normal, p.normal);
            q.enqueueUnmapMemObject(tangent, p.tangent);
            q.enqueueUnmapMemObject(uv, p.uv);
            q.enqueueUnmapMemObject(ids, p.material);
            q.enqueueUnmapMemObject(density, p.density);
        };
        move_planes(*m.raster, m.depth, m.normal, m.tangent, m.uv, m.ids, m.density, m.curvature);
        if (forward) {
            forward_uv.resize(n);
            forward_fetches.resize(n);
            const std::vector<float> off = m.raster->read_offset();
            for (size_t k = 0; k < n; ++k) {
                forward_uv[k] = {{off[4 * k], off[4 * k + 1]}};
                t_gl[k] = off[4 * k + 2];
                forward_fetches[k] = static_cast<std::uint32_t>(off[4 * k + 3]);
            }
            q.enqueueWriteBuffer(m.targets.uv, CL_FALSE, 0, n * sizeof(cl_float2),
                                 forward_uv.data());
            q.enqueueWriteBuffer(m.targets.depth, CL_FALSE, 0, n * sizeof(float), t_gl.data());
        }
        q.finish();
        t.to_device = ms_since(t0);

        t0 = Clock::now();
        EngineGBuffer g;
        g.width = w;
        g.height = h;
        g.camera = gl_camera;
        g.depth.buffer = m.depth;
        g.normal.buffer = m.normal;
        g.tangent.buffer = m.tangent;
        g.uv.buffer = m.uv;
        g.light = m.light;
        if (m.triplanar)
            m.reconstruct->enqueue(g, m.dg, m.frame->triplanar_table(), *m.triplanar);
        else
            m.reconstruct->enqueue(g, m.dg);
        q.finish();
        if (forward && m.triplanar) {
            // The fragment shader traced each axis's projection; the shading takes them in the
            // order of the projections the reconstruct pass gave each pixel.
            std::vector<cl_float4> blend(n);
            q.enqueueReadBuffer(m.triplanar->blend, CL_TRUE, 0, n * sizeof(cl_float4),
                                blend.data());
            const std::vector<float> yz = m.raster->read_offset_yz();
            std::vector<cl_float2> second(n), third(n);
            for (size_t k = 0; k < n; ++k) {
                if (!(blend[k].s[0] >= 0.0f)) continue;
                const cl_float2 axis_uv[3] = {
                    forward_uv[k], {{yz[4 * k], yz[4 * k + 1]}}, {{yz[4 * k + 2], yz[4 * k + 3]}}};
                // x = 2 c + w1, c = p0 + 6 where the second is on the axis of p0's B
                // (kernels/common/triplanar.cl).
                const int c = static_cast<int>(std::floor(0.5f * blend[k].s[0]));
                const int a0 = (c % 6) >> 1, at = a0 == 0 ? 2 : 0, ab = a0 == 1 ? 2 : 1;
                const bool b_first = c >= 6;
                forward_uv[k] = axis_uv[a0];
                second[k] = axis_uv[b_first ? ab : at];
                third[k] = axis_uv[b_first ? at : ab];
            }
            q.enqueueWriteBuffer(m.targets.uv, CL_FALSE, 0, n * sizeof(cl_float2),
                                 forward_uv.data());
            q.enqueueWriteBuffer(m.triplanar->second_targets.uv, CL_FALSE, 0, n * sizeof(cl_float2),
                                 second.data());
            q.enqueueWriteBuffer(m.triplanar->third_targets.uv, CL_TRUE, 0, n * sizeof(cl_float2),
                                 third.data());
        }
        t.reconstruct = ms_since(t0);

        if (!forward) {
            t0 = Clock::now();
            if (behind) {
                // The first layer, then the second drawn, read and traced only where the first
                // left its pixels for what lies behind (its times go to those passes' columns);
                // set_layers's `whole` draws, reads and reconstructs all of it.
                m.frame->enqueue(m.dg, m.targets);
                q.enqueueReadBuffer(m.targets.flags, CL_TRUE, 0, n * sizeof(cl_uint), flags.data());
                const double first_offset = ms_since(t0);
                const auto regions = needed_behind(flags, w, h, needed);
                const bool whole = m.whole_behind;
                if (!needed.empty() || whole) {
                    auto t1 = Clock::now();
                    behind->raster->draw_behind(m.view, *m.raster, run.curved,
                                                whole ? nullptr : &needed);
                    t.gbuffer += ms_since(t1);
                    t1 = Clock::now();
                    move_planes(*behind->raster, behind->depth, behind->normal, behind->tangent,
                                behind->uv, behind->ids, behind->density, behind->curvature,
                                whole ? nullptr : &regions);
                    q.finish();
                    t.to_device += ms_since(t1);
                    t1 = Clock::now();
                    EngineGBuffer g2 = g;
                    g2.depth.buffer = behind->depth;
                    g2.normal.buffer = behind->normal;
                    g2.tangent.buffer = behind->tangent;
                    g2.uv.buffer = behind->uv;
                    // One launch a band (a launch costs more than the columns between runs).
                    for (const PixelRegion& r : whole ? std::vector<PixelRegion>() : regions) {
                        if (!g2.regions.empty() && g2.regions.back().y == r.y)
                            g2.regions.back().width = r.x + r.width - g2.regions.back().x;
                        else
                            g2.regions.push_back(r);
                    }
                    m.reconstruct->enqueue(g2, behind->dg);
                    q.finish();
                    t.reconstruct += ms_since(t1);
                    t1 = Clock::now();
                    m.frame->enqueue_behind(m.dg, m.targets,
                                            LayerBehind{behind->dg, behind->targets});
                    // The depth offset's planes: the window depth and uv density of the surface
                    // shown.
                    m.frame->take_behind(m.targets.flags, behind->depth, m.depth, n, 1);
                    m.frame->take_behind(m.targets.flags, behind->density, m.density, n, 1);
                    q.finish();
                    t.offset += ms_since(t1);
                }
                t.offset += first_offset;
                t0 = Clock::now();
            } else if (m.triplanar) {
                m.frame->enqueue(m.dg, m.targets, *m.triplanar);
            } else {
                m.frame->enqueue(m.dg, m.targets);
            }
            q.finish();
            t.offset += ms_since(t0);
            kernel.push_back(m.frame->kernel_ms());
        }

        // The pixel depth offset, from the depth, t and the uv density already on the device:
        // before the shading, whose shadow test takes the depth it writes.
        t0 = Clock::now();
        m.depth_offset->enqueue(q, m.depth_params, m.depth, m.targets.depth, m.density,
                                m.depth_after);
        q.finish();
        t.depth_offset = ms_since(t0);

        if (shadows) {
            t0 = Clock::now();
            shadows->test->enqueue(q, shadows->params,
                                   shadows->settings.displaced ? m.depth_after : m.depth,
                                   shadow_map, shadows->mask);
            q.finish();
            t.shadow_mask = ms_since(t0);
        }

        t0 = Clock::now();
        const cl::Event shaded = m.frame->shade(
            m.targets.uv, forward ? cl::Buffer() : m.targets.flags, m.dg, m.shading, m.rgba,
            shadows ? shadows->mask : cl::Buffer(), shadows ? shadows->visibility : cl::Buffer(),
            m.triplanar ? &*m.triplanar : nullptr);
        q.finish();
        t.shade = ms_since(t0);
        if (rt.profiling()) shade_kernel.push_back(event_ms(shaded));

        // What GL takes back: the colour and the depth, from the mapped buffers.
        t0 = Clock::now();
        {
            const auto* color = static_cast<const float*>(
                q.enqueueMapBuffer(m.rgba, CL_TRUE, CL_MAP_READ, 0, n * sizeof(cl_float4)));
            const auto* after = static_cast<const float*>(
                q.enqueueMapBuffer(m.depth_after, CL_TRUE, CL_MAP_READ, 0, n * sizeof(float)));
            m.raster->write_results(color, after);
            q.enqueueUnmapMemObject(m.rgba, const_cast<float*>(color));
            q.enqueueUnmapMemObject(m.depth_after, const_cast<float*>(after));
            q.finish();
        }
        t.to_gl = ms_since(t0);
        t.total = ms_since(start);
        if (rep > 0) times.push_back(t);  // the first frame warms up
    }

    // The last frame's outputs, rows top first: read again outside the timed frames, after the
    // same draw with the uv derivatives and the curvature kept (the G-buffer file's).
    m.raster->draw(m.view, forward ? &m.forward : nullptr, prepass, true, true, run.curved);
    planes = m.raster->read(false);
    for (size_t k = 0; k < n; ++k) ids[k] = planes.material[2 * k];
    run.material = ids;
    if (behind) q.enqueueReadBuffer(m.ids, CL_TRUE, 0, n * sizeof(float), run.material.data());
    run.material = flip_rows(run.material, w, h, 1);
    run.color.resize(n);
    q.enqueueReadBuffer(m.rgba, CL_TRUE, 0, n * sizeof(cl_float4), run.color.data());
    if (!forward) q.enqueueReadBuffer(m.targets.depth, CL_TRUE, 0, n * sizeof(float), t_gl.data());
    OffsetResult& out = run.offset;
    out.width = w;
    out.height = h;
    out.depth = t_gl;
    if (forward) {
        out.uv = std::move(forward_uv);
        out.fetches = std::move(forward_fetches);
        out.flags.assign(n, 0u);
        for (size_t k = 0; k < n; ++k)
            if (std::isnan(planes.uv[2 * k])) out.flags[k] = OM_FLAG_EMPTY;
    } else {
        out.uv.resize(n);
        out.fetches.resize(n);
        out.flags.resize(n);
        q.enqueueReadBuffer(m.targets.uv, CL_FALSE, 0, n * sizeof(cl_float2), out.uv.data());
        q.enqueueReadBuffer(m.targets.fetches, CL_FALSE, 0, n * sizeof(cl_uint),
                            out.fetches.data());
        q.enqueueReadBuffer(m.targets.flags, CL_TRUE, 0, n * sizeof(cl_uint), out.flags.data());
    }
    flip_result(out);
    for (std::uint32_t f : out.flags) {
        run.behind_pixels += (f & OM_FLAG_BEHIND) != 0;
        run.missed_pixels += behind && (f & OM_FLAGS_SEE_BEHIND);
    }
    if (m.triplanar) {
        std::vector<cl_float4> blend(n);
        q.enqueueReadBuffer(m.triplanar->blend, CL_TRUE, 0, n * sizeof(cl_float4), blend.data());
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
    run.color = flip_rows(run.color, w, h, 1);
    run.depth_after = flip_rows(m.raster->depth_after(), w, h, 1);
    if (shadows) {
        run.shadow_mask.resize(n);
        run.light_visibility.resize(n);
        q.enqueueReadBuffer(shadows->mask, CL_TRUE, 0, n * sizeof(float), run.shadow_mask.data());
        q.enqueueReadBuffer(shadows->visibility, CL_TRUE, 0, n * sizeof(float),
                            run.light_visibility.data());
        run.shadow_mask = flip_rows(run.shadow_mask, w, h, 1);
        run.light_visibility = flip_rows(run.light_visibility, w, h, 1);
    }
    run.shaded_fragments =
        m.raster->count_fragments(m.view, forward ? &m.forward : nullptr, prepass, run.curved);

    engine_.width = w;
    engine_.height = h;
    engine_.camera = gl_camera;
    engine_.camera.first_row = FirstRow::Top;
    engine_.frame = FrameForm::NormalTangent;
    engine_.light = m.light;
    engine_.depth = flip_rows(planes.depth, w, h, 1);
    engine_.normal = flip_rows(planes.normal, w, h, 4);
    engine_.tangent = flip_rows(planes.tangent, w, h, 4);
    engine_.uv = flip_rows(planes.uv, w, h, 2);
    engine_.material = flip_rows(ids, w, h, 1);
    // Per pixel right and per row down (rows now top first: GL's dFdy flips sign).
    engine_.uv_derivatives = flip_rows(m.raster->read_uv_derivatives(), w, h, 4);
    for (size_t k = 0; k < n; ++k) {
        engine_.uv_derivatives[4 * k + 2] *= -1.0f;
        engine_.uv_derivatives[4 * k + 3] *= -1.0f;
    }
    const std::vector<float> curvature = flip_rows(m.raster->read_curvature(), w, h, 4);
    engine_.curvature.resize(3 * n);
    engine_.uv_stretch.resize(n);
    for (size_t k = 0; k < n; ++k) {
        std::copy_n(&curvature[4 * k], 3, &engine_.curvature[3 * k]);
        engine_.uv_stretch[k] = curvature[4 * k + 3];
    }
    auto med = [&](double PassTimes::*field) {
        std::vector<double> v;
        for (const PassTimes& t : times) v.push_back(t.*field);
        return median(v);
    };
    for (double PassTimes::*f :
         {&PassTimes::gbuffer, &PassTimes::to_device, &PassTimes::reconstruct, &PassTimes::offset,
          &PassTimes::shade, &PassTimes::to_gl, &PassTimes::depth_offset, &PassTimes::shadow_mask,
          &PassTimes::total})
        run.ms.*f = med(f);
    run.offset_kernel_ms = median(kernel);
    // Depth, normal, tangent, uv, material id and uv density (forward: and the offset plane;
    // deferred with curvature: and the curvature); the colour and the depth after the offset.
    run.to_device_bytes = n * sizeof(float) *
                          (1 + 4 + 4 + 2 + 1 + 1 + (forward || run.curved ? 4 : 0)) *
                          (behind ? 2 : 1);
    run.to_gl_bytes = n * sizeof(float) * (4 + 1);
    run.shade_kernel_ms = median(shade_kernel);
    if (!forward) run.offset.kernel_ms = kernel;

    // The explicit G-buffer, as the passes saw it (rows top first).
    explicit_.resize(w, h, m.dg.light(), false);
    q.enqueueReadBuffer(m.dg.uv, CL_TRUE, 0, n * sizeof(cl_float2), explicit_.uv.data());
    q.enqueueReadBuffer(m.dg.view, CL_TRUE, 0, n * sizeof(cl_float4), explicit_.view.data());
    if (m.dg.light())
        q.enqueueReadBuffer(m.dg.light, CL_TRUE, 0, n * sizeof(cl_float4), explicit_.light.data());
    explicit_.uv = flip_rows(explicit_.uv, w, h, 1);
    explicit_.view = flip_rows(explicit_.view, w, h, 1);
    explicit_.light = flip_rows(explicit_.light, w, h, 1);
    explicit_.material = run.material;
    return run;
}

GeometryFrame FrameRenderer::render_geometry(const Scene& scene, int repeats) {
    Impl& m = *impl_;
    m.gl->make_current();
    Raster raster(scene, m.width, m.height);
    std::vector<double> times;
    for (int k = 0; k <= repeats; ++k) {
        const auto t0 = Clock::now();
        raster.draw(m.view, nullptr, false);  // ends in glFinish
        if (k > 0) times.push_back(ms_since(t0));
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

#include "exr.hpp"

namespace offsetmap::renderer {
std::vector<float> flip_row_order(const std::vector<float>& in, int width, int height, int c) {
    return flip_rows(in, width, height, c);
}
void write_depth_exr(const std::string& path, int width, int height,
                     const std::vector<float>& depth) {
    write_float_exr(path, "depth", width, height, {"depth"}, depth, {{"offsetmap:depth", "gl"}});
}
}  // namespace offsetmap::renderer
