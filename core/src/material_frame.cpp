// The material frame's table: each material checked, laid out in slots and gathered on the device
// (again where its field changed). Its trace, layer behind, triplanar projections and shading are
// the material_frame_*.cpp beside it.
#include "offsetmap/material_frame.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <sstream>

#include "launch.hpp"
#include "precompute/precompute.hpp"
#include "shade_params.hpp"

namespace offsetmap {

namespace {

std::string label(const FrameMaterial& m) {
    std::string s = "material " + std::to_string(m.id);
    return m.name.empty() ? s : s + " (" + m.name + ")";
}

// Offsets within the gathered buffers start on 64-byte boundaries (16 floats, 4 float4s).
size_t aligned(size_t n, size_t to) { return (n + to - 1) / to * to; }

// Element offset for an int field of the slot table: refuses what an int cannot address.
om_int element_offset(size_t n, const std::string& what) {
    if (n > static_cast<size_t>(INT_MAX))
        throw Error("the material table's " + what + " take more than 2^31 elements");
    return static_cast<om_int>(n);
}

void check_material(const cl::Context& context, const FrameMaterial& m) {
    if (m.id < 1 || m.id > kMaxMaterialId)
        throw Error(label(m) + ": the id must be in [1, " + std::to_string(kMaxMaterialId) +
                    "] (0 is the pixels without relief)");
    try {
        validate(m.settings);
        check_field(context, m.field, true);
    } catch (const Error& e) {
        throw Error(label(m) + ": " + e.what());
    }
    if (m.settings.lod.enabled)
        throw Error(label(m) + ": the LOD system is not available in a material frame");
    validate(m.triplanar, label(m));
    if (m.triplanar.enabled && m.settings.address != AddressMode::Wrap)
        throw Error(label(m) +
                    ": a triplanar projection tiles the world, so it needs wrap addressing");
    if (!m.params.method || m.params.values.size() != m.params.method->params.size())
        throw Error(label(m) + ": its method parameters are not resolved (resolve_params)");
    if (m.albedo.texels() &&
        (m.albedo.width <= 0 || m.albedo.height <= 0 ||
         m.albedo.texels.getInfo<CL_MEM_SIZE>() <
             static_cast<size_t>(m.albedo.width) * m.albedo.height * sizeof(cl_float4)))
        throw Error(label(m) + ": its albedo image's texels do not match its size " +
                    std::to_string(m.albedo.width) + "x" + std::to_string(m.albedo.height));
}

}  // namespace

std::string unknown_material(float id, size_t pixel, int width, size_t count) {
    std::ostringstream text;
    text << "the G-buffer's material id " << id << " at pixel (" << pixel % width << ", "
         << pixel / width << ") has no entry in the material table";
    if (count > 1) text << " (" << count << " pixels have ids without one)";
    return text.str();
}

MaterialFrame::MaterialFrame(std::shared_ptr<Runtime> runtime, std::vector<FrameMaterial> materials,
                             int tile_rows)
    : runtime_(std::move(runtime)), materials_(std::move(materials)), tile_rows_(tile_rows) {
    check_table();
    Layout layout;
    lay_out(layout);
    gather_table(layout);
    build_kernels();
}

void MaterialFrame::check_table() {
    const cl::Context& context = runtime_->context();
    if (materials_.empty()) throw Error("the material table is empty");
    if (materials_.size() > OM_MAX_MATERIALS)
        throw Error("the material table has " + std::to_string(materials_.size()) +
                    " materials; a frame takes at most " + std::to_string(OM_MAX_MATERIALS));
    if (tile_rows_ < 1 || tile_rows_ > 64)
        throw Error("tile rows must be in [1, 64], got " + std::to_string(tile_rows_));
    for (size_t s = 0; s < materials_.size(); ++s) {
        check_material(context, materials_[s]);
        for (size_t r = 0; r < s; ++r)
            if (materials_[r].id == materials_[s].id)
                throw Error("material id " + std::to_string(materials_[s].id) +
                            " appears twice in the table: " + label(materials_[r]) + " and " +
                            label(materials_[s]));
        id_limit_ = std::max(id_limit_, materials_[s].id + 1);
    }
}

void MaterialFrame::lay_out(Layout& l) {
    // Slots, methods and where each material's data goes in the gathered buffers.
    const size_t n_slots = materials_.size();
    slots_.assign(n_slots, OmMaterialSlot{});
    gathered_.assign(n_slots, Gathered{});
    l.built.resize(n_slots);
    for (size_t s = 0; s < n_slots; ++s) {
        const FrameMaterial& m = materials_[s];
        const MethodInfo* info = m.params.method;
        auto it = std::find_if(methods_.begin(), methods_.end(),
                               [&](const Method& x) { return x.params.method == info; });
        if (it == methods_.end()) it = methods_.insert(methods_.end(), Method{m.params, {}, {}});
        slots_[s].method = static_cast<int>(it - methods_.begin());
        const DeviceHeightField& f = m.field;
        Gathered& at = gathered_[s];
        at.heights = l.heights;
        l.heights += aligned(height_buffer_bytes(f) / sizeof(float), 16);
        at.normals = l.normals;
        l.normals += aligned(static_cast<size_t>(f.width) * f.height, 4);
        at.albedo = l.albedo;
        if (m.albedo.texels())
            l.albedo += aligned(static_cast<size_t>(m.albedo.width) * m.albedo.height, 4);
        at.version = f.version ? f.version->state() : FieldVersion::State{};
        if (info->precompute) l.built[s] = build_precomputed(s);
        OmMaterialSlot& slot = slots_[s];
        slot.P = offset_params(m.settings, f.width, f.height);
        slot.P.mip_levels = f.mip_levels;
        slot.P.packed_heights = packed_heights_offset(f);
        std::copy(m.params.values.begin(), m.params.values.end(), slot.P.p);
        slot.id = m.id;
        slot.heights_offset = element_offset(at.heights, "reliefs");
        slot.normals_offset = element_offset(at.normals, "normals");
        slot.albedo_offset = element_offset(at.albedo, "albedo images");
    }
    // Each method's precomputed data: its materials' in slot order.
    l.aux.assign(methods_.size(), 0);
    for (size_t s = 0; s < n_slots; ++s) {
        if (!l.built[s].data()) continue;
        size_t& total = l.aux[slots_[s].method];
        gathered_[s].aux = total;
        gathered_[s].aux_bytes = l.built[s].data.getInfo<CL_MEM_SIZE>();
        slots_[s].aux_offset = element_offset(total, "precomputed data");
        total += aligned(gathered_[s].aux_bytes / sizeof(float), 16);
    }
}

void MaterialFrame::gather_table(const Layout& l) {
    Runtime& rt = *runtime_;
    const cl::Context& context = rt.context();
    const size_t n_slots = materials_.size();
    // Gather: each material's relief, normals, albedo and precomputed data written into the frame's
    // buffers by the gather kernel, after each field's upload and each build. Each buffer is made
    // with its contents (zeros, the padding between materials), not left for the gather alone:
    // Oclgrind 21.10 hands a released buffer's record of initialised bytes, of that buffer's size,
    // to the next buffer made, and a kernel's stores past that size go unrecorded.
    gather_ = rt.kernel(rt.program({"frame/gather.cl"}), "om_gather_words");
    try {
        const std::vector<float> zeros(
            std::max({l.heights, 4 * l.normals, 4 * l.albedo,
                      l.aux.empty() ? size_t(0) : *std::max_element(l.aux.begin(), l.aux.end())}));
        auto zeroed = [&](size_t floats, const std::string& what) {
            return device_buffer(context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                 floats * sizeof(float), what, zeros.data());
        };
        heights_ = zeroed(l.heights, "the material table's reliefs");
        normals_ = zeroed(4 * l.normals, "the material table's normals");
        if (l.albedo > 0) albedo_ = zeroed(4 * l.albedo, "the material table's albedo images");
        for (size_t k = 0; k < methods_.size(); ++k)
            if (l.aux[k] > 0)
                methods_[k].aux = zeroed(
                    l.aux[k], "the precomputed data of '" + methods_[k].params.method->name + "'");
        for (size_t s = 0; s < n_slots; ++s) {
            const FrameMaterial& m = materials_[s];
            gather_field(s, l.built[s], {});
            if (m.albedo.texels())
                gathered_[s].albedo_copied =
                    gather(m.albedo.texels, albedo_, 4 * gathered_[s].albedo,
                           4 * static_cast<size_t>(m.albedo.width) * m.albedo.height, {});
        }
        write_tables();
        // Submitted now: every frame waits on these copies, maybe from another queue, and OpenCL
        // lets a queue hold back what was never flushed (rusticl does, and a frame on a second
        // queue then waited for ever).
        rt.queue().flush();
    } catch (const cl::Error& e) {
        throw Error("cannot gather the material table on the device: " +
                    describe_cl_error(e.err()));
    }
}

void MaterialFrame::write_tables() {
    const cl::Context& context = runtime_->context();
    const size_t n_slots = materials_.size();
    std::vector<cl_float4> triplanar(id_limit_, cl_float4{{0, 0, 0, 0}});
    for (const FrameMaterial& m : materials_) {
        if (!m.triplanar.enabled) continue;
        const Triplanar& t = m.triplanar;
        triplanar[m.id] = cl_float4{{t.world_scale, t.sharpness, t.cutoff, 1.0f}};
        if (!triplanar_table_.any) triplanar_table_.name = label(m);
        triplanar_table_.any = true;
    }
    triplanar_table_.of_id = device_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                           triplanar.size() * sizeof(cl_float4),
                                           "the material table's projections", triplanar.data());
    triplanar_table_.id_limit = id_limit_;
    std::vector<cl_int> slot_of_id(id_limit_, -1), method_of_slot(n_slots);
    for (size_t s = 0; s < n_slots; ++s) {
        slot_of_id[materials_[s].id] = static_cast<int>(s);
        method_of_slot[s] = slots_[s].method;
    }
    auto table = [&](const void* data, size_t bytes, const char* what) {
        return device_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, what, data);
    };
    slot_table_ =
        table(slots_.data(), slots_.size() * sizeof(OmMaterialSlot), "the material table's slots");
    shade_table_ = table(slots_.data(), slots_.size() * sizeof(OmMaterialSlot),
                         "the material table's shading slots");
    slot_of_id_ =
        table(slot_of_id.data(), slot_of_id.size() * sizeof(cl_int), "the material table's ids");
    method_of_slot_ = table(method_of_slot.data(), method_of_slot.size() * sizeof(cl_int),
                            "the material table's methods");
}

void MaterialFrame::build_kernels() {
    Runtime& rt = *runtime_;
    classify_ = rt.kernel(rt.program(classify_program_files()), "om_classify");
    const cl::Program behind = rt.program(behind_program_files());
    behind_mask_ = rt.kernel(behind, "om_behind_mask");
    behind_choose_ = rt.kernel(behind, "om_behind_choose");
    behind_take_ = rt.kernel(behind, "om_behind_take");
    triplanar_merge_ = rt.kernel(rt.program({"frame/triplanar.cl"}), "om_triplanar_merge");
    shade_lanes_ = rt.lanes();
    shade_ = shade_kernel(rt, "om_shade_materials");
    // Compile the usual variant now, so a method's build errors surface here.
    for (Method& m : methods_) tile_kernel(m, variant_writing_every_output());
}

PrecomputeSpec::Built MaterialFrame::build_precomputed(size_t s) {
    const FrameMaterial& m = materials_[s];
    try {
        return m.params.method->precompute->build(*runtime_, m.field, m.settings, m.params);
    } catch (const cl::Error& e) {
        throw Error(label(m) + ": cannot build the precomputed data of '" + m.params.method->name +
                    "': " + describe_cl_error(e.err()));
    }
}

void MaterialFrame::gather_field(size_t s, const PrecomputeSpec::Built& built,
                                 const std::vector<cl::Event>& after) {
    const DeviceHeightField& f = materials_[s].field;
    Gathered& at = gathered_[s];
    // After the field's version read with the generation: a copy of a later change is gathered
    // again at the next check, never an earlier one kept.
    std::vector<cl::Event> ready = after;
    if (f.ready()) ready.push_back(f.ready);
    if (at.version.written()) ready.push_back(at.version.written);
    const size_t texels = static_cast<size_t>(f.width) * f.height;
    at.copies = {
        gather(f.heights, heights_, at.heights, height_buffer_bytes(f) / sizeof(float), ready),
        gather(f.normals, normals_, 4 * at.normals, 4 * texels, ready)};
    if (built.data()) {
        std::vector<cl::Event> done = after;
        done.insert(done.end(), built.events.begin(), built.events.end());
        at.copies.push_back(gather(built.data, methods_[slots_[s].method].aux, at.aux,
                                   at.aux_bytes / sizeof(float), done));
    }
}

cl::Event MaterialFrame::gather(const cl::Buffer& src, const cl::Buffer& dst, size_t at,
                                size_t words, const std::vector<cl::Event>& after) {
    if (at + words > UINT_MAX) throw Error("the material table's buffers are too large");
    set_args(gather_, src, static_cast<cl_uint>(words), dst, static_cast<cl_uint>(at));
    cl::Event done;
    runtime_->queue().enqueueNDRangeKernel(gather_, cl::NullRange, padded(words),
                                           cl::NDRange(kLocalSize), &after, &done);
    return done;
}

std::vector<cl::Event> MaterialFrame::setup_events() const {
    std::vector<cl::Event> out;
    for (const Gathered& at : gathered_) {
        out.insert(out.end(), at.copies.begin(), at.copies.end());
        if (at.albedo_copied()) out.push_back(at.albedo_copied);
    }
    return out;
}

void MaterialFrame::refresh() {
    std::vector<cl::Event> reads;  // what still reads the gathered buffers
    for (const Dispatch& d : dispatches_) reads.push_back(d.event);
    if (last_shade_()) reads.push_back(last_shade_);
    bool changed = false;
    try {
        for (size_t s = 0; s < gathered_.size(); ++s) {
            const DeviceHeightField& f = materials_[s].field;
            if (!f.version) continue;
            const FieldVersion::State now = f.version->state();
            if (now.generation == gathered_[s].version.generation) continue;
            gathered_[s].version = now;
            const PrecomputeSpec::Built built = materials_[s].params.method->precompute
                                                    ? build_precomputed(s)
                                                    : PrecomputeSpec::Built{};
            gather_field(s, built, reads);
            changed = true;
        }
        if (changed) runtime_->queue().flush();  // as the constructor's copies
    } catch (const cl::Error& e) {
        throw Error("cannot gather the material table's changed fields on the device: " +
                    describe_cl_error(e.err()));
    }
}

}  // namespace offsetmap
