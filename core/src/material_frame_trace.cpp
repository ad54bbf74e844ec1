// The material frame's trace: tile classification, the entry counts read back, one dispatch per
// method over its tiles.
#include <algorithm>
#include <climits>
#include <cstring>

#include "launch.hpp"
#include "offsetmap/material_frame.hpp"

namespace offsetmap {

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
            variant.uv_metric = g.uv_metric() != nullptr;
            cl::Kernel& kernel = tile_kernel(methods_[k], variant);
            set_args(kernel, T, slot_table_, entries_, g.material, g.uv, g.view, heights_);
            set_optional(kernel, 7, methods_[k].aux);
            kernel.setArg(8, t.uv);
            set_optional(kernel, 9, t.depth);
            set_optional(kernel, 10, t.fetches);
            set_optional(kernel, 11, t.flags);
            set_optional(kernel, 12, g.curvature);
            set_optional(kernel, 13, g.uv_metric);
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

}  // namespace offsetmap
