// A deferred frame of many materials: per pixel a material id (the G-buffer's `material`), per id
// a relief, its placement, the method that traces it and how it is shaded.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/offset_pass.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/settings.hpp"
#include "offsetmap/shade_pass.hpp"
#include "offsetmap/triplanar.hpp"

namespace offsetmap {

// A G-buffer's second layer: at each pixel the nearest surface behind the first (depth peeling),
// every plane the frame reads (its material required; its curvature traces it curved), and the
// targets to trace it into (every output required).
struct LayerBehind {
    DeviceGBuffer gbuffer;
    OffsetTargets targets;
};

// One material of a frame's table. Id 0 is reserved for pixels without relief (uv' = uv).
struct FrameMaterial {
    int id = 1;               // [1, kMaxMaterialId]
    std::string name;         // for messages and reports: its height map's file, or a label
    DeviceHeightField field;  // with normals, for the shading
    PassSettings settings;    // scale, reference plane, address mode, grazing rule (no LOD)
    MethodParams params;      // its method, resolved (resolve_params)
    DeviceImage albedo;       // optional (null texels: the neutral checker)
    // Projected from the world instead of the G-buffer's uv (wrap addressing only); its pixels
    // need the triplanar split (ReconstructPass) and the enqueue and shade that take its planes.
    Triplanar triplanar;
};

inline constexpr int kMaxMaterialId = 65535;

// What a material frame's shade reads beside the G-buffer: ShadePass's inputs, with the albedo
// each material's own and the triplanar split for a table that projects from the world.
struct FrameShadeInputs {
    cl::Buffer uv{};     // float2 per pixel, uv' (OffsetTargets::uv)
    cl::Buffer flags{};  // uint per pixel (OffsetTargets::flags), or null
    // float per pixel: a shadow map's lit fraction (ShadowMaskPass), or null, as
    // ShadeInputs::shadow_mask.
    cl::Buffer shadow_mask{};
    const TriplanarPlanes* triplanar = nullptr;  // the reconstruct pass's split, or null
};
// A frame's offset targets as its shade's inputs.
inline FrameShadeInputs frame_shade_inputs(const OffsetTargets& offsets,
                                           const TriplanarPlanes* triplanar = nullptr) {
    return {offsets.uv, offsets.flags, cl::Buffer(), triplanar};
}
// Tile rows (tiles are OM_TILE_W = 16 pixels wide): the tile measurement in docs/materials.md chose
// it.
inline constexpr int kDefaultTileRows = 8;

// The message for a G-buffer id without a table entry: the first such pixel (index in a row-major
// frame `width` wide) and how many there are.
std::string unknown_material(float id, size_t pixel, int width, size_t count);

// The materials' passes as one frame. Construction gathers every material's relief (and normals,
// albedo) into one buffer each and each method's precomputed data into one, so that a method runs
// as one dispatch over all its materials' tiles with each material's parameters; enqueued on the
// runtime's queue, waited for by the first frame. A field changed in place since (update(),
// mark_changed(), through any copy of it) is gathered again with its precomputed data by the next
// enqueue or shade, after the frames still reading the old copy; a new field (another upload)
// needs a new frame, and the albedo images are copied once. Throws Error for an empty table, more
// than OM_MAX_MATERIALS materials, an id out of range or given twice, a field without normals, LOD
// settings, or settings validate() refuses, naming the material.
class MaterialFrame {
  public:
    MaterialFrame(std::shared_ptr<Runtime> runtime, std::vector<FrameMaterial> materials,
                  int tile_rows = kDefaultTileRows);

    // Offsets every pixel by its material (`gbuffer.material` is required): classifies the tiles,
    // reads the entry counts back (the one wait inside: OpenCL 1.2 has no indirect dispatch),
    // throws Error naming a material id the table lacks before any pixel is traced, then enqueues
    // one dispatch per method present over its tiles. Each pixel gets the bits its material's
    // OffsetPass alone would give it (tested); id 0 gets uv' = uv, depth 0, no fetches. Returns an
    // event complete when every dispatch is. A table with a triplanar material needs the overload
    // that takes its TriplanarPlanes (and refuses this one, naming the material), as does shade.
    cl::Event enqueue(const DeviceGBuffer& gbuffer, const OffsetTargets& targets,
                      const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());
    // The same frame with a layer behind (`targets.flags` required). The pixels the first layer
    // does not show for the relief's sake (OM_FLAGS_SEE_BEHIND: a ray that left a curved base, a
    // tile mask's discard) are traced on the second layer with its material, method and
    // curvature, and only they: the others' ids are masked to 0 in a buffer of the frame's, so
    // the second classification lists just their tiles. Where the second layer shows a surface the
    // pixel takes its result into `targets`, flagged OM_FLAG_BEHIND, and the second layer's uv,
    // view, light, lod, material and curvature into `gbuffer`'s buffers (overwritten in place: they
    // must be writable), all in one pass, so shade() and an engine's depth offset see one layer
    // (take_behind copies its other planes: window depth, uv density); where it shows none the
    // pixel keeps its flag for the background. Without a layer behind (the overload above) such
    // pixels stay flagged for the engine to fill.
    cl::Event enqueue(const DeviceGBuffer& gbuffer, const OffsetTargets& targets,
                      const LayerBehind& behind, const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());
    // The same in two steps, for an engine that draws its second layer only where the first
    // needs it: after enqueue(gbuffer, targets) has traced the first layer (and the engine has
    // read its flags, OM_FLAGS_SEE_BEHIND, and drawn the layer behind at those pixels), this
    // traces the second layer there (after the first layer's dispatches, besides `wait`) and takes
    // its results as the overload above does. Only those pixels' values of the second layer's
    // planes matter: the rest may hold anything (finite or not). `dispatches()` then lists both
    // layers'.
    cl::Event enqueue_behind(const DeviceGBuffer& gbuffer, const OffsetTargets& targets,
                             const LayerBehind& behind, const std::vector<cl::Event>& wait = {},
                             const cl::CommandQueue& queue = cl::CommandQueue());
    // The same frame with triplanar materials: `planes` as the reconstruct pass's triplanar split
    // wrote them. The G-buffer's pass traces every pixel's dominant projection with the others;
    // the second and third projections are traced where they weigh (their own classification, so
    // a tile no blend crosses costs nothing more), and the blend's pixels take the weighted depth
    // of the three and the sum of their fetches in `targets`. Without triplanar materials it is
    // the enqueue above.
    cl::Event enqueue(const DeviceGBuffer& gbuffer, const OffsetTargets& targets,
                      const TriplanarPlanes& planes, const std::vector<cl::Event>& wait = {},
                      const cl::CommandQueue& queue = cl::CommandQueue());
    // What the reconstruct pass's triplanar split reads: per id the material's projection.
    const TriplanarTable& triplanar_table() const { return triplanar_table_; }

    // After an enqueue with a layer behind: copies `words` 4-byte words a pixel from `from` (the
    // second layer's plane) to `to` (the first's) where `flags` (its targets' flags) say BEHIND.
    cl::Event take_behind(const cl::Buffer& flags, const cl::Buffer& from, const cl::Buffer& to,
                          size_t pixels, int words, const std::vector<cl::Event>& wait = {},
                          const cl::CommandQueue& queue = cl::CommandQueue());

    // Shades uv' with each pixel's material: its normals, albedo and self-shadows (and a shadow
    // map's test where `inputs.shadow_mask` is given); id 0 flat with the checker. With triplanar
    // planes each triplanar pixel is shaded with the blend of its projections' albedo, relief
    // normals (reoriented onto the G-buffer's normal) and self-shadows (docs/design.md); a table
    // with a triplanar material refuses to shade without them. One dispatch, as ShadePass's
    // targets say.
    cl::Event shade(const DeviceGBuffer& gbuffer, const FrameShadeInputs& inputs,
                    const ShadeSettings& shade, const ShadeTargets& targets,
                    const std::vector<cl::Event>& wait = {},
                    const cl::CommandQueue& queue = cl::CommandQueue());

    // The last enqueue's dispatches, one per method present on screen (with a layer behind, the
    // first layer's and then the second's).
    struct Dispatch {
        const MethodInfo* method = nullptr;
        size_t entries = 0;     // (tile, material) entries it traced
        size_t work_items = 0;  // entries x work-items per tile (a block each, or two)
        cl::Event event;
    };
    const std::vector<Dispatch>& dispatches() const { return dispatches_; }
    const cl::Event& classify_event() const { return classify_event_; }
    // The last enqueue's kernel time: classification and dispatches, once complete (profiling
    // events; needs a profiling queue).
    double kernel_ms() const;
    const std::vector<FrameMaterial>& materials() const { return materials_; }
    int tile_rows() const { return tile_rows_; }

  private:
    struct Method {
        MethodParams params;  // the first of its materials' (the program's slot defines)
        cl::Buffer aux;       // its materials' precomputed data, concatenated (or null)
        std::map<std::string, cl::Kernel> kernels;  // by the outputs bound
    };
    // Where slot s's data lies in the gathered buffers (in their elements: floats, float4s,
    // float4s, floats), the field version it was gathered from and the copies that gathered it.
    struct Gathered {
        size_t heights = 0, normals = 0, albedo = 0, aux = 0;
        size_t aux_bytes = 0;
        FieldVersion::State version;
        std::vector<cl::Event> copies;  // relief, normals and precomputed data
        cl::Event albedo_copied;
    };
    // The construction's steps: the table's checks (an Error naming the material); each slot's
    // place in the gathered buffers (`Layout`, with each precomputed data built); the buffers made
    // and gathered, with the id, method and projection tables; the kernels built.
    struct Layout {
        size_t heights = 0, normals = 0, albedo = 0;  // the gathered buffers' elements
        std::vector<size_t> aux;                      // per method: its precomputed data's
        std::vector<PrecomputeSpec::Built> built;     // per slot
    };
    void check_table();
    void lay_out(Layout& layout);
    void gather_table(const Layout& layout);
    void write_tables();
    void build_kernels();
    // `words` 32-bit words of `src` into `dst` from word `at`, after `after`, on the runtime's
    // queue.
    cl::Event gather(const cl::Buffer& src, const cl::Buffer& dst, size_t at, size_t words,
                     const std::vector<cl::Event>& after);
    // The enqueue above; without `pass_through` id 0's pixels get no outputs.
    cl::Event trace(const DeviceGBuffer& g, const OffsetTargets& t,
                    const std::vector<cl::Event>& wait, const cl::CommandQueue& queue,
                    bool pass_through);
    // The layer behind's checks (an Error naming what is wrong; then the queue to enqueue on), and
    // its trace after the first layer's enqueue: the mask, the second layer's classification and
    // trace, the choice.
    const cl::CommandQueue& check_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                                         const LayerBehind& behind, const cl::CommandQueue& queue);
    cl::Event trace_behind(const DeviceGBuffer& g, const OffsetTargets& t,
                           const LayerBehind& behind, const std::vector<cl::Event>& wait,
                           const cl::CommandQueue& queue);
    // Its tile entry as `variant` asks (outputs only: the tile entry takes neither images nor LOD).
    cl::Kernel& tile_kernel(Method& m, OffsetVariant variant);
    // Slot s's precomputed data built from its field (an Error naming the material on failure).
    PrecomputeSpec::Built build_precomputed(size_t s);
    // Copies slot s's relief, normals and `built` data into the gathered buffers, after `after`,
    // its field's version and the build.
    void gather_field(size_t s, const PrecomputeSpec::Built& built,
                      const std::vector<cl::Event>& after);
    // Gathers again every slot whose field changed since (update, mark_changed), after the frames
    // still reading the gathered buffers.
    void refresh();
    std::vector<cl::Event> setup_events() const;  // every gathering copy's
    // The queue to enqueue on, after the G-buffer's checks (a material buffer required).
    const cl::CommandQueue& checked_queue(const DeviceGBuffer& g,
                                          const cl::CommandQueue& queue) const;
    void check_triplanar_planes(const cl::Context& context, const TriplanarPlanes& planes,
                                const DeviceGBuffer& g) const;
    // Throws Error naming the table's triplanar material for `call` without the planes.
    void refuse_without_projections(const char* call) const;

    std::shared_ptr<Runtime> runtime_;
    std::vector<FrameMaterial> materials_;
    int tile_rows_;
    std::vector<Method> methods_;
    std::vector<OmMaterialSlot> slots_;
    cl::Buffer slot_table_, slot_of_id_, method_of_slot_;
    // The slots again with the shading of the last ShadeSettings (written from slots_).
    cl::Buffer shade_table_;
    cl::Event shade_write_;
    ShadeSettings shade_settings_;
    bool shade_written_ = false;
    cl::Buffer heights_, normals_, albedo_;
    int id_limit_ = 1;
    std::vector<Gathered> gathered_;  // per slot
    cl::Event last_shade_;            // the last shade dispatch (it reads the gathered buffers)
    cl::Kernel gather_, classify_, shade_;
    cl::Kernel behind_mask_, behind_choose_, behind_take_, triplanar_merge_;
    TriplanarTable triplanar_table_;
    std::vector<cl::Event> triplanar_events_;  // the last enqueue's classifications and merge
    cl::Buffer behind_ids_;                    // the second layer's ids, masked (behind_mask_)
    std::vector<cl::Event> behind_events_;     // the last enqueue's mask and choice
    int shade_lanes_ = 1;                      // shade_'s lanes, the runtime's when it was built
    // Per frame size: the classification's counts, lists and their bases.
    size_t tiles_ = 0;
    cl::Buffer counts_, entries_, list_base_;
    std::vector<cl_uint> counts_reset_;  // the counts before a classification (written whole)
    std::vector<cl_uint> bases_;
    std::vector<Dispatch> dispatches_;
    cl::Event classify_event_;
};

}  // namespace offsetmap
