// The shade pass: Blinn-Phong with the relief's normals and self-shadows at uv'.
#include "offsetmap/shade_pass.hpp"

#include <cmath>

#include "launch.hpp"
#include "offsetmap/registry.hpp"
#include "shade_params.hpp"

namespace offsetmap {

DeviceImage upload(Runtime& rt, const Image4& image) {
    if (image.width <= 0 || image.height <= 0 ||
        image.texels.size() != static_cast<size_t>(image.width) * image.height)
        throw Error("image is empty or its texels do not match its size");
    DeviceImage d;
    d.width = image.width;
    d.height = image.height;
    d.texels =
        device_buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                      image.texels.size() * sizeof(cl_float4), "the image", image.texels.data());
    return d;
}

OmShadeParams shade_params(const PassSettings& settings, const ShadeSettings& s, int map_w,
                           int map_h, const DeviceImage* albedo) {
    OmShadeParams p{};
    p.hf_width = map_w;
    p.hf_height = map_h;
    p.address_mode = static_cast<om_int>(settings.address);
    p.light_x = s.light[0];
    p.light_y = s.light[1];
    p.light_z = s.light[2];
    p.ambient = s.ambient;
    p.diffuse = s.diffuse;
    p.specular = s.specular;
    if (!(s.shininess >= 0.0f && s.shininess <= 1.0e4f))
        throw Error("shininess must be in [0, 10000], got " + std::to_string(s.shininess));
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
    const GrazingRule rule = grazing_rule(settings, map_w, map_h);
    p.min_vz = rule.min_vz;
    p.grazing = static_cast<om_int>(settings.grazing);
    p.has_albedo = albedo ? 1 : 0;
    p.albedo_width = albedo ? albedo->width : 0;
    p.albedo_height = albedo ? albedo->height : 0;
    return p;
}

void check_shade_buffers(const cl::Context& context, const cl::Buffer& uv, const cl::Buffer& flags,
                         const cl::Buffer& out_rgba, size_t n) {
    check_buffer(context, uv, {"the shade pass's uv input", "float2", sizeof(cl_float2), n});
    check_buffer(context, flags,
                 {"the shade pass's flags input", "uint", sizeof(cl_uint), n, false, true});
    check_buffer(context, out_rgba,
                 {"the shade pass's colour output", "float4", sizeof(cl_float4), n, true});
}

void check_shadow_buffers(const cl::Context& context, const cl::Buffer& mask,
                          const cl::Buffer& visibility, size_t n) {
    check_buffer(context, mask,
                 {"the shade pass's shadow mask", "float", sizeof(float), n, false, true});
    check_buffer(context, visibility,
                 {"the shade pass's visibility output", "float", sizeof(float), n, true, true});
}

cl::Kernel shade_kernel(Runtime& rt, const std::string& name) {
    const bool materials = name == "om_shade_materials";
    return rt.kernel(
        rt.program(shade_program_files(), shade_program_defines(rt.lanes(), materials)), name);
}

cl::NDRange shade_grid(int lanes, int width, int height) {
    return padded(static_cast<size_t>(om_image_blocks(width, height, lanes)));
}

ShadePass::ShadePass(std::shared_ptr<Runtime> runtime) : runtime_(std::move(runtime)) {
    lanes_ = runtime_->lanes();
    kernel_ = shade_kernel(*runtime_, "om_shade");
}

cl::Event ShadePass::enqueue(const DeviceGBuffer& g, const DeviceHeightField& f,
                             const ShadeInputs& in, const PassSettings& settings,
                             const ShadeSettings& s, const ShadeTargets& out,
                             const std::vector<cl::Event>& wait, const cl::CommandQueue& queue) {
    const cl::Buffer &uv = in.uv, &flags = in.flags, &out_rgba = out.rgba;
    const DeviceImage* albedo = in.albedo;
    const cl::Context& context = runtime_->context();
    const cl::CommandQueue& q = pass_queue(*runtime_, queue);
    check_gbuffer(context, g);
    check_field(context, f, true);
    const size_t n = g.pixels();
    check_shade_buffers(context, uv, flags, out_rgba, n);
    check_shadow_buffers(context, in.shadow_mask, out.visibility, n);
    if (albedo) {
        if (albedo->width <= 0 || albedo->height <= 0)
            throw Error("the albedo image's size is " + std::to_string(albedo->width) + "x" +
                        std::to_string(albedo->height));
        check_buffer(context, albedo->texels,
                     {"the albedo image's texels", "float4", sizeof(cl_float4),
                      static_cast<size_t>(albedo->width) * albedo->height});
    }
    if (runtime_->lanes() != lanes_) {
        lanes_ = runtime_->lanes();
        kernel_ = shade_kernel(*runtime_, "om_shade");
    }
    OmShadeParams p = shade_params(settings, s, f.width, f.height, albedo);
    p.gb_width = g.width;
    p.gb_height = g.height;
    p.has_light = g.light() ? 1 : 0;
    kernel_.setArg(0, p);
    kernel_.setArg(1, uv);
    set_optional(kernel_, 2, flags);
    kernel_.setArg(3, g.view);
    set_optional(kernel_, 4, g.light);
    kernel_.setArg(5, f.normals);
    kernel_.setArg(6, f.heights);
    set_optional(kernel_, 7, albedo ? albedo->texels : cl::Buffer());
    set_optional(kernel_, 8, in.shadow_mask);
    kernel_.setArg(9, out_rgba);
    set_optional(kernel_, 10, out.visibility);
    cl::Event event;
    try {
        std::vector<cl::Event> deps = wait;  // and the field's upload or last change
        const std::vector<cl::Event> ready = field_ready(f);
        deps.insert(deps.end(), ready.begin(), ready.end());
        q.enqueueNDRangeKernel(kernel_, cl::NullRange, shade_grid(lanes_, g.width, g.height),
                               cl::NDRange(kLocalSize), &deps, &event);
    } catch (const cl::Error& e) {
        throw Error(std::string("cannot run the shading pass: ") + describe_cl_error(e.err()));
    }
    return event;
}

}  // namespace offsetmap
