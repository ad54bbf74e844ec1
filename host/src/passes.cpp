#include "offsetmap/passes.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <sstream>

#include "offsetmap/error.hpp"
#include "om_shared.h"

namespace offsetmap {
namespace {

// PoCL compiles a kernel once per local size: keep it fixed and pad the global size.
constexpr size_t kLocalSize = 64;

cl::NDRange padded(size_t n) { return cl::NDRange((n + kLocalSize - 1) / kLocalSize * kLocalSize); }

// Every offset program: the sampling layer, the ray, the shared searches, one method, the entry.
std::vector<std::string> offset_program_files(const MethodInfo& m) {
    return {"common/lanes.h",       "common/sampling.cl",  "common/ray.cl",
            "common/patch.cl", "methods/" + m.kernel_file, "offset.cl"};
}

void set_optional(cl::Kernel& k, cl_uint index, const cl::Buffer& b) {
    if (b())
        k.setArg(index, b);
    else
        k.setArg(index, sizeof(cl_mem), nullptr);  // a NULL global pointer in the kernel
}

void check_field(const DeviceHeightField& f) {
    if (f.width <= 0 || f.height <= 0 || !f.heights())
        throw Error("the height field has not been uploaded");
}

void check_gbuffer(const DeviceGBuffer& g) {
    if (g.width <= 0 || g.height <= 0 || !g.uv() || !g.view())
        throw Error("the G-buffer has no uv or view buffer");
    if (g.pixels() > static_cast<size_t>(INT_MAX))
        throw Error("the G-buffer is too large (" + std::to_string(g.pixels()) + " pixels)");
}

void build_mips(Runtime& rt, DeviceHeightField& f) {
    if (f.mip_levels < 2) return;
    cl::Kernel k(rt.program({"prep/mips.cl"}), "om_mip_level");
    int w = f.width, h = f.height, offset = 0;
    for (int level = 1; level < f.mip_levels; ++level) {
        int cw = std::max(1, w / 2), ch = std::max(1, h / 2), child = offset + w * h;
        k.setArg(0, f.heights);
        k.setArg(1, offset);
        k.setArg(2, w);
        k.setArg(3, h);
        k.setArg(4, child);
        k.setArg(5, cw);
        k.setArg(6, ch);
        rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(cw, ch));
        offset = child;
        w = cw;
        h = ch;
    }
    rt.queue().finish();
}

}  // namespace

OmOffsetParams offset_params(const PassSettings& s, int pixels, int hf_w, int hf_h) {
    OmOffsetParams p{};
    p.pixel_count = pixels;
    p.hf_width = hf_w;
    p.hf_height = hf_h;
    p.address_mode = static_cast<om_int>(s.address);
    p.scale = s.scale;
    p.ref_plane = s.reference_plane;
    const GrazingRule g = grazing_rule(s, hf_w, hf_h);
    p.min_vz = g.min_vz;
    p.grazing = static_cast<om_int>(s.grazing);
    p.max_cells = g.max_cells;
    p.tile_mask = s.out_of_tile_mask ? 1 : 0;
    p.mip_levels = 1;
    p.lod_threshold = s.lod.threshold;
    p.lod_fade = s.lod.fade;
    p.lod_min_detail = s.lod.min_detail;
    p.lod_footprint = s.lod.footprint ? 1 : 0;
    p.lod_fade_lo = s.lod.fade_texels_lo;
    p.lod_fade_hi = s.lod.fade_texels_hi;
    return p;
}

int mip_level_count(int width, int height) {
    int levels = 1;
    while ((width > 1 || height > 1) && levels < OM_MAX_MIP_LEVELS) {
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
        ++levels;
    }
    return levels;
}

size_t mip_pyramid_floats(int width, int height, int levels) {
    size_t total = 0;
    for (int k = 0; k < levels; ++k) {
        total += static_cast<size_t>(width) * height;
        width = std::max(1, width / 2);
        height = std::max(1, height / 2);
    }
    return total;
}

void validate(const PassSettings& s) {
    auto range = [](const char* name, float v, float lo, float hi) {
        if (!(v >= lo && v <= hi)) {
            std::ostringstream m;
            m << name << " must be in [" << lo << ", " << hi << "], got " << v;
            throw Error(m.str());
        }
    };
    range("scale", s.scale, 0.0f, 1.0f);
    range("reference plane", s.reference_plane, 0.0f, 1.0f);
    range("minimum elevation (degrees)", s.min_elevation_deg, 0.1f, 89.0f);
    range("maximum offset (texels)", s.max_offset_texels, 1.0f, 1.0e6f);
    if (s.lod.enabled) {
        range("LOD threshold", s.lod.threshold, 0.5f, 16.0f);
        if (!(s.lod.fade > 0.0f && s.lod.fade <= s.lod.threshold))
            throw Error("LOD fade must be in (0, threshold], got " + std::to_string(s.lod.fade));
        if (!(s.lod.fade_texels_lo >= 0.0f && s.lod.fade_texels_hi > s.lod.fade_texels_lo))
            throw Error("LOD fade texel range must satisfy 0 <= low < high, got [" +
                        std::to_string(s.lod.fade_texels_lo) + ", " +
                        std::to_string(s.lod.fade_texels_hi) + "]");
        if (!(s.lod.min_detail > 0.0f && s.lod.min_detail <= 1.0f))
            throw Error("LOD minimum detail must be in (0, 1], got " +
                        std::to_string(s.lod.min_detail));
    }
}

DeviceHeightField upload(Runtime& rt, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map) {
    validate_height_map(map, "height map");
    validate(settings);
    DeviceHeightField f;
    f.width = map.width;
    f.height = map.height;
    const size_t n = map.h.size();
    f.mip_levels = mip_level_count(map.width, map.height);
    f.heights = cl::Buffer(rt.context(), CL_MEM_READ_WRITE,
                           mip_pyramid_floats(map.width, map.height, f.mip_levels) * sizeof(float));
    rt.queue().enqueueWriteBuffer(f.heights, CL_TRUE, 0, n * sizeof(float), map.h.data());
    build_mips(rt, f);
    if (normal_map) {
        if (normal_map->width != map.width || normal_map->height != map.height)
            throw Error("normal map is " + std::to_string(normal_map->width) + "x" +
                        std::to_string(normal_map->height) + " but the height map is " +
                        std::to_string(map.width) + "x" + std::to_string(map.height));
        f.normals =
            cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float4),
                       const_cast<cl_float4*>(normal_map->texels.data()));
        return f;
    }
    f.normals = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4));
    cl::Kernel k(rt.program({"common/lanes.h", "common/sampling.cl", "prep/normals.cl"}),
                 "om_normals");
    k.setArg(0, offset_params(settings, 0, map.width, map.height));
    k.setArg(1, f.heights);
    k.setArg(2, f.normals);
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(map.width, map.height));
    rt.queue().finish();
    return f;
}

OffsetPass::OffsetPass(std::shared_ptr<Runtime> runtime, const std::string& method,
                       const std::map<std::string, std::string>& params)
    : runtime_(std::move(runtime)), method_(&find_method(method)) {
    params_ = resolve_params(*method_, params);
    lanes_ = runtime_->lanes();
    // Compile now (the tools' usual outputs), so a method's build errors surface here.
    kernel(false, true, true, true, runtime_->images());
}

cl::Kernel& OffsetPass::kernel(bool lod, bool depth, bool fetches, bool flags, bool images) {
    // One program per combination actually used: each drops the branches it does not need.
    std::string defines = lanes_ > 1 ? "#define OM_LANES " + std::to_string(lanes_) + "\n" : "";
    if (images) defines += "#define OM_IMAGES\n";
    if (lod) defines += "#define OM_LOD\n";
    if (depth) defines += "#define OM_OUT_DEPTH\n";
    if (fetches) defines += "#define OM_OUT_FETCHES\n";
    if (flags) defines += "#define OM_OUT_FLAGS\n";
    auto it = kernels_.find(defines);
    if (it == kernels_.end())
        it = kernels_
                 .emplace(defines,
                          cl::Kernel(runtime_->program(offset_program_files(*method_), defines),
                                     "om_offset"))
                 .first;
    return it->second;
}

void OffsetPass::prepare(const DeviceHeightField& f, const PassSettings& settings) {
    if (method_->precompute == Precompute::None) return;
    check_field(f);
    std::ostringstream key;
    key << f.heights() << ' ' << f.width << 'x' << f.height << ' ' << settings.scale << ' '
        << static_cast<int>(settings.address);
    for (float p : params_) key << ' ' << p;
    if (key.str() == aux_key_) return;
    aux_key_.clear();
    auto start = std::chrono::steady_clock::now();
    double kernel_ms = 0.0;
    try {
        switch (method_->precompute) {
            case Precompute::DistanceMap:
                kernel_ms = build_distance_map(f, settings);
                break;
            case Precompute::MaxMip:
                kernel_ms = build_max_pyramid(f, settings);
                break;
            case Precompute::ConeMap:
                kernel_ms = build_cone_map(f, settings);
                break;
            case Precompute::None:
                break;
        }
    } catch (const cl::Error& e) {
        throw Error("cannot build the precomputed data of '" + method_->name + "' (" +
                    std::to_string(precomputed_.bytes) + " bytes): " + describe_cl_error(e.err()));
    }
    precomputed_.build_ms =
        runtime_->profiling()
            ? kernel_ms
            : std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                  .count();
    aux_key_ = key.str();
}

double OffsetPass::build_distance_map(const DeviceHeightField& f, const PassSettings& settings) {
    auto& rt = *runtime_;
    OmOffsetParams p = offset_params(settings, 0, f.width, f.height);
    const int res = static_cast<int>(params_[0]), layers = static_cast<int>(params_[1]);
    const size_t voxels = static_cast<size_t>(res) * res * layers;
    precomputed_.bytes = voxels * sizeof(float);
    cl::Program program =
        rt.program({"common/lanes.h", "common/sampling.cl", "prep/distance.cl"});
    cl::Buffer colmax(rt.context(), CL_MEM_READ_WRITE,
                      static_cast<size_t>(res) * res * sizeof(float));
    aux_ = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, voxels * sizeof(float));
    cl::Kernel kc(program, "om_column_max");
    kc.setArg(0, p);
    kc.setArg(1, f.heights);
    kc.setArg(2, res);
    kc.setArg(3, colmax);
    cl::Kernel kd(program, "om_distance_map");
    kd.setArg(0, p);
    kd.setArg(1, colmax);
    kd.setArg(2, res);
    kd.setArg(3, layers);
    kd.setArg(4, aux_);
    cl::Event e1, e2;
    rt.queue().enqueueNDRangeKernel(kc, cl::NullRange, cl::NDRange(res, res), cl::NullRange,
                                    nullptr, &e1);
    rt.queue().enqueueNDRangeKernel(kd, cl::NullRange, cl::NDRange(res, res, layers), cl::NullRange,
                                    nullptr, &e2);
    e2.wait();
    return rt.profiling() ? event_ms(e1) + event_ms(e2) : 0.0;
}

double OffsetPass::build_max_pyramid(const DeviceHeightField& f, const PassSettings& settings) {
    auto& rt = *runtime_;
    // Levels while both sizes stay even, in wrap mode only (as om_maxmip_levels in the kernel).
    int levels = 0;
    if (settings.address == AddressMode::Wrap)
        while (levels < 15 && ((f.width >> levels) & 1) == 0 && ((f.height >> levels) & 1) == 0)
            ++levels;
    size_t floats = 0;
    for (int k = 1; k <= levels; ++k) floats += static_cast<size_t>(f.width >> k) * (f.height >> k);
    precomputed_.bytes = floats * sizeof(float);
    aux_ = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, std::max<size_t>(floats, 1) * sizeof(float));
    if (levels == 0) return 0.0;
    cl::Program program =
        rt.program({"common/lanes.h", "common/sampling.cl", "prep/maxmip.cl"});
    OmOffsetParams p = offset_params(settings, 0, f.width, f.height);
    double ms = 0.0;
    cl::Kernel first(program, "om_maxmip_first");
    first.setArg(0, p);
    first.setArg(1, f.heights);
    first.setArg(2, aux_);
    first.setArg(3, f.width >> 1);
    first.setArg(4, f.height >> 1);
    cl::Event e;
    rt.queue().enqueueNDRangeKernel(first, cl::NullRange, cl::NDRange(f.width >> 1, f.height >> 1),
                                    cl::NullRange, nullptr, &e);
    e.wait();
    if (rt.profiling()) ms += event_ms(e);
    cl::Kernel next(program, "om_maxmip_next");
    int offset = 0;
    for (int k = 2; k <= levels; ++k) {
        int pw = f.width >> (k - 1), ph = f.height >> (k - 1), cw = f.width >> k,
            ch = f.height >> k;
        next.setArg(0, aux_);
        next.setArg(1, offset);
        next.setArg(2, pw);
        next.setArg(3, offset + pw * ph);
        next.setArg(4, cw);
        next.setArg(5, ch);
        rt.queue().enqueueNDRangeKernel(next, cl::NullRange, cl::NDRange(cw, ch), cl::NullRange,
                                        nullptr, &e);
        e.wait();
        if (rt.profiling()) ms += event_ms(e);
        offset += pw * ph;
    }
    return ms;
}

double OffsetPass::build_cone_map(const DeviceHeightField& f, const PassSettings& settings) {
    auto& rt = *runtime_;
    constexpr int kBlock = 8;  // OM_CONE_BLOCK in prep/cone.cl
    const int bw = (f.width + kBlock - 1) / kBlock, bh = (f.height + kBlock - 1) / kBlock;
    const size_t cells = static_cast<size_t>(f.width) * f.height;
    precomputed_.bytes = 2 * cells * sizeof(float);
    cl::Program program = rt.program({"common/lanes.h", "common/sampling.cl", "prep/cone.cl"});
    OmOffsetParams p = offset_params(settings, 0, f.width, f.height);
    cl::Buffer blocks(rt.context(), CL_MEM_READ_WRITE,
                      static_cast<size_t>(bw) * bh * sizeof(float));
    aux_ = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, 2 * cells * sizeof(float));
    cl::Kernel kb(program, "om_cone_blocks");
    kb.setArg(0, p);
    kb.setArg(1, f.heights);
    kb.setArg(2, bw);
    kb.setArg(3, bh);
    kb.setArg(4, blocks);
    cl::Event e1, e2;
    rt.queue().enqueueNDRangeKernel(kb, cl::NullRange, cl::NDRange(bw, bh), cl::NullRange, nullptr,
                                    &e1);
    std::vector<float> block_max(static_cast<size_t>(bw) * bh);
    rt.queue().enqueueReadBuffer(blocks, CL_TRUE, 0, block_max.size() * sizeof(float),
                                 block_max.data());
    const float global_max = *std::max_element(block_max.begin(), block_max.end());
    // Wrapped block indices name the same cells only when blocks tile the map.
    const int blocks_valid =
        settings.address == AddressMode::Clamp || (f.width % kBlock == 0 && f.height % kBlock == 0);
    cl::Kernel kc(program, "om_cone_map");
    kc.setArg(0, p);
    kc.setArg(1, f.heights);
    kc.setArg(2, blocks);
    kc.setArg(3, bw);
    kc.setArg(4, bh);
    kc.setArg(5, blocks_valid);
    kc.setArg(6, global_max);
    kc.setArg(7, params_[0]);
    kc.setArg(8, aux_);
    rt.queue().enqueueNDRangeKernel(kc, cl::NullRange, cl::NDRange(f.width, f.height),
                                    cl::NullRange, nullptr, &e2);
    e2.wait();
    return rt.profiling() ? event_ms(e1) + event_ms(e2) : 0.0;
}

const cl::Image1DBuffer& OffsetPass::heights_image(const DeviceHeightField& f) {
    if (image_of_ != f.heights()) {
        const size_t floats = f.heights.getInfo<CL_MEM_SIZE>() / sizeof(float);
        heights_image_ = floats <= runtime_->device().getInfo<CL_DEVICE_IMAGE_MAX_BUFFER_SIZE>()
                             ? cl::Image1DBuffer(runtime_->context(), CL_MEM_READ_ONLY,
                                                 cl::ImageFormat(CL_R, CL_FLOAT), floats, f.heights)
                             : cl::Image1DBuffer();
        image_of_ = f.heights();
    }
    return heights_image_;
}

cl::Buffer OffsetPass::footprint(const DeviceGBuffer& g, const DeviceHeightField& f,
                                 const std::vector<cl::Event>& wait, std::vector<cl::Event>& deps) {
    auto& rt = *runtime_;
    if (footprint_pixels_ != g.pixels()) {
        footprint_ = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, g.pixels() * sizeof(float));
        footprint_pixels_ = g.pixels();
    }
    if (!footprint_kernel_())
        footprint_kernel_ = cl::Kernel(rt.program({"prep/footprint.cl"}), "om_footprint_lod");
    cl::Kernel& k = footprint_kernel_;
    k.setArg(0, g.uv);
    k.setArg(1, g.width);
    k.setArg(2, g.height);
    k.setArg(3, static_cast<float>(f.width));
    k.setArg(4, static_cast<float>(f.height));
    k.setArg(5, footprint_);
    cl::Event e;
    rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(g.width, g.height), cl::NullRange,
                                    &wait, &e);
    deps = {e};
    return footprint_;
}

cl::Event OffsetPass::enqueue(const DeviceGBuffer& g, const DeviceHeightField& f,
                              const PassSettings& settings, const OffsetTargets& t,
                              const std::vector<cl::Event>& wait) {
    validate(settings);
    check_gbuffer(g);
    check_field(f);
    if (!t.uv()) throw Error("the offset pass needs a uv output buffer");
    prepare(f, settings);
    OmOffsetParams p = offset_params(settings, static_cast<int>(g.pixels()), f.width, f.height);
    p.mip_levels = f.mip_levels;
    std::copy(params_.begin(), params_.end(), p.p);
    // The image path where the runtime wants it and the pyramid fits an image1d_buffer.
    const bool images = runtime_->images() && heights_image(f)() != nullptr;
    cl::Kernel& k = kernel(settings.lod.enabled, t.depth() != nullptr, t.fetches() != nullptr,
                           t.flags() != nullptr, images);
    k.setArg(0, p);
    k.setArg(1, g.uv);
    k.setArg(2, g.view);
    k.setArg(3, f.heights);
    set_optional(k, 4, aux_);
    k.setArg(6, t.uv);
    set_optional(k, 7, t.depth);
    set_optional(k, 8, t.fetches);
    set_optional(k, 9, t.flags);
    if (images) k.setArg(10, heights_image(f));
    cl::Event event;
    try {
        std::vector<cl::Event> deps = wait;
        cl::Buffer lod;
        if (settings.lod.enabled) {
            lod = g.lod() ? g.lod : footprint(g, f, wait, deps);
        }
        set_optional(k, 5, lod);
        runtime_->queue().enqueueNDRangeKernel(k, cl::NullRange,
                                               padded((g.pixels() + lanes_ - 1) / lanes_),
                                               cl::NDRange(kLocalSize), &deps, &event);
    } catch (const cl::Error& e) {
        throw Error("cannot run the '" + method_->name +
                    "' offset pass: " + describe_cl_error(e.err()));
    }
    return event;
}

DeviceImage upload(Runtime& rt, const Image4& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.texels.size() != static_cast<size_t>(image.width) * image.height)
        throw Error("image is empty or its texels do not match its size");
    DeviceImage d;
    d.width = image.width;
    d.height = image.height;
    d.texels = cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                          image.texels.size() * sizeof(cl_float4),
                          const_cast<cl_float4*>(image.texels.data()));
    return d;
}

ShadePass::ShadePass(std::shared_ptr<Runtime> runtime) : runtime_(std::move(runtime)) {
    kernel_ = cl::Kernel(
        runtime_->program({"common/lanes.h", "common/sampling.cl", "shade.cl"}), "om_shade");
}

cl::Event ShadePass::enqueue(const cl::Buffer& uv, const cl::Buffer& flags, const DeviceGBuffer& g,
                             const DeviceHeightField& f, const DeviceImage* albedo,
                             const PassSettings& settings, const ShadeSettings& s,
                             const cl::Buffer& out_rgba, const std::vector<cl::Event>& wait) {
    check_gbuffer(g);
    check_field(f);
    if (!f.normals()) throw Error("the height field has no normals");
    OmShadeParams p{};
    p.pixel_count = static_cast<int>(g.pixels());
    p.hf_width = f.width;
    p.hf_height = f.height;
    p.address_mode = static_cast<om_int>(settings.address);
    p.light_x = s.light[0];
    p.light_y = s.light[1];
    p.light_z = s.light[2];
    p.has_light = g.light() ? 1 : 0;
    p.ambient = s.ambient;
    p.diffuse = s.diffuse;
    p.specular = s.specular;
    p.shininess = s.shininess;
    if (s.shadow_steps < 1 || s.shadow_steps > 256)
        throw Error("shadow steps must be in [1, 256], got " + std::to_string(s.shadow_steps));
    if (!(s.light_size_deg > 0.0f && s.light_size_deg <= 90.0f))
        throw Error("light size must be in (0, 90] degrees, got " +
                    std::to_string(s.light_size_deg));
    p.shadow_mode = static_cast<om_int>(s.shadow);
    p.shadow_steps = s.shadow_steps;
    p.light_size = static_cast<float>(s.light_size_deg * M_PI / 180.0);
    p.scale = settings.scale;
    p.ref_plane = settings.reference_plane;
    const GrazingRule rule = grazing_rule(settings, f.width, f.height);
    p.min_vz = rule.min_vz;
    p.grazing = static_cast<om_int>(settings.grazing);
    p.has_albedo = albedo ? 1 : 0;
    p.albedo_width = albedo ? albedo->width : 0;
    p.albedo_height = albedo ? albedo->height : 0;
    kernel_.setArg(0, p);
    kernel_.setArg(1, uv);
    set_optional(kernel_, 2, flags);
    kernel_.setArg(3, g.view);
    set_optional(kernel_, 4, g.light);
    kernel_.setArg(5, f.normals);
    kernel_.setArg(6, f.heights);
    set_optional(kernel_, 7, albedo ? albedo->texels : cl::Buffer());
    kernel_.setArg(8, out_rgba);
    cl::Event event;
    try {
        runtime_->queue().enqueueNDRangeKernel(kernel_, cl::NullRange, padded(g.pixels()),
                                               cl::NDRange(kLocalSize), &wait, &event);
    } catch (const cl::Error& e) {
        throw Error(std::string("cannot run the shading pass: ") + describe_cl_error(e.err()));
    }
    return event;
}

}  // namespace offsetmap
