// The reconstruct pass: the engine's G-buffer (depth, camera, frame, uv) to the explicit one.
#include <cmath>

#include "launch.hpp"
#include "offsetmap/engine_gbuffer.hpp"

namespace offsetmap {
namespace {

constexpr size_t kTile = 8;  // work-group side: fixed, so PoCL compiles one work-group function

std::string image_type_name(cl_channel_type type) {
    switch (type) {
        case CL_FLOAT:
            return "float";
        case CL_HALF_FLOAT:
            return "half";
        case CL_UNORM_INT8:
            return "unorm8";
        case CL_UNORM_INT16:
            return "unorm16";
        case CL_SNORM_INT8:
            return "snorm8";
        case CL_SNORM_INT16:
            return "snorm16";
        default:
            return "";
    }
}

// Channels read_imagef returns in .x, .xy, ... for each order an input may use (it returns
// (r, g, b, a) whatever order the memory holds them in).
int leading_channels(cl_channel_order order) {
    switch (order) {
        case CL_R:
            return 1;
        case CL_RG:
            return 2;
        case CL_RGBA:
        case CL_BGRA:
        case CL_ARGB:
            return 4;
        default:
            return 0;
    }
}

// Checks one input: bound exactly once, of this context, `values` per pixel for the whole frame.
void check_input(const cl::Context& context, const Input& in, const std::string& name, int values,
                 int width, int height) {
    const std::string what = "the engine G-buffer's " + name;
    if (in.buffer() && in.image()) throw Error(what + " has both a buffer and an image; bind one");
    if (!in.bound()) throw Error(what + " is not bound (no buffer and no image)");
    const size_t pixels = static_cast<size_t>(width) * height;
    if (in.buffer()) {
        const std::string element = std::to_string(values) + " value(s) of " +
                                    std::to_string(storage_bytes(in.storage)) + " byte(s)";
        const std::string buffer_name = what + " buffer";
        check_buffer(
            context, in.buffer,
            {buffer_name.c_str(), element.c_str(), values * storage_bytes(in.storage), pixels});
        return;
    }
    cl_mem_object_type type = 0;
    cl_context owner = nullptr;
    cl_image_format format{};
    size_t w = 0, h = 0;
    const cl_mem m = in.image();
    if (clGetMemObjectInfo(m, CL_MEM_TYPE, sizeof type, &type, nullptr) != CL_SUCCESS ||
        clGetMemObjectInfo(m, CL_MEM_CONTEXT, sizeof owner, &owner, nullptr) != CL_SUCCESS)
        throw Error(what + " image is not a valid OpenCL memory object");
    if (type != CL_MEM_OBJECT_IMAGE2D) throw Error(what + " image is not a 2D image");
    if (owner != context()) throw Error(what + " image belongs to another OpenCL context");
    clGetImageInfo(m, CL_IMAGE_FORMAT, sizeof format, &format, nullptr);
    clGetImageInfo(m, CL_IMAGE_WIDTH, sizeof w, &w, nullptr);
    clGetImageInfo(m, CL_IMAGE_HEIGHT, sizeof h, &h, nullptr);
    if (w != static_cast<size_t>(width) || h != static_cast<size_t>(height))
        throw Error(what + " image is " + std::to_string(w) + "x" + std::to_string(h) +
                    "; the G-buffer is " + std::to_string(width) + "x" + std::to_string(height));
    if (image_type_name(format.image_channel_data_type).empty())
        throw Error(what + " image's channel type (0x" + [&] {
            char hex[16];
            std::snprintf(hex, sizeof hex, "%X", format.image_channel_data_type);
            return std::string(hex);
        }() + ") is not read as float; use float, half, unorm8/16 or snorm8/16");
    if (leading_channels(format.image_channel_order) < values)
        throw Error(what + " image needs " + std::to_string(values) +
                    " channel(s) (order CL_R, CL_RG, CL_RGBA, CL_BGRA or CL_ARGB; the first " +
                    std::to_string(values) + " read)");
}

bool finite(const float* v, size_t n) {
    for (size_t k = 0; k < n; ++k)
        if (!std::isfinite(v[k])) return false;
    return true;
}

}  // namespace

size_t storage_bytes(Storage s) {
    switch (s) {
        case Storage::Float:
            return 4;
        case Storage::Half:
        case Storage::Snorm16:
        case Storage::Unorm16:
            return 2;
        case Storage::Unorm8:
            return 1;
    }
    throw Error("unknown storage " + std::to_string(static_cast<int>(s)));
}

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

cl::Kernel& ReconstructPass::kernel(const EngineGBuffer& in) {
    const bool quaternion = in.frame == FrameForm::Quaternion;
    std::string defines;
    if (in.depth.image()) defines += "#define OM_IMAGE_DEPTH 1\n";
    if (in.normal.image()) defines += "#define OM_IMAGE_FRAME 1\n";
    if (!quaternion && in.tangent.image()) defines += "#define OM_IMAGE_TANGENT 1\n";
    if (in.uv.image()) defines += "#define OM_IMAGE_UV 1\n";
    auto it = kernels_.find(defines);
    if (it == kernels_.end()) {
        cl::Program program = runtime_->program(
            {"common/lanes.h", "common/storage.cl", "gbuffer/reconstruct.cl"}, defines);
        it = kernels_.emplace(defines, cl::Kernel(program, "om_reconstruct")).first;
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

cl::Event ReconstructPass::launch(const EngineGBuffer& in, const DeviceGBuffer& out,
                                  const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                                  bool no_pixels) {
    const cl::Context& context = runtime_->context();
    check_gbuffer_size(in.width, in.height, "the engine G-buffer");
    const bool quaternion = in.frame == FrameForm::Quaternion;
    if (!quaternion && in.frame != FrameForm::NormalTangent)
        throw Error("the engine G-buffer's frame form " +
                    std::to_string(static_cast<int>(in.frame)) + " is not one of the two forms");
    check_input(context, in.depth, "depth", 1, in.width, in.height);
    check_input(context, in.normal, quaternion ? "quaternion" : "normal", 4, in.width, in.height);
    if (!quaternion) check_input(context, in.tangent, "tangent", 4, in.width, in.height);
    check_input(context, in.uv, "uv", 2, in.width, in.height);
    const EngineCamera& cam = in.camera;
    if (!finite(cam.inverse_view_projection.data(), 16) || !finite(cam.eye.data(), 3))
        throw Error("the engine camera's inverse view-projection and eye must be finite");
    if (cam.depth != DepthConvention::GL && cam.depth != DepthConvention::ZeroToOne &&
        cam.depth != DepthConvention::Reversed)
        throw Error("the engine camera's depth convention " +
                    std::to_string(static_cast<int>(cam.depth)) +
                    " is not GL, zero-one or reversed");
    if (cam.first_row != FirstRow::Top && cam.first_row != FirstRow::Bottom)
        throw Error("the engine camera's first row must be Top or Bottom");
    const EngineLight& light = in.light;
    const bool lit = light.kind != LightKind::None;
    std::array<float, 3> lv = light.vector;
    if (lit) {
        if (!finite(lv.data(), 3)) throw Error("the engine light's vector must be finite");
        if (light.kind == LightKind::Directional) {
            const double len =
                std::sqrt(double(lv[0]) * lv[0] + double(lv[1]) * lv[1] + double(lv[2]) * lv[2]);
            if (!(len > 0.0)) throw Error("the engine light's direction is the zero vector");
            for (float& c : lv) c = static_cast<float>(c / len);
        } else if (light.kind != LightKind::Point) {
            throw Error("the engine light's kind " + std::to_string(static_cast<int>(light.kind)) +
                        " is not None, Directional or Point");
        }
    }
    if (out.width != in.width || out.height != in.height)
        throw Error("the reconstructed G-buffer is " + std::to_string(out.width) + "x" +
                    std::to_string(out.height) + "; the engine G-buffer is " +
                    std::to_string(in.width) + "x" + std::to_string(in.height));
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

    OmReconstructParams p{};
    p.width = no_pixels ? 0 : in.width;
    p.height = no_pixels ? 0 : in.height;
    std::copy(cam.inverse_view_projection.begin(), cam.inverse_view_projection.end(),
              p.inv_view_proj);
    std::copy(cam.eye.begin(), cam.eye.end(), p.eye);
    p.depth_convention = static_cast<om_int>(cam.depth);
    p.row0_ndc_y = static_cast<float>(static_cast<int>(cam.first_row));
    p.frame = static_cast<om_int>(in.frame);
    p.light = static_cast<om_int>(light.kind);
    std::copy(lv.begin(), lv.end(), p.light_vec);
    p.depth_storage = static_cast<om_int>(in.depth.storage);
    p.frame_storage = static_cast<om_int>(in.normal.storage);
    p.tangent_storage = static_cast<om_int>(in.tangent.storage);
    p.uv_storage = static_cast<om_int>(in.uv.storage);

    cl::Kernel& k = kernel(in);
    k.setArg(0, p);
    auto bind = [&](cl_uint index, const Input& input) {
        if (input.image())
            k.setArg(index, input.image);
        else
            set_optional(k, index, input.buffer);
    };
    bind(1, in.depth);
    bind(2, in.normal);
    bind(3, quaternion ? Input() : in.tangent);
    bind(4, in.uv);
    k.setArg(5, out.uv);
    k.setArg(6, out.view);
    set_optional(k, 7, lit ? out.light : cl::Buffer());
    const cl::CommandQueue& q = pass_queue(*runtime_, queue);
    const cl::NDRange global = no_pixels ? cl::NDRange(kTile, kTile)
                                         : cl::NDRange((in.width + kTile - 1) / kTile * kTile,
                                                       (in.height + kTile - 1) / kTile * kTile);
    cl::Event done;
    q.enqueueNDRangeKernel(k, cl::NullRange, global, cl::NDRange(kTile, kTile), &wait, &done);
    return done;
}

}  // namespace offsetmap
