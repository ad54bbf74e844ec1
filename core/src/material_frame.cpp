// The material frame: the table gathered on the device, tile classification, one dispatch per
// method over its tiles, shading per material.
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
    Runtime& rt = *runtime_;
    const cl::Context& context = rt.context();
    const cl::CommandQueue& queue = rt.queue();
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

    // Slots, methods and where each material's data goes in the gathered buffers.
    const size_t n_slots = materials_.size();
    slots_.assign(n_slots, OmMaterialSlot{});
    gathered_.assign(n_slots, Gathered{});
    size_t heights_total = 0, normals_total = 0, albedo_total = 0;
    std::vector<PrecomputeSpec::Built> built(n_slots);
    for (size_t s = 0; s < n_slots; ++s) {
        const FrameMaterial& m = materials_[s];
        const MethodInfo* info = m.params.method;
        auto it = std::find_if(methods_.begin(), methods_.end(),
                               [&](const Method& x) { return x.params.method == info; });
        if (it == methods_.end()) it = methods_.insert(methods_.end(), Method{m.params, {}, {}});
        slots_[s].method = static_cast<int>(it - methods_.begin());
        const DeviceHeightField& f = m.field;
        Gathered& at = gathered_[s];
        at.heights = heights_total;
        heights_total += aligned(height_buffer_bytes(f) / sizeof(float), 16);
        at.normals = normals_total;
        normals_total += aligned(static_cast<size_t>(f.width) * f.height, 4);
        at.albedo = albedo_total;
        if (m.albedo.texels())
            albedo_total += aligned(static_cast<size_t>(m.albedo.width) * m.albedo.height, 4);
        at.version = f.version ? f.version->state() : FieldVersion::State{};
        if (info->precompute) built[s] = build_precomputed(s);
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
    std::vector<size_t> aux_total(methods_.size(), 0);
    for (size_t s = 0; s < n_slots; ++s) {
        if (!built[s].data()) continue;
        size_t& total = aux_total[slots_[s].method];
        gathered_[s].aux = total;
        gathered_[s].aux_bytes = built[s].data.getInfo<CL_MEM_SIZE>();
        slots_[s].aux_offset = element_offset(total, "precomputed data");
        total += aligned(gathered_[s].aux_bytes / sizeof(float), 16);
    }

    // Gather: each material's relief, normals, albedo and precomputed data written into the frame's
    // buffers by the gather kernel, after each field's upload and each build. Each buffer is made
    // with its contents (zeros, the padding between materials), not left for the gather alone:
    // Oclgrind 21.10 hands a released buffer's record of initialised bytes, of that buffer's size,
    // to the next buffer made, and a kernel's stores past that size go unrecorded.
    gather_ = rt.kernel(rt.program({"frame/gather.cl"}), "om_gather_words");
    try {
        const std::vector<float> zeros(
            std::max({heights_total, 4 * normals_total, 4 * albedo_total,
                      aux_total.empty() ? size_t(0)
                                        : *std::max_element(aux_total.begin(), aux_total.end())}));
        auto zeroed = [&](size_t floats, const std::string& what) {
            return device_buffer(context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                 floats * sizeof(float), what, zeros.data());
        };
        heights_ = zeroed(heights_total, "the material table's reliefs");
        normals_ = zeroed(4 * normals_total, "the material table's normals");
        if (albedo_total > 0) albedo_ = zeroed(4 * albedo_total, "the material table's albedo images");
        for (size_t k = 0; k < methods_.size(); ++k)
            if (aux_total[k] > 0)
                methods_[k].aux = zeroed(
                    aux_total[k], "the precomputed data of '" + methods_[k].params.method->name + "'");
        for (size_t s = 0; s < n_slots; ++s) {
            const FrameMaterial& m = materials_[s];
            gather_field(s, built[s], {});
            if (m.albedo.texels())
                gathered_[s].albedo_copied =
                    gather(m.albedo.texels, albedo_, 4 * gathered_[s].albedo,
                           4 * static_cast<size_t>(m.albedo.width) * m.albedo.height, {});
        }
        std::vector<cl_float4> triplanar(id_limit_, cl_float4{{0, 0, 0, 0}});
        for (const FrameMaterial& m : materials_) {
            if (!m.triplanar.enabled) continue;
            const Triplanar& t = m.triplanar;
            triplanar[m.id] = cl_float4{{t.world_scale, t.sharpness, t.cutoff, 1.0f}};
            if (!triplanar_table_.any) triplanar_table_.name = label(m);
            triplanar_table_.any = true;
        }
        triplanar_table_.of_id = device_buffer(
            context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, triplanar.size() * sizeof(cl_float4),
            "the material table's projections", triplanar.data());
        triplanar_table_.id_limit = id_limit_;
        std::vector<cl_int> slot_of_id(id_limit_, -1), method_of_slot(n_slots);
        for (size_t s = 0; s < n_slots; ++s) {
            slot_of_id[materials_[s].id] = static_cast<int>(s);
            method_of_slot[s] = slots_[s].method;
        }
        auto table = [&](const void* data, size_t bytes, const char* what) {
            return device_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, what,
                                 data);
        };
        slot_table_ = table(slots_.data(), slots_.size() * sizeof(OmMaterialSlot),
                            "the material table's slots");
        shade_table_ = table(slots_.data(), slots_.size() * sizeof(OmMaterialSlot),
                             "the material table's shading slots");
        slot_of_id_ = table(slot_of_id.data(), slot_of_id.size() * sizeof(cl_int),
                            "the material table's ids");
        method_of_slot_ = table(method_of_slot.data(), method_of_slot.size() * sizeof(cl_int),
                                "the material table's methods");
        // Submitted now: every frame waits on these copies, maybe from another queue, and OpenCL
        // lets a queue hold back what was never flushed (rusticl does, and a frame on a second
        // queue then waited for ever).
        queue.flush();
    } catch (const cl::Error& e) {
        throw Error("cannot gather the material table on the device: " +
                    describe_cl_error(e.err()));
    }
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
    at.copies = {gather(f.heights, heights_, at.heights, height_buffer_bytes(f) / sizeof(float),
                        ready),
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

cl::Kernel& MaterialFrame::tile_kernel(Method& m, OffsetVariant v) {
    v.lanes = runtime_->lanes();
    const std::string defines = offset_program_defines(*m.params.method, v, true);
    auto it = m.kernels.find(defines);
    if (it == m.kernels.end()) {
        std::vector<std::string> files = offset_program_files(*m.params.method);
        files.push_back("frame/tiles.cl");
        it = m.kernels
                 .emplace(defines,
                          runtime_->kernel(runtime_->program(files, defines), "om_offset_tiles"))
                 .first;
    }
    return it->second;
}

double MaterialFrame::kernel_ms() const {
    double ms = event_ms(classify_event_);
    for (const Dispatch& d : dispatches_) ms += event_ms(d.event);
    for (const cl::Event& e : behind_events_) ms += event_ms(e);
    for (const cl::Event& e : triplanar_events_) ms += event_ms(e);
    return ms;
}

const cl::CommandQueue& MaterialFrame::checked_queue(const DeviceGBuffer& g,
                                                     const cl::CommandQueue& queue) const {
    const cl::CommandQueue& q = pass_queue(*runtime_, queue);
    check_gbuffer(runtime_->context(), g);
    if (!g.material())
        throw Error(
            "the G-buffer has no material buffer: a material frame needs each pixel's material id");
    return q;
}

cl::Event MaterialFrame::enqueue(const DeviceGBuffer& g, const OffsetTargets& t,
                                 const std::vector<cl::Event>& wait,
                                 const cl::CommandQueue& queue_given) {
    refuse_without_projections("enqueue");
    return trace(g, t, wait, queue_given, true);
}

void MaterialFrame::refuse_without_projections(const char* call) const {
    // Its pixels' G-buffer holds no uv of theirs without the split: a frame would trace and
    // shade them silently wrong.
    if (triplanar_table_.any)
        throw Error(triplanar_table_.name + " is triplanar: the material frame's " + call +
                    " needs its projections (ReconstructPass's triplanar split, then the " + call +
                    " that takes the TriplanarPlanes)");
}

cl::Event MaterialFrame::trace(const DeviceGBuffer& g, const OffsetTargets& t,
                               const std::vector<cl::Event>& wait,
                               const cl::CommandQueue& queue_given, bool pass_through) {
    Runtime& rt = *runtime_;
    const cl::Context& context = rt.context();
    const cl::CommandQueue& queue = checked_queue(g, queue_given);
    check_targets(context, t, g.pixels());
    behind_events_.clear();
    triplanar_events_.clear();

    OmTileParams T{};
    T.width = g.width;
    T.height = g.height;
    T.tile_h = tile_rows_;
    T.tiles_x = (g.width + OM_TILE_W - 1) / OM_TILE_W;
    T.tile_count = T.tiles_x * ((g.height + tile_rows_ - 1) / tile_rows_);
    T.slot_count = static_cast<om_int>(materials_.size());
    T.method_count = static_cast<om_int>(methods_.size());
    T.id_limit = id_limit_;
    T.pass_through = pass_through ? 1 : 0;
    const size_t n_methods = methods_.size();
    std::vector<cl_uint> counts(n_methods + 2);
    refresh();
    // The last frame's dispatches read the lists this classification rewrites.
    std::vector<cl::Event> previous;
    for (const Dispatch& d : dispatches_) previous.push_back(d.event);
    dispatches_.clear();
    try {
        if (tiles_ != static_cast<size_t>(T.tile_count)) {
            // Method k's list holds up to one entry per tile for each of its materials.
            tiles_ = static_cast<size_t>(T.tile_count);
            bases_.assign(n_methods, 0);
            size_t total = 0;
            for (size_t k = 0; k < n_methods; ++k) {
                bases_[k] = static_cast<cl_uint>(total);
                for (const OmMaterialSlot& s : slots_)
                    if (s.method == static_cast<int>(k)) total += tiles_;
            }
            if (2 * total > UINT_MAX) throw Error("the G-buffer has too many tiles");
            counts_ = device_buffer(context, CL_MEM_READ_WRITE, counts.size() * sizeof(cl_uint),
                                    "the tile counts");
            counts_reset_.assign(counts.size(), 0u);
            counts_reset_.back() = 0xffffffffu;
            entries_ = device_buffer(context, CL_MEM_READ_WRITE, 2 * total * sizeof(cl_uint),
                                     "the tile lists");
            list_base_ = device_buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                       bases_.size() * sizeof(cl_uint), "the tile list bases",
                                       bases_.data());
        }
        // One write of the whole buffer, not a fill of each part: Oclgrind 21.10 takes the size of
        // a partial host store for its record of the whole buffer's initialised bytes, and then
        // reads the classification's counts past it as uninitialised.
        cl::Event reset;
        queue.enqueueWriteBuffer(counts_, CL_FALSE, 0, counts_reset_.size() * sizeof(cl_uint),
                                 counts_reset_.data(), &wait, &reset);
        std::vector<cl::Event> deps = wait;
        const std::vector<cl::Event> setup = setup_events();
        deps.insert(deps.end(), setup.begin(), setup.end());
        deps.insert(deps.end(), previous.begin(), previous.end());
        deps.push_back(reset);
        set_args(classify_, T, g.material, g.uv, slot_of_id_, method_of_slot_, list_base_, counts_,
                 entries_, t.uv);
        set_optional(classify_, 9, t.depth);
        set_optional(classify_, 10, t.fetches);
        set_optional(classify_, 11, t.flags);
        queue.enqueueNDRangeKernel(classify_, cl::NullRange, padded(tiles_),
                                   cl::NDRange(kLocalSize), &deps, &classify_event_);
        const std::vector<cl::Event> classified{classify_event_};
        queue.enqueueReadBuffer(counts_, CL_TRUE, 0, counts.size() * sizeof(cl_uint), counts.data(),
                                &classified);
        if (counts[n_methods] > 0) {
            const size_t p = counts[n_methods + 1];
            float id = 0.0f;
            queue.enqueueReadBuffer(g.material, CL_TRUE, p * sizeof(float), sizeof(float), &id);
            throw Error(unknown_material(id, p, g.width, counts[n_methods]));
        }
        const int lanes = rt.lanes();
        std::vector<cl::Event> done;
        for (size_t k = 0; k < n_methods; ++k) {
            if (counts[k] == 0) continue;
            Dispatch d;
            d.method = methods_[k].params.method;
            d.entries = counts[k];
            // A work-item per block of a tile, or per two blocks (tiles.cl).
            const int groups = lane_groups(*d.method, lanes);
            const size_t per_entry =
                static_cast<size_t>((om_tile_blocks(lanes, tile_rows_) + groups - 1) / groups);
            d.work_items = d.entries * per_entry;
            T.entry_base = static_cast<om_int>(bases_[k]);
            T.entry_count = static_cast<om_int>(counts[k]);
            OffsetVariant variant = variant_writing(t);
            variant.curved = g.curvature() != nullptr;
            cl::Kernel& kernel = tile_kernel(methods_[k], variant);
            set_args(kernel, T, slot_table_, entries_, g.material, g.uv, g.view, heights_);
            set_optional(kernel, 7, methods_[k].aux);
            kernel.setArg(8, t.uv);
            set_optional(kernel, 9, t.depth);
            set_optional(kernel, 10, t.fetches);
            set_optional(kernel, 11, t.flags);
            set_optional(kernel, 12, g.curvature);
            queue.enqueueNDRangeKernel(kernel, cl::NullRange, padded(d.work_items),
                                       cl::NDRange(kLocalSize), &classified, &d.event);
            done.push_back(d.event);
            dispatches_.push_back(d);
        }
        if (done.empty()) return classify_event_;
        if (done.size() == 1) return done.front();
        cl::Event all;
        queue.enqueueMarkerWithWaitList(&done, &all);
        return all;
    } catch (const cl::Error& e) {
        throw Error("cannot run the material frame: " + describe_cl_error(e.err()));
    }
}

const cl::CommandQueue& MaterialFrame::check_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                                    const LayerBehind& behind,
                                                    const cl::CommandQueue& queue_given) {
    if (triplanar_table_.any)
        throw Error("the layer behind does not trace triplanar materials: " +
                    triplanar_table_.name + " is one");
    const cl::Context& context = runtime_->context();
    const cl::CommandQueue& queue = checked_queue(g, queue_given);
    const DeviceGBuffer& b = behind.gbuffer;
    const size_t n = g.pixels();
    if (b.width != g.width || b.height != g.height)
        throw Error("the layer behind is " + std::to_string(b.width) + "x" +
                    std::to_string(b.height) + "; the G-buffer is " + std::to_string(g.width) +
                    "x" + std::to_string(g.height));
    if (!t.flags()) throw Error("a frame with a layer behind needs the offset pass's flags output");
    checked_queue(b, queue);
    check_targets(context, behind.targets, n);
    if (!behind.targets.depth() || !behind.targets.fetches() || !behind.targets.flags())
        throw Error("the layer behind's targets need every output (uv, depth, fetches, flags)");
    // Read back here as well as written: none may be write-only.
    check_buffer(context, t.flags, {"the offset pass's flags output", "uint", sizeof(cl_uint), n});
    check_buffer(context, behind.targets.uv,
                 {"the layer behind's uv output", "float2", sizeof(cl_float2), n});
    check_buffer(context, behind.targets.depth,
                 {"the layer behind's depth output", "float", sizeof(float), n});
    check_buffer(context, behind.targets.fetches,
                 {"the layer behind's fetches output", "uint", sizeof(cl_uint), n});
    check_buffer(context, behind.targets.flags,
                 {"the layer behind's flags output", "uint", sizeof(cl_uint), n});
    if (static_cast<bool>(g.light()) != static_cast<bool>(b.light()) ||
        static_cast<bool>(g.lod()) != static_cast<bool>(b.lod()))
        throw Error("the layer behind must carry the same planes (light, lod) as the G-buffer");
    // The first layer's planes its pixels that show the second take from it.
    const struct {
        const cl::Buffer& plane;
        const char* name;
        size_t bytes;
    } taken[] = {{g.uv, "the G-buffer's uv", sizeof(cl_float2)},
                 {g.view, "the G-buffer's view", sizeof(cl_float4)},
                 {g.material, "the G-buffer's material", sizeof(float)},
                 {g.light, "the G-buffer's light", sizeof(cl_float4)},
                 {g.lod, "the G-buffer's lod", sizeof(float)},
                 {g.curvature, "the G-buffer's curvature", sizeof(cl_float4)}};
    for (const auto& p : taken)
        check_buffer(context, p.plane, {p.name, "value", p.bytes, n, true, true});
    return queue;
}

cl::Event MaterialFrame::enqueue(const DeviceGBuffer& g, const OffsetTargets& t,
                                 const LayerBehind& behind, const std::vector<cl::Event>& wait,
                                 const cl::CommandQueue& queue_given) {
    const cl::CommandQueue& queue = check_behind(g, t, behind, queue_given);
    const cl::Event first = enqueue(g, t, wait, queue);
    return trace_behind(g, t, behind, {first}, queue);
}

cl::Event MaterialFrame::enqueue_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                        const LayerBehind& behind,
                                        const std::vector<cl::Event>& wait,
                                        const cl::CommandQueue& queue_given) {
    const cl::CommandQueue& queue = check_behind(g, t, behind, queue_given);
    // After the first layer's trace whatever the caller waits on (an out-of-order queue too).
    std::vector<cl::Event> after = wait;
    if (classify_event_()) after.push_back(classify_event_);
    for (const Dispatch& d : dispatches_)
        if (d.event()) after.push_back(d.event);
    return trace_behind(g, t, behind, after, queue);
}

cl::Event MaterialFrame::trace_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                      const LayerBehind& behind, const std::vector<cl::Event>& wait,
                                      const cl::CommandQueue& queue) {
    const cl::Context& context = runtime_->context();
    const DeviceGBuffer& b = behind.gbuffer;
    const size_t n = g.pixels();
    const std::vector<Dispatch> first_dispatches = dispatches_;
    const cl::Event first_classify = classify_event_;
    try {
        if (!behind_ids_() || behind_ids_.getInfo<CL_MEM_SIZE>() != n * sizeof(float))
            behind_ids_ = device_buffer(context, CL_MEM_READ_WRITE, n * sizeof(float),
                                        "the layer behind's masked ids");
        const cl_int count = static_cast<cl_int>(n);
        cl::Event masked, chosen;
        set_args(behind_mask_, count, t.flags, b.material, behind_ids_);
        queue.enqueueNDRangeKernel(behind_mask_, cl::NullRange, padded(n), cl::NDRange(kLocalSize),
                                   &wait, &masked);
        DeviceGBuffer kept = b;
        kept.material = behind_ids_;
        const cl::Event second = enqueue(kept, behind.targets, {masked}, queue);
        // The planes the layers share (a null one where either lacks it).
        auto both = [](const cl::Buffer& from, const cl::Buffer& to) {
            return from() && to() ? std::make_pair(from, to)
                                  : std::make_pair(cl::Buffer(), cl::Buffer());
        };
        const auto light = both(b.light, g.light), lod = both(b.lod, g.lod),
                   curvature = both(b.curvature, g.curvature);
        set_args(behind_choose_, count, t.flags, behind.targets.flags, behind.targets.uv,
                 behind.targets.depth, behind.targets.fetches, t.uv);
        set_optional(behind_choose_, 7, t.depth);
        set_optional(behind_choose_, 8, t.fetches);
        set_args_from(behind_choose_, 9, b.uv, b.view);
        set_optional(behind_choose_, 11, light.first);
        set_optional(behind_choose_, 12, lod.first);
        behind_choose_.setArg(13, b.material);
        set_optional(behind_choose_, 14, curvature.first);
        set_args_from(behind_choose_, 15, g.uv, g.view);
        set_optional(behind_choose_, 17, light.second);
        set_optional(behind_choose_, 18, lod.second);
        behind_choose_.setArg(19, g.material);
        set_optional(behind_choose_, 20, curvature.second);
        const std::vector<cl::Event> after_second{second};
        queue.enqueueNDRangeKernel(behind_choose_, cl::NullRange, padded(n),
                                   cl::NDRange(kLocalSize), &after_second, &chosen);
        std::vector<Dispatch> layers = first_dispatches;
        layers.insert(layers.end(), dispatches_.begin(), dispatches_.end());
        dispatches_ = layers;
        // The second classification's event is classify_event_.
        behind_events_ = {first_classify, masked, chosen};
        return chosen;
    } catch (const cl::Error& e) {
        throw Error("cannot run the material frame's layer behind: " + describe_cl_error(e.err()));
    }
}

cl::Event MaterialFrame::enqueue(const DeviceGBuffer& g, const OffsetTargets& t,
                                 const TriplanarPlanes& planes, const std::vector<cl::Event>& wait,
                                 const cl::CommandQueue& queue_given) {
    if (!triplanar_table_.any) return enqueue(g, t, wait, queue_given);
    const cl::Context& context = runtime_->context();
    const cl::CommandQueue& queue = checked_queue(g, queue_given);
    const size_t n = g.pixels();
    check_triplanar_planes(context, planes, g);
    const cl::Event first = trace(g, t, wait, queue, true);
    std::vector<Dispatch> all = dispatches_;
    std::vector<cl::Event> events{classify_event_};
    // The second and third projections' id-0 pixels are nobody's: no pass-through for them.
    const cl::Event second = trace(planes.second, planes.second_targets, {first}, queue, false);
    all.insert(all.end(), dispatches_.begin(), dispatches_.end());
    events.push_back(classify_event_);
    const cl::Event third = trace(planes.third, planes.third_targets, {second}, queue, false);
    all.insert(all.end(), dispatches_.begin(), dispatches_.end());
    dispatches_ = all;
    try {
        set_args(triplanar_merge_, static_cast<cl_int>(n), planes.second.material, planes.blend);
        set_optional(triplanar_merge_, 3, t.depth);
        set_optional(triplanar_merge_, 4, t.fetches);
        set_args_from(triplanar_merge_, 5, planes.second_targets.depth,
                      planes.second_targets.fetches, planes.third_targets.depth,
                      planes.third_targets.fetches, planes.ray_scale, planes.second.view,
                      planes.third.view);
        cl::Event merged;
        const std::vector<cl::Event> after{third};
        queue.enqueueNDRangeKernel(triplanar_merge_, cl::NullRange, padded((n + 15) / 16),
                                   cl::NDRange(kLocalSize), &after, &merged);
        // The third classification's event is classify_event_.
        events.push_back(merged);
        triplanar_events_ = events;
        return merged;
    } catch (const cl::Error& e) {
        throw Error("cannot merge the triplanar projections: " + describe_cl_error(e.err()));
    }
}

void MaterialFrame::check_triplanar_planes(const cl::Context& context, const TriplanarPlanes& p,
                                           const DeviceGBuffer& g) const {
    const size_t n = g.pixels();
    for (const DeviceGBuffer* b : {&p.second, &p.third}) {
        if (b->width != g.width || b->height != g.height)
            throw Error("the triplanar planes are " + std::to_string(b->width) + "x" +
                        std::to_string(b->height) + "; the G-buffer is " + std::to_string(g.width) +
                        "x" + std::to_string(g.height));
    }
    for (const OffsetTargets* o : {&p.second_targets, &p.third_targets}) {
        check_targets(context, *o, n);
        if (!o->depth() || !o->fetches() || !o->flags())
            throw Error(
                "the triplanar projections' targets need every output (uv, depth, "
                "fetches, flags)");
    }
    check_buffer(context, p.blend, {"the triplanar weights", "float4", sizeof(cl_float4), n});
    check_buffer(context, p.ray_scale, {"the triplanar ray scales", "float", sizeof(float), n});
}

cl::Event MaterialFrame::take_behind(const cl::Buffer& flags, const cl::Buffer& from,
                                     const cl::Buffer& to, size_t pixels, int words,
                                     const std::vector<cl::Event>& wait,
                                     const cl::CommandQueue& queue_given) {
    const cl::CommandQueue& queue = pass_queue(*runtime_, queue_given);
    const cl::Context& context = runtime_->context();
    const size_t bytes = static_cast<size_t>(words) * 4;
    check_buffer(context, flags, {"the frame's flags", "uint", sizeof(cl_uint), pixels});
    check_buffer(context, from, {"the layer behind's plane", "word", bytes, pixels});
    check_buffer(context, to, {"the G-buffer's plane", "word", bytes, pixels, true, false});
    set_args(behind_take_, static_cast<cl_int>(pixels), static_cast<cl_int>(words), flags, from,
             to);
    cl::Event done;
    try {
        queue.enqueueNDRangeKernel(behind_take_, cl::NullRange, padded(pixels),
                                   cl::NDRange(kLocalSize), &wait, &done);
    } catch (const cl::Error& e) {
        throw Error("cannot copy a plane of the layer behind: " + describe_cl_error(e.err()));
    }
    return done;
}

cl::Event MaterialFrame::shade(const cl::Buffer& uv, const cl::Buffer& flags,
                               const DeviceGBuffer& g, const ShadeSettings& s,
                               const cl::Buffer& out_rgba, const std::vector<cl::Event>& wait,
                               const cl::CommandQueue& queue) {
    return shade(uv, flags, g, s, out_rgba, cl::Buffer(), cl::Buffer(), nullptr, wait, queue);
}

cl::Event MaterialFrame::shade(const cl::Buffer& uv, const cl::Buffer& flags,
                               const DeviceGBuffer& g, const ShadeSettings& s,
                               const cl::Buffer& out_rgba, const cl::Buffer& shadow_mask,
                               const cl::Buffer& out_visibility, const std::vector<cl::Event>& wait,
                               const cl::CommandQueue& queue) {
    return shade(uv, flags, g, s, out_rgba, shadow_mask, out_visibility, nullptr, wait, queue);
}

cl::Event MaterialFrame::shade(const cl::Buffer& uv, const cl::Buffer& flags,
                               const DeviceGBuffer& g, const ShadeSettings& s,
                               const cl::Buffer& out_rgba, const cl::Buffer& shadow_mask,
                               const cl::Buffer& out_visibility, const TriplanarPlanes* planes,
                               const std::vector<cl::Event>& wait,
                               const cl::CommandQueue& queue_given) {
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
