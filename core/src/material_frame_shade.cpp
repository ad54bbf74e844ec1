// The material frame's shading: each pixel with its material's normals, albedo and shadows, in
// one dispatch.
#include <cstring>

#include "launch.hpp"
#include "offsetmap/material_frame.hpp"
#include "shade_params.hpp"

namespace offsetmap {

cl::Event MaterialFrame::shade(const DeviceGBuffer& g, const FrameShadeInputs& in,
                               const ShadeSettings& s, const ShadeTargets& out,
                               const std::vector<cl::Event>& wait,
                               const cl::CommandQueue& queue_given) {
    const cl::Buffer &uv = in.uv, &flags = in.flags, &shadow_mask = in.shadow_mask;
    const cl::Buffer &out_rgba = out.rgba, &out_visibility = out.visibility;
    const TriplanarPlanes* planes = in.triplanar;
    Runtime& rt = *runtime_;
    const cl::Context& context = rt.context();
    const cl::CommandQueue& queue = checked_queue(g, queue_given);
    const size_t n = g.pixels();
    check_shade_buffers(context, uv, flags, out_rgba, n);
    check_shadow_buffers(context, shadow_mask, out_visibility, n);
    if (!planes) refuse_without_projections("shade");
    if (planes && triplanar_table_.any) check_triplanar_planes(context, *planes, g);
    const bool blend = planes && triplanar_table_.any;
    // The frame's parameters (id 0: flat, the checker, no shadows), then each slot's.
    PassSettings flat;
    OmShadeParams frame = shade_params(flat, s, 1, 1, nullptr);
    frame.gb_width = g.width;
    frame.gb_height = g.height;
    if (rt.lanes() != shade_lanes_) {
        shade_lanes_ = rt.lanes();
        shade_ = shade_kernel(rt, "om_shade_materials");
    }
    frame.has_light = g.light() ? 1 : 0;
    frame.shadow_mode = OM_SHADOW_NONE;
    refresh();
    std::vector<cl::Event> deps = wait;
    const std::vector<cl::Event> setup = setup_events();
    deps.insert(deps.end(), setup.begin(), setup.end());
    try {
        if (!shade_written_ || std::memcmp(&shade_settings_, &s, sizeof s) != 0) {
            if (shade_write_()) shade_write_.wait();  // slots_ is its source
            for (size_t k = 0; k < slots_.size(); ++k) {
                const FrameMaterial& m = materials_[k];
                slots_[k].shade = shade_params(m.settings, s, m.field.width, m.field.height,
                                               m.albedo.texels() ? &m.albedo : nullptr);
            }
            queue.enqueueWriteBuffer(shade_table_, CL_FALSE, 0,
                                     slots_.size() * sizeof(OmMaterialSlot), slots_.data(), nullptr,
                                     &shade_write_);
            shade_settings_ = s;
            shade_written_ = true;
        }
        deps.push_back(shade_write_);
        set_args(shade_, frame, shade_table_, slot_of_id_, static_cast<cl_int>(id_limit_),
                 g.material, uv);
        set_optional(shade_, 6, flags);
        shade_.setArg(7, g.view);
        set_optional(shade_, 8, g.light);
        set_args_from(shade_, 9, normals_, heights_);
        set_optional(shade_, 11, albedo_);
        set_optional(shade_, 12, shadow_mask);
        shade_.setArg(13, out_rgba);
        set_optional(shade_, 14, out_visibility);
        set_optional(shade_, 15, blend ? planes->blend : cl::Buffer());
        set_optional(shade_, 16, blend ? planes->second_targets.uv : cl::Buffer());
        set_optional(shade_, 17, blend ? planes->third_targets.uv : cl::Buffer());
        queue.enqueueNDRangeKernel(shade_, cl::NullRange,
                                   shade_grid(shade_lanes_, g.width, g.height),
                                   cl::NDRange(kLocalSize), &deps, &last_shade_);
        return last_shade_;
    } catch (const cl::Error& e) {
        throw Error("cannot shade the material frame: " + describe_cl_error(e.err()));
    }
}

}  // namespace offsetmap
