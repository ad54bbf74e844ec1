// The height field on the device: heights with their box-filtered mip pyramid, and normals.
#include "offsetmap/height_field.hpp"

#include <algorithm>
#include <cmath>

#include "launch.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap {
namespace {

const cl_uint kZero = 0;

// The mip chain after `after`; returns the last level's event (or `after` when there is none).
std::vector<cl::Event> build_mips(Runtime& rt, DeviceHeightField& f, std::vector<cl::Event> after) {
    if (f.mip_levels < 2) return after;
    cl::Kernel k = rt.kernel(rt.program({"prep/mips.cl"}), "om_mip_level");
    int w = f.width, h = f.height, offset = 0;
    for (int level = 1; level < f.mip_levels; ++level) {
        int cw = std::max(1, w / 2), ch = std::max(1, h / 2), child = offset + w * h;
        set_args(k, f.heights, offset, w, h, child, cw, ch);
        // Each level reads the one before it: chained by events (the queue may be out of order).
        cl::Event done;
        enqueue_grid(rt.queue(), k, cl::NDRange(cw, ch), &after, &done);
        after = {done};
        offset = child;
        w = cw;
        h = ch;
    }
    return after;
}

// HeightStorage::Unorm16 after `after`: the pyramid rounded, then each level's words packed.
std::vector<cl::Event> pack_unorm16(Runtime& rt, DeviceHeightField& f,
                                    std::vector<cl::Event> after) {
    if (!f.packed) return after;
    const cl::Program& program = rt.program({"prep/unorm16.cl"});
    const int words = static_cast<int>(mip_pyramid_floats(f.width, f.height, f.mip_levels));
    cl::Kernel round = rt.kernel(program, "om_round_heights");
    set_args(round, f.heights, words);
    cl::Event rounded;
    enqueue_grid(rt.queue(), round, cl::NDRange(words), &after, &rounded);
    cl::Kernel pack = rt.kernel(program, "om_pack_heights");
    std::vector<cl::Event> done;
    int w = f.width, h = f.height, offset = 0;
    for (int level = 0; level < f.mip_levels; ++level) {
        set_args(pack, f.heights, words, offset, w, h);
        std::vector<cl::Event> wait = {rounded};
        cl::Event packed;
        enqueue_grid(rt.queue(), pack, cl::NDRange(w, h), &wait, &packed);
        done.push_back(packed);
        offset += w * h;
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
    return done;
}

// Whether a field stored by `settings` is packed, given whether its level 0 loses nothing rounded.
bool packs(const PassSettings& settings, bool lossless) {
    return settings.heights == HeightStorage::Unorm16 ||
           (settings.heights == HeightStorage::Auto && lossless);
}

// Whether rounding level 0 to unorm16 loses nothing: every height within a float's rounding (2^-24,
// the spacing of floats just below 1) of the multiple of 1/65535 it rounds to. 16-bit files read
// as themselves; 8-bit ones (c / 255 = 257 c / 65535, converted in one rounding) within that.
bool holds_unorm16(const HeightMap& map) {
    for (float h : map.h) {
        const float q = std::floor(h * 65535.0f + 0.5f) * OM_UNORM16_STEP;
        if (!(std::fabs(h - q) <= 0x1p-24f)) return false;
    }
    return true;
}

// The same for heights in the caller's memory, by their format: unorm8 or unorm16 values (the
// import's c / 65535 is within a float's rounding of the product the words decode to).
bool at_most_16_bits(const DeviceHeights& d) {
    if (d.texels.image()) {
        const cl_channel_type t =
            d.texels.image.getImageInfo<CL_IMAGE_FORMAT>().image_channel_data_type;
        return t == CL_UNORM_INT8 || t == CL_UNORM_INT16;
    }
    return d.texels.storage == Storage::Unorm8 || d.texels.storage == Storage::Unorm16;
}

}  // namespace

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

size_t height_buffer_bytes(const DeviceHeightField& f) {
    return mip_pyramid_floats(f.width, f.height, f.mip_levels) * (f.packed ? 2 : 1) * sizeof(float);
}

int packed_heights_offset(const DeviceHeightField& f) {
    return f.packed ? static_cast<int>(mip_pyramid_floats(f.width, f.height, f.mip_levels)) : 0;
}

namespace {

void check_normal_map(const Image4* normal_map, int width, int height) {
    if (normal_map && (normal_map->width != width || normal_map->height != height))
        throw Error("normal map is " + std::to_string(normal_map->width) + "x" +
                    std::to_string(normal_map->height) + " but the height map is " +
                    std::to_string(width) + "x" + std::to_string(height));
}

// A field of width x height with its pyramid and normals allocated, level 0 still to fill. The
// normals are writable whether they come from a file or not: an update may derive them.
DeviceHeightField allocate_field(Runtime& rt, int width, int height, const Image4* normal_map,
                                 bool packed) {
    check_normal_map(normal_map, width, height);
    DeviceHeightField f;
    f.width = width;
    f.height = height;
    f.mip_levels = mip_level_count(width, height);
    f.packed = packed;
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    f.heights = device_buffer(rt.context(), CL_MEM_READ_WRITE, height_buffer_bytes(f),
                              "the " + size + " height pyramid");
    const size_t normals_bytes = static_cast<size_t>(width) * height * sizeof(cl_float4);
    f.normals = normal_map ? device_buffer(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR,
                                           normals_bytes, "the " + size + " normal map",
                                           normal_map->texels.data())
                           : device_buffer(rt.context(), CL_MEM_READ_WRITE, normals_bytes,
                                           "the " + size + " normals");
    return f;
}

// Everything after level 0 (`filled`): the mips, the unorm16 rounding and words, the normals
// (derived from the heights the passes read; or the normal map's, copied after `wait` from
// `normal_texels` when given, already in place otherwise), and the field's `ready` marker.
void finish_field(Runtime& rt, DeviceHeightField& f, const PassSettings& settings,
                  const Image4* normal_map, const cl::Event& filled,
                  const std::vector<cl::Event>& wait = {},
                  const cl::Buffer& normal_texels = cl::Buffer()) {
    std::vector<cl::Event> done = pack_unorm16(rt, f, build_mips(rt, f, {filled}));
    const std::vector<cl::Event> heights_done = f.packed ? done : std::vector<cl::Event>{filled};
    if (normal_map) {
        if (normal_texels()) {
            cl::Event copied;
            rt.queue().enqueueCopyBuffer(normal_texels, f.normals, 0, 0,
                                         normal_map->texels.size() * sizeof(cl_float4), &wait,
                                         &copied);
            done.push_back(copied);
        }
    } else {
        cl::Kernel k =
            rt.kernel(rt.program(sampling_program_files("prep/normals.cl")), "om_normals");
        set_args(k, offset_params(settings, f.width, f.height), f.heights, f.normals);
        cl::Event normals;  // after level 0, so after `wait` too
        enqueue_grid(rt.queue(), k, cl::NDRange(f.width, f.height), &heights_done, &normals);
        done.push_back(normals);
    }
    rt.queue().enqueueMarkerWithWaitList(&done, &f.ready);
    // Submitted now, so a caller waiting on `ready` alone never waits on an unflushed queue.
    rt.queue().flush();
}

// The import's clamped-value counter, zeroed as it is made.
cl::Buffer clamp_counter(Runtime& rt) {
    return device_buffer(rt.context(), CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, sizeof(cl_uint),
                         "the clamped-height counter", &kZero);
}

// Level 0 of `f` from `texels` (a buffer of `storage` values or an image) by the import kernel,
// after `wait`, counting clamped values in `count`; returns its event. Both uploads write level 0
// this way, on the device: a host-side copy into part of the pyramid is also where Oclgrind 21.10
// loses track of the buffer's initialised bytes (it resizes its shadow of the whole buffer to the
// copy), so a store into level 1 then runs past that shadow.
cl::Event import_level0(Runtime& rt, DeviceHeightField& f, const Input& texels, bool depth_map,
                        std::vector<cl::Event> after, const cl::Buffer& count) {
    const bool image = texels.image() != nullptr;
    cl::Kernel k = rt.kernel(rt.program({"common/storage.cl", "prep/import.cl"},
                                        image ? "#define OM_IMAGE_HEIGHTS\n" : ""),
                             "om_import_heights");
    if (image)
        k.setArg(0, texels.image);
    else
        k.setArg(0, texels.buffer);
    set_args_from(k, 1, static_cast<cl_int>(texels.storage), f.width, f.height,
                  static_cast<cl_int>(depth_map), f.heights, count);
    cl::Event filled;
    enqueue_grid(rt.queue(), k, cl::NDRange(f.width, f.height), &after, &filled);
    return filled;
}

// The host map's heights in a buffer that copies them as it is made, so the caller's map may go
// at once; the import into the pyramid is enqueued like the rest. The map's heights lie in [0, 1]
// (validated), so the import keeps them bit for bit.
Input host_texels(Runtime& rt, const HeightMap& map) {
    Input texels;
    texels.buffer = device_buffer(
        rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, map.h.size() * sizeof(float),
        "the " + std::to_string(map.width) + "x" + std::to_string(map.height) + " heights",
        map.h.data());
    return texels;
}

// Checks the device heights' size and input; returns the input as the import kernel reads it
// and, in `after`, `wait` and the copy that makes it readable (if any).
Input device_texels(Runtime& rt, const DeviceHeights& heights, const std::vector<cl::Event>& wait,
                    std::vector<cl::Event>& after) {
    const int w = heights.width, h = heights.height;
    if (w <= 0 || h <= 0 || static_cast<long long>(w) * h > kMaxHeightTexels)
        throw Error("the device heights are " + std::to_string(w) + "x" + std::to_string(h) +
                    "; a height map has 1 to " + std::to_string(kMaxHeightTexels) + " texels");
    check_input(rt.context(), heights.texels, "the device heights", 1, w, h);
    cl::Event copied;
    const Input texels = readable_input(rt, heights.texels, w, h, rt.queue(), wait, copied);
    after = wait;
    if (copied()) after.push_back(copied);
    return texels;
}

// What an update may rewrite: a field of the same size whose buffers the library can write, kept
// as the settings keep it (floats, or unorm16 words when the new heights fit them).
void check_update(const Runtime& rt, const DeviceHeightField& f, int width, int height,
                  const PassSettings& settings, bool lossless, const Image4* normal_map) {
    check_field(rt.context(), f, true);
    if (width != f.width || height != f.height)
        throw Error("cannot update the " + std::to_string(f.width) + "x" +
                    std::to_string(f.height) + " height field in place with " +
                    std::to_string(width) + "x" + std::to_string(height) +
                    " heights: a field changes size only by a new upload");
    check_normal_map(normal_map, width, height);
    check_buffer(rt.context(), f.heights,
                 {"the height field's heights buffer", "float", sizeof(float),
                  height_buffer_bytes(f) / sizeof(float), true});
    check_buffer(rt.context(), f.normals,
                 {"the height field's normals buffer", "float4", sizeof(cl_float4),
                  static_cast<size_t>(f.width) * f.height, true});
    if (f.packed && !packs(settings, lossless))
        throw Error(
            "cannot update the height field in place: it keeps its heights as unorm16 words "
            "(uploaded from 16-bit values) and these heights are not 16-bit values (or the "
            "settings ask for floats); upload a new field, or upload with HeightStorage::Float");
    if (!f.packed && settings.heights == HeightStorage::Unorm16)
        throw Error(
            "cannot update the height field in place as unorm16 words: it keeps its heights as "
            "floats; upload a new field with HeightStorage::Unorm16");
}

// Rewrites the field from `texels` after `after`: level 0, the pyramid, words and normals; the
// field's `ready` becomes the last step and its version advances.
void rewrite_field(Runtime& rt, DeviceHeightField& f, const PassSettings& settings,
                   const Image4* normal_map, const Input& texels, bool depth_map,
                   const std::vector<cl::Event>& after, cl::Buffer* clamped) {
    const cl::Buffer normal_texels =
        normal_map ? device_buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                   normal_map->texels.size() * sizeof(cl_float4), "the normal map",
                                   normal_map->texels.data())
                   : cl::Buffer();
    const cl::Buffer count = clamp_counter(rt);
    const cl::Event filled = import_level0(rt, f, texels, depth_map, after, count);
    finish_field(rt, f, settings, normal_map, filled, after, normal_texels);
    mark_changed(f, f.ready);
    if (clamped) *clamped = count;
}

}  // namespace

DeviceHeightField upload(Runtime& rt, const HeightMap& map, const PassSettings& settings,
                         const Image4* normal_map, const std::vector<cl::Event>& wait) {
    validate_height_map(map, "height map");
    validate(settings);
    // The staging buffers before the field's own (here and below): Oclgrind 21.10 hands a released
    // buffer's record of initialised bytes to the next buffer made, and a field's pyramid that
    // took the last upload's staging heights then read as uninitialised past their size. Made
    // first, the staging buffers take those places and write them whole.
    const Input texels = host_texels(rt, map);
    const cl::Buffer count = clamp_counter(rt);
    DeviceHeightField f =
        allocate_field(rt, map.width, map.height, normal_map, packs(settings, holds_unorm16(map)));
    const cl::Event filled = import_level0(rt, f, texels, false, wait, count);
    finish_field(rt, f, settings, normal_map, filled);
    return f;
}

DeviceHeightField upload(Runtime& rt, const DeviceHeights& heights, const PassSettings& settings,
                         const Image4* normal_map, const std::vector<cl::Event>& wait,
                         cl::Buffer* clamped) {
    validate(settings);
    std::vector<cl::Event> after;
    const Input texels = device_texels(rt, heights, wait, after);
    const cl::Buffer count = clamp_counter(rt);
    DeviceHeightField f = allocate_field(rt, heights.width, heights.height, normal_map,
                                         packs(settings, at_most_16_bits(heights)));
    const cl::Event filled = import_level0(rt, f, texels, heights.depth_map != 0, after, count);
    finish_field(rt, f, settings, normal_map, filled);
    if (clamped) *clamped = count;
    return f;
}

void update(Runtime& rt, DeviceHeightField& f, const HeightMap& map, const PassSettings& settings,
            const Image4* normal_map, const std::vector<cl::Event>& wait) {
    validate_height_map(map, "height map");
    validate(settings);
    check_update(rt, f, map.width, map.height, settings, holds_unorm16(map), normal_map);
    rewrite_field(rt, f, settings, normal_map, host_texels(rt, map), false, wait, nullptr);
}

void update(Runtime& rt, DeviceHeightField& f, const DeviceHeights& heights,
            const PassSettings& settings, const Image4* normal_map,
            const std::vector<cl::Event>& wait, cl::Buffer* clamped) {
    validate(settings);
    std::vector<cl::Event> after;
    const Input texels = device_texels(rt, heights, wait, after);
    check_update(rt, f, heights.width, heights.height, settings, at_most_16_bits(heights),
                 normal_map);
    rewrite_field(rt, f, settings, normal_map, texels, heights.depth_map != 0, after, clamped);
}

}  // namespace offsetmap
