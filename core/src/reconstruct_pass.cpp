// The reconstruct pass: the engine's G-buffer (depth, camera, frame, uv) to the explicit one.
#include <cmath>

#include "launch.hpp"
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/registry.hpp"
#include "pixel_grid.hpp"

namespace offsetmap {
namespace {

// The work-group (work-items of OM_LANES pixels each): fixed, so PoCL compiles one work-group
// function.
constexpr size_t kGroupX = 8, kGroupY = 8;

// The planes a triplanar split reads and writes, and the engine planes it needs.
void check_triplanar(const EngineGBuffer& in, const DeviceGBuffer& out, const TriplanarTable& table,
                     const TriplanarPlanes& t) {
    if (!table.of_id() || table.id_limit < 1)
        throw Error("the triplanar table is empty (MaterialFrame::triplanar_table)");
    if (!in.depth.bound())
        throw Error(table.name +
                    " is triplanar: it needs the engine G-buffer's depth (its world "
                    "position)");
    if (!in.normal.bound())
        throw Error(table.name + " is triplanar: it needs the engine G-buffer's " +
                    (in.frame == FrameForm::Quaternion ? "quaternion" : "normal") +
                    " (its weights and its frames)");
    if (!out.material())
        throw Error("a triplanar split needs the reconstructed G-buffer's material ids");
    for (const DeviceGBuffer* g : {&t.second, &t.third})
        if (g->width != out.width || g->height != out.height || !g->material())
            throw Error("the triplanar planes are not the G-buffer's size (allocate_triplanar)");
}

// A spot light's axis (finite, not zero) and cone (0 <= inner <= outer < pi / 2).
void check_spot(const EngineLight& light) {
    const std::array<float, 3>& a = light.axis;
    if (!finite(a.data(), 3) ||
        !(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2] > 0.0))
        throw Error("the engine spot light's axis must be finite and not the zero vector");
    const double inner = light.cone_inner, outer = light.cone_outer;
    if (!(inner >= 0.0 && inner <= outer && outer < M_PI / 2))
        throw Error(
            "the engine spot light's cone must have 0 <= inner <= outer < pi / 2 radians, "
            "got inner " +
            std::to_string(inner) + ", outer " + std::to_string(outer));
}

// The light's parameters, checked: a directional light's direction normalised, a spot's axis and
// its cone's cosines (Error naming what is wrong).
void light_params(const EngineLight& light, OmReconstructParams& p) {
    if (light.kind == LightKind::None) return;
    std::array<float, 3> lv = light.vector;
    if (!finite(lv.data(), 3)) throw Error("the engine light's vector must be finite");
    if (light.kind == LightKind::Directional) {
        const double len =
            std::sqrt(double(lv[0]) * lv[0] + double(lv[1]) * lv[1] + double(lv[2]) * lv[2]);
        if (!(len > 0.0)) throw Error("the engine light's direction is the zero vector");
        for (float& c : lv) c = static_cast<float>(c / len);
    } else if (light.kind == LightKind::Spot) {
        check_spot(light);
        const std::array<float, 3>& a = light.axis;
        const double len =
            std::sqrt(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]);
        for (int c = 0; c < 3; ++c) p.light_axis[c] = static_cast<float>(a[c] / len);
        p.cone_cos_outer = static_cast<float>(std::cos(double(light.cone_outer)));
        p.cone_cos_inner = static_cast<float>(std::cos(double(light.cone_inner)));
    } else if (light.kind != LightKind::Point) {
        throw Error("the engine light's kind " + std::to_string(static_cast<int>(light.kind)) +
                    " is not None, Directional, Point or Spot");
    }
    std::copy(lv.begin(), lv.end(), p.light_vec);
}

}  // namespace

DeviceGBuffer allocate_gbuffer(Runtime& rt, int width, int height, bool light, bool lod) {
    check_gbuffer_size(width, height, "the G-buffer");
    DeviceGBuffer g;
    g.width = width;
    g.height = height;
    const size_t n = g.pixels();
    const std::string what =
        "the " + std::to_string(width) + "x" + std::to_string(height) + " G-buffer's ";
    g.uv = device_buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2), what + "uv");
    g.view = device_buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4), what + "view");
    if (light)
        g.light =
            device_buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4), what + "light");
    if (lod)
        g.lod = device_buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(float), what + "lod");
    return g;
}

ReconstructPass::ReconstructPass(std::shared_ptr<Runtime> runtime) : runtime_(std::move(runtime)) {}

std::vector<std::string> reconstruct_program_files() {
    return {"common/storage.cl", "common/triplanar.cl", "common/unproject.cl",
            "gbuffer/reconstruct.cl"};
}

std::string reconstruct_program_defines(int lanes, const std::array<int, 4>& inputs,
                                        bool quaternion, LightKind light, bool triplanar) {
    // Per input: an image, or a buffer of a storage the decoding is specialised for.
    std::string defines = lanes_define(lanes);
    const char* names[] = {"DEPTH", "FRAME", "TANGENT", "UV"};
    for (int k = 0; k < 4; ++k) {
        if (quaternion && k == 2) continue;
        if (inputs[k] == kImageInput)
            defines += std::string("#define OM_IMAGE_") + names[k] + " 1\n";
        else if (inputs[k] != kNoInput)
            defines += std::string("#define OM_STORAGE_") + names[k] + " " +
                       std::to_string(inputs[k]) + "\n";
    }
    if (quaternion) defines += "#define OM_QUATERNION_FRAME\n";
    if (light != LightKind::None) defines += "#define OM_LIT\n";
    if (light == LightKind::Point || light == LightKind::Spot)
        defines += "#define OM_POINT_LIGHT\n";
    if (light == LightKind::Spot) defines += "#define OM_SPOT_LIGHT\n";
    if (triplanar) {
        defines += "#define OM_TRIPLANAR\n";
        if (inputs[3] == kNoInput) defines += "#define OM_NO_UV\n";
        if (!quaternion && inputs[2] == kNoInput) defines += "#define OM_NO_TANGENT\n";
    }
    return defines;
}

cl::Kernel& ReconstructPass::kernel(const EngineGBuffer& in, bool triplanar) {
    auto code = [](const Input& i) {
        return i.image() ? kImageInput : i.buffer() ? static_cast<int>(i.storage) : kNoInput;
    };
    const std::string defines = reconstruct_program_defines(
        runtime_->lanes(), {code(in.depth), code(in.normal), code(in.tangent), code(in.uv)},
        in.frame == FrameForm::Quaternion, in.light.kind, triplanar);
    auto it = kernels_.find(defines);
    if (it == kernels_.end()) {
        cl::Program program = runtime_->program(reconstruct_program_files(), defines);
        it = kernels_.emplace(defines, runtime_->kernel(program, "om_reconstruct")).first;
    }
    return it->second;
}

void ReconstructPass::prepare(const EngineGBuffer& in, const DeviceGBuffer& out) {
    launch(in, out, {}, cl::CommandQueue(), true).wait();
}

cl::Event ReconstructPass::enqueue(const EngineGBuffer& in, const DeviceGBuffer& out,
                                   const std::vector<cl::Event>& wait,
                                   const cl::CommandQueue& queue) {
    return launch(in, out, wait, queue, false);
}

cl::Event ReconstructPass::enqueue(const EngineGBuffer& in, const DeviceGBuffer& out,
                                   const TriplanarTable& table, const TriplanarPlanes& planes,
                                   const std::vector<cl::Event>& wait,
                                   const cl::CommandQueue& queue) {
    return launch(in, out, wait, queue, false, &table, &planes);
}

cl::Event ReconstructPass::launch(const EngineGBuffer& in, const DeviceGBuffer& out,
                                  const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                                  bool no_pixels, const TriplanarTable* table,
                                  const TriplanarPlanes* planes) {
    const cl::Context& context = runtime_->context();
    const bool triplanar = table != nullptr;
    if (triplanar) check_triplanar(in, out, *table, *planes);
    check_gbuffer_size(in.width, in.height, "the engine G-buffer");
    const bool quaternion = in.frame == FrameForm::Quaternion;
    if (!quaternion && in.frame != FrameForm::NormalTangent)
        throw Error("the engine G-buffer's frame form " +
                    std::to_string(static_cast<int>(in.frame)) + " is not one of the two forms");
    check_input(context, in.depth, "the engine G-buffer's depth", 1, in.width, in.height);
    check_input(context, in.normal,
                std::string("the engine G-buffer's ") + (quaternion ? "quaternion" : "normal"), 4,
                in.width, in.height);
    // A triplanar frame may leave uv and the tangent out: its triplanar pixels need neither.
    if (!quaternion && !(triplanar && !in.tangent.bound()))
        check_input(context, in.tangent, "the engine G-buffer's tangent", 4, in.width, in.height);
    if (!(triplanar && !in.uv.bound()))
        check_input(context, in.uv, "the engine G-buffer's uv", 2, in.width, in.height);
    const EngineCamera& cam = in.camera;
    const OmPixelGrid grid = pixel_grid(cam, in.width, in.height, "the engine camera");
    const EngineLight& light = in.light;
    const bool lit = light.kind != LightKind::None;
    OmReconstructParams p{};
    light_params(light, p);
    if (out.width != in.width || out.height != in.height)
        throw Error("the reconstructed G-buffer is " + std::to_string(out.width) + "x" +
                    std::to_string(out.height) + "; the engine G-buffer is " +
                    std::to_string(in.width) + "x" + std::to_string(in.height));
    for (size_t r = 0; r < in.regions.size(); ++r) {
        const PixelRegion& g = in.regions[r];
        if (g.x < 0 || g.y < 0 || g.width < 1 || g.height < 1 || g.x > in.width - g.width ||
            g.y > in.height - g.height)
            throw Error("the engine G-buffer's region " + std::to_string(r) + " (" +
                        std::to_string(g.width) + "x" + std::to_string(g.height) + " at " +
                        std::to_string(g.x) + ", " + std::to_string(g.y) + ") is not inside its " +
                        std::to_string(in.width) + "x" + std::to_string(in.height) + " pixels");
    }
    const size_t n = in.pixels();
    check_buffer(context, out.uv,
                 {"the reconstructed G-buffer's uv buffer", "float2", sizeof(cl_float2), n, true});
    check_buffer(
        context, out.view,
        {"the reconstructed G-buffer's view buffer", "float4", sizeof(cl_float4), n, true});
    if (lit)
        check_buffer(
            context, out.light,
            {"the reconstructed G-buffer's light buffer", "float4", sizeof(cl_float4), n, true});

    p.width = no_pixels ? 0 : in.width;
    p.height = no_pixels ? 0 : in.height;
    std::copy(cam.inverse_view_projection.begin(), cam.inverse_view_projection.end(),
              p.inv_view_proj);
    std::copy(cam.eye.begin(), cam.eye.end(), p.eye);
    p.eye_w = cam.orthographic ? 0.0f : 1.0f;
    p.depth_scale = grid.depth_scale;
    p.depth_offset = grid.depth_offset;
    p.far_depth = grid.far_depth;
    p.far_sign = grid.far_sign;
    p.row0_ndc_y = grid.row0_ndc_y;
    const cl::CommandQueue& q = pass_queue(*runtime_, queue);
    // The inputs as the kernel reads them (a copy for the one image form PoCL misreads).
    EngineGBuffer use = in;
    std::vector<cl::Event> deps = wait;
    if (quaternion) use.tangent = Input();  // not read in this form
    for (Input* input : {&use.depth, &use.normal, &use.tangent, &use.uv}) {
        if (!input->bound()) continue;
        cl::Event copied;
        *input = readable_input(*runtime_, *input, in.width, in.height, q, wait, copied);
        if (copied()) deps.push_back(copied);
    }
    cl::Kernel& k = kernel(use, triplanar);
    k.setArg(0, p);
    auto bind = [&](cl_uint index, const Input& input) {
        if (input.image())
            k.setArg(index, input.image);
        else
            set_optional(k, index, input.buffer);
    };
    bind(1, use.depth);
    bind(2, use.normal);
    bind(3, use.tangent);
    bind(4, use.uv);
    k.setArg(5, out.uv);
    k.setArg(6, out.view);
    set_optional(k, 7, lit ? out.light : cl::Buffer());
    if (triplanar) {
        const TriplanarPlanes& t = *planes;
        set_args_from(k, 8, out.material, table->of_id, static_cast<cl_int>(table->id_limit));
        int a = 11;
        for (const DeviceGBuffer* g : {&t.second, &t.third}) {
            set_args_from(k, a, g->uv, g->view, g->material);
            a += 3;
        }
        set_args_from(k, a, t.blend, t.ray_scale);
    }
    const size_t lanes = runtime_->lanes();
    auto round_up = [](size_t v, size_t m) { return (v + m - 1) / m * m; };
    if (no_pixels || in.regions.empty()) {
        const size_t items = (in.width + lanes - 1) / lanes;  // per row
        const cl::NDRange global =
            no_pixels ? cl::NDRange(kGroupX, kGroupY)
                      : cl::NDRange(round_up(items, kGroupX), round_up(in.height, kGroupY));
        cl::Event done;
        q.enqueueNDRangeKernel(k, cl::NullRange, global, cl::NDRange(kGroupX, kGroupY), &deps,
                               &done);
        return done;
    }
    std::vector<cl::Event> launched;
    for (const PixelRegion& r : in.regions) {
        const size_t first = static_cast<size_t>(r.x) / lanes,
                     last = (static_cast<size_t>(r.x) + r.width + lanes - 1) / lanes;
        cl::Event done;
        q.enqueueNDRangeKernel(k, cl::NDRange(first, r.y),
                               cl::NDRange(round_up(last - first, kGroupX),
                                           round_up(static_cast<size_t>(r.height), kGroupY)),
                               cl::NDRange(kGroupX, kGroupY), &deps, &done);
        launched.push_back(done);
    }
    cl::Event done;
    q.enqueueMarkerWithWaitList(&launched, &done);
    return done;
}

}  // namespace offsetmap
