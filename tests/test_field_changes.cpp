// A height field replaced every frame, or rewritten in place, never meets a pass's stale
// precomputed data: every frame equals a fresh pass's frame over a fresh upload, bit for bit.
#include <array>
#include <cstring>

#include "support.hpp"

namespace omtest {
namespace {

struct Maps {
    HeightMap a, b;
};

const Maps& data_maps() {
    static const Maps maps = {
        load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png"),
        load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/bumps.png")};
    return maps;
}

// The scene: a 320 x 180 plane G-buffer, s = 0.05.
const GBuffer& plane_gbuffer() {
    static const GBuffer gb = [] {
        PlaneScene scene;
        scene.width = 320;
        scene.height = 180;
        return make_scene(scene);
    }();
    return gb;
}

PassSettings field_settings() {
    PassSettings s;
    s.scale = 0.05f;
    return s;
}

// Every method with precomputed data, at parameters that keep the loop short (sphere's distance
// map coarser than its default; staleness does not depend on its resolution).
std::vector<MethodParams> precomputing_methods() {
    std::vector<MethodParams> out;
    for (const MethodInfo& m : methods()) {
        if (!m.precompute) continue;
        std::map<std::string, std::string> p;
        if (m.name == "sphere") p = {{"res", "64"}, {"layers", "16"}};
        out.push_back(resolve_params(m, p));
    }
    return out;
}

// The map's heights as the caller's float buffer.
DeviceHeights device_heights(Runtime& rt, const HeightMap& map) {
    DeviceHeights d;
    d.width = map.width;
    d.height = map.height;
    d.texels.storage = Storage::Float;
    d.texels.buffer = cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                 map.h.size() * sizeof(float), const_cast<float*>(map.h.data()));
    return d;
}

bool same_frame(const OffsetResult& x, const OffsetResult& y, size_t* differing) {
    size_t bad = 0;
    for (size_t k = 0; k < x.uv.size(); ++k)
        bad += std::memcmp(&x.uv[k], &y.uv[k], sizeof(cl_float2)) != 0 ||
               std::memcmp(&x.depth[k], &y.depth[k], sizeof(float)) != 0 ||
               x.fetches[k] != y.fetches[k] || x.flags[k] != y.flags[k];
    *differing = bad;
    return bad == 0;
}

// Each method's frame of each map from a fresh pass over a fresh upload.
std::vector<std::array<OffsetResult, 2>> fresh_frames(const std::vector<MethodParams>& methods) {
    auto rt = runtime();
    const DeviceGBuffer g = upload(*rt, plane_gbuffer());
    const PassSettings s = field_settings();
    std::vector<std::array<OffsetResult, 2>> out(methods.size());
    for (int m = 0; m < 2; ++m) {
        const DeviceHeightField f = upload(*rt, m ? data_maps().b : data_maps().a, s);
        for (size_t k = 0; k < methods.size(); ++k) {
            OffsetPass fresh(rt, methods[k]);
            out[k][m] = run_offset(*rt, fresh, g, f, s);
        }
    }
    return out;
}

// The loop: one pass per method kept across frames, the field replaced every frame by a
// new upload of the other map (from the host or the caller's device memory), each released before
// the next is made, so the driver may hand the new pyramid the released one's handle.
TEST(FieldChanges, ReplacedFieldsNeverMeetStalePrecomputedData) {
    auto rt = runtime();
    const std::vector<MethodParams> methods = precomputing_methods();
    ASSERT_GE(methods.size(), 3u);
    const auto fresh = fresh_frames(methods);
    const DeviceGBuffer g = upload(*rt, plane_gbuffer());
    const PassSettings s = field_settings();
    const int frames = 16;
    for (bool from_device : {false, true}) {
        std::vector<std::unique_ptr<OffsetPass>> passes;
        for (const MethodParams& p : methods) passes.push_back(std::make_unique<OffsetPass>(rt, p));
        std::vector<cl_mem> seen;
        int reused = 0;
        std::vector<int> wrong(methods.size(), 0);
        for (int frame = 0; frame < frames; ++frame) {
            const int m = frame % 2;
            const HeightMap& map = m ? data_maps().b : data_maps().a;
            const DeviceHeightField f =
                from_device ? upload(*rt, device_heights(*rt, map), s) : upload(*rt, map, s);
            reused += std::count(seen.begin(), seen.end(), f.heights()) > 0;
            seen.push_back(f.heights());
            for (size_t k = 0; k < methods.size(); ++k) {
                size_t differing = 0;
                if (!same_frame(run_offset(*rt, *passes[k], g, f, s), fresh[k][m], &differing)) {
                    ++wrong[k];
                    ADD_FAILURE() << methods[k].method->name
                                  << (from_device ? ", device" : ", host") << " upload, frame "
                                  << frame << ": " << differing << " of " << g.pixels()
                                  << " pixels differ from a fresh pass's";
                }
            }
        }
        std::printf("%s uploads: the new pyramid had a released one's handle in %d of %d frames\n",
                    from_device ? "device" : "host", reused, frames);
    }
}

// The map's heights as the caller's unorm16 buffer (the 16-bit PNGs' values, exactly).
DeviceHeights device_unorm16(Runtime& rt, const HeightMap& map) {
    std::vector<std::uint16_t> words(map.h.size());
    for (size_t k = 0; k < words.size(); ++k)
        words[k] = static_cast<std::uint16_t>(std::lround(map.h[k] * 65535.0));
    DeviceHeights d;
    d.width = map.width;
    d.height = map.height;
    d.texels.storage = Storage::Unorm16;
    d.texels.buffer = cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                 words.size() * sizeof(std::uint16_t), words.data());
    return d;
}

struct FieldData {
    std::vector<float> words, normals;  // the whole heights buffer (pyramid and any words)
};

FieldData read_field(Runtime& rt, const DeviceHeightField& f) {
    for (const cl::Event& e : field_ready(f)) e.wait();
    FieldData d;
    d.words.resize(height_buffer_bytes(f) / sizeof(float));
    d.normals.resize(static_cast<size_t>(f.width) * f.height * 4);
    rt.queue().enqueueReadBuffer(f.heights, CL_TRUE, 0, d.words.size() * sizeof(float),
                                 d.words.data());
    rt.queue().enqueueReadBuffer(f.normals, CL_TRUE, 0, d.normals.size() * sizeof(float),
                                 d.normals.data());
    return d;
}

bool same_floats(const std::vector<float>& x, const std::vector<float>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
}

// One field rewritten in place every frame, alternating the maps and the update's source (host,
// the caller's device memory), with one pass per method kept across frames: the field (pyramid,
// unorm16 words, normals) is a fresh upload's from the same source bit for bit, in the same
// buffers, and every frame a fresh pass's over it. Both storages: the 16-bit maps kept as unorm16
// words (host uploads and unorm16 buffers), and as floats (float buffers, or floats asked for).
TEST(FieldChanges, UpdatesInPlaceGiveAFreshUploadsFieldAndFrames) {
    auto rt = runtime();
    std::vector<MethodParams> methods = precomputing_methods();
    methods.push_back(resolve_params(find_method("pom"), {}));  // reads the words, no precompute
    const DeviceGBuffer g = upload(*rt, plane_gbuffer());
    const PassSettings s = field_settings();
    PassSettings as_floats = s;
    as_floats.heights = HeightStorage::Float;
    for (bool words : {true, false}) {
        // The map from the host or from a device buffer of the field's storage.
        auto fresh_upload = [&](const HeightMap& map, bool device) {
            if (!device) return upload(*rt, map, words ? s : as_floats);
            return upload(*rt, words ? device_unorm16(*rt, map) : device_heights(*rt, map), s);
        };
        DeviceHeightField field = fresh_upload(data_maps().a, !words);
        ASSERT_EQ(field.packed, words);
        const cl_mem heights = field.heights(), normals = field.normals();
        std::vector<std::unique_ptr<OffsetPass>> passes;
        for (const MethodParams& p : methods) passes.push_back(std::make_unique<OffsetPass>(rt, p));
        for (int frame = 0; frame < 6; ++frame) {
            const HeightMap& map = frame % 2 ? data_maps().b : data_maps().a;
            const bool device = frame % 4 >= 2;
            const std::string what = std::string(words ? "words" : "floats") + ", frame " +
                                     std::to_string(frame) + (device ? ", device" : ", host");
            if (frame > 0) {
                if (device)
                    update(*rt, field, words ? device_unorm16(*rt, map) : device_heights(*rt, map),
                           s);
                else
                    update(*rt, field, map, s);
            }
            ASSERT_EQ(field.heights(), heights) << what << ": reallocated";
            ASSERT_EQ(field.normals(), normals) << what << ": reallocated";
            const DeviceHeightField fresh = fresh_upload(map, device);
            const FieldData got = read_field(*rt, field), want = read_field(*rt, fresh);
            EXPECT_TRUE(same_floats(got.words, want.words)) << what << ": heights";
            EXPECT_TRUE(same_floats(got.normals, want.normals)) << what << ": normals";
            for (size_t k = 0; k < methods.size(); ++k) {
                OffsetPass fresh_pass(rt, methods[k]);
                size_t differing = 0;
                EXPECT_TRUE(same_frame(run_offset(*rt, *passes[k], g, field, s),
                                       run_offset(*rt, fresh_pass, g, fresh, s), &differing))
                    << methods[k].method->name << ", " << what << ": " << differing
                    << " pixels differ from a fresh pass's";
            }
        }
    }
}

// A 320 x 180 plane whose columns show four materials.
GBuffer material_gbuffer() {
    GBuffer gb = plane_gbuffer();
    gb.material.resize(gb.pixels());
    for (size_t k = 0; k < gb.pixels(); ++k)
        gb.material[k] = static_cast<float>(1 + (k % gb.width) * 4 / gb.width);
    return gb;
}

std::vector<FrameMaterial> frame_materials(const std::vector<MethodParams>& methods,
                                           const std::vector<DeviceHeightField>& fields) {
    std::vector<FrameMaterial> out;
    for (size_t k = 0; k < methods.size(); ++k) {
        FrameMaterial m;
        m.id = static_cast<int>(k) + 1;
        m.name = methods[k].method->name;
        m.field = fields[k];
        m.settings = field_settings();
        m.params = methods[k];
        out.push_back(m);
    }
    return out;
}

// Frame and shading of a material frame, read back.
struct Shaded {
    OffsetResult offsets;
    std::vector<cl_float4> rgba;
};

Shaded run_frame(Runtime& rt, MaterialFrame& frame, const DeviceGBuffer& g) {
    Shaded out;
    out.offsets = run_material_frame(rt, frame, g);
    const size_t n = g.pixels();
    cl::Buffer uv(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float2),
                  out.offsets.uv.data());
    cl::Buffer rgba(rt.context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
    ShadeSettings shade;
    shade.shadow = ShadowMode::Soft;
    frame.shade(g, {uv}, shade, {rgba}).wait();
    out.rgba.resize(n);
    rt.queue().enqueueReadBuffer(rgba, CL_TRUE, 0, n * sizeof(cl_float4), out.rgba.data());
    return out;
}

// A material frame kept across frames while its materials' fields are rewritten in place through
// the caller's own copies (the frame holds others): every frame, offsets and shading, is a frame
// built afresh from fresh uploads, bit for bit. Each material's map alternates on its own period.
TEST(FieldChanges, MaterialFrameGathersFieldsUpdatedInPlace) {
    auto rt = runtime();
    std::vector<MethodParams> methods = precomputing_methods();
    methods.push_back(resolve_params(find_method("pom"), {}));
    ASSERT_EQ(methods.size(), 4u);
    const PassSettings s = field_settings();
    const DeviceGBuffer g = upload(*rt, material_gbuffer());
    std::vector<DeviceHeightField> fields;
    for (size_t k = 0; k < methods.size(); ++k) fields.push_back(upload(*rt, data_maps().a, s));
    MaterialFrame kept(rt, frame_materials(methods, fields));
    std::vector<int> shown(methods.size(), 0);
    for (int frame = 0; frame < 5; ++frame) {
        for (size_t k = 0; k < methods.size(); ++k) {
            const int want = (frame >> (k % 2)) & 1;  // material k's map this frame
            if (want == shown[k]) continue;
            const HeightMap& map = want ? data_maps().b : data_maps().a;
            if (k < 2)
                update(*rt, fields[k], map, s);
            else
                update(*rt, fields[k], device_unorm16(*rt, map), s);
            shown[k] = want;
        }
        std::vector<DeviceHeightField> fresh_fields;  // each from its update's source
        for (size_t k = 0; k < methods.size(); ++k) {
            const HeightMap& map = shown[k] ? data_maps().b : data_maps().a;
            fresh_fields.push_back(k < 2 ? upload(*rt, map, s)
                                         : upload(*rt, device_unorm16(*rt, map), s));
        }
        MaterialFrame fresh(rt, frame_materials(methods, fresh_fields));
        const Shaded got = run_frame(*rt, kept, g), want = run_frame(*rt, fresh, g);
        size_t differing = 0;
        EXPECT_TRUE(same_frame(got.offsets, want.offsets, &differing))
            << "frame " << frame << ": " << differing << " pixels differ from a fresh frame's";
        EXPECT_EQ(
            std::memcmp(got.rgba.data(), want.rgba.data(), got.rgba.size() * sizeof(cl_float4)), 0)
            << "frame " << frame << ": shading differs from a fresh frame's";
    }
}

// A field the caller fills itself: after rewriting its heights (here a device copy of another
// field's), mark_changed makes a kept pass rebuild; the pass keys by the buffer it holds too, so
// re-pointing the field at another buffer is seen even without it.
TEST(FieldChanges, CallerFilledFieldsAreRebuiltWhenMarkedOrRepointed) {
    auto rt = runtime();
    const PassSettings s = field_settings();
    const std::vector<MethodParams> methods = precomputing_methods();
    const auto fresh = fresh_frames(methods);
    const DeviceGBuffer g = upload(*rt, plane_gbuffer());
    const DeviceHeightField a = upload(*rt, data_maps().a, s), b = upload(*rt, data_maps().b, s);
    for (const cl::Event& e : field_ready(a)) e.wait();
    for (const cl::Event& e : field_ready(b)) e.wait();
    auto copy_of = [&](const DeviceHeightField& from) {
        DeviceHeightField f;
        f.width = from.width;
        f.height = from.height;
        f.mip_levels = from.mip_levels;
        f.packed = from.packed;
        const size_t bytes = height_buffer_bytes(from);
        f.heights = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, bytes);
        f.normals = from.normals;
        rt->queue().enqueueCopyBuffer(from.heights, f.heights, 0, 0, bytes);
        rt->queue().finish();
        return f;
    };
    for (size_t k = 0; k < methods.size(); ++k) {
        OffsetPass pass(rt, methods[k]);
        DeviceHeightField mine = copy_of(a);
        size_t differing = 0;
        EXPECT_TRUE(same_frame(run_offset(*rt, pass, g, mine, s), fresh[k][0], &differing));
        // Rewritten in place, then marked.
        cl::Event copied;
        rt->queue().enqueueCopyBuffer(b.heights, mine.heights, 0, 0, height_buffer_bytes(b),
                                      nullptr, &copied);
        mine.normals = b.normals;
        mark_changed(mine, copied);
        EXPECT_TRUE(same_frame(run_offset(*rt, pass, g, mine, s), fresh[k][1], &differing))
            << methods[k].method->name << ", marked: " << differing << " pixels differ";
        // Re-pointed at a copy of the first map's heights, unmarked.
        const DeviceHeightField other = copy_of(a);
        mine.heights = other.heights;
        mine.normals = other.normals;
        EXPECT_TRUE(same_frame(run_offset(*rt, pass, g, mine, s), fresh[k][0], &differing))
            << methods[k].method->name << ", re-pointed: " << differing << " pixels differ";
    }
}

// Updates that cannot be made in place are refused, naming why, and change nothing.
TEST(FieldChanges, UpdatesThatCannotBeInPlaceAreRefused) {
    auto rt = runtime();
    const PassSettings s = field_settings();
    DeviceHeightField words = upload(*rt, data_maps().a, s);
    ASSERT_TRUE(words.packed);
    const std::uint64_t generation = field_key(words).generation;
    EXPECT_TRUE(contains(error_of([&] { update(*rt, words, smooth_map(256), s); }),
                         "these heights are not 16-bit values"));
    EXPECT_TRUE(
        contains(error_of([&] { update(*rt, words, device_heights(*rt, data_maps().b), s); }),
                 "these heights are not 16-bit values"));
    EXPECT_TRUE(contains(error_of([&] { update(*rt, words, smooth_map(64), s); }),
                         "cannot update the 256x256 height field in place with 64x64 heights"));
    PassSettings as_words = s;
    as_words.heights = HeightStorage::Unorm16;
    DeviceHeightField floats = upload(*rt, smooth_map(64), s);
    ASSERT_FALSE(floats.packed);
    EXPECT_TRUE(contains(error_of([&] { update(*rt, floats, smooth_map(64), as_words); }),
                         "it keeps its heights as floats"));
    DeviceHeightField read_only = floats;
    read_only.normals = cl::Buffer(rt->context(), CL_MEM_READ_ONLY, 64 * 64 * sizeof(cl_float4));
    EXPECT_TRUE(contains(error_of([&] { update(*rt, read_only, smooth_map(64), s); }),
                         "the height field's normals buffer is read-only"));
    EXPECT_EQ(field_key(words).generation, generation) << "a refused update changed the field";
}

}  // namespace
}  // namespace omtest
