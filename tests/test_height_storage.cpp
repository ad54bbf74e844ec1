// Height storage (PassSettings::heights): a Unorm16 field holds its heights rounded to multiples of
// 1/65535 and packs them beside the floats, two per word, for the passes' bilinear reads. Packing
// changes where the values are read from, never the values: every method must give, bit for bit,
// the frame a float field of the rounded heights gives, on every lane count and address path.
#include <cmath>
#include <cstring>

#include "support.hpp"

namespace omtest {
namespace {

float rounded(float h) { return std::floor(h * 65535.0f + 0.5f) * OM_UNORM16_STEP; }

HeightMap rounded_map(HeightMap map) {
    for (float& h : map.h) h = rounded(h);
    return map;
}

std::shared_ptr<Runtime> runtime_with_lanes(int lanes) {
    static std::map<int, std::shared_ptr<Runtime>> runtimes;
    auto& rt = runtimes[lanes];
    if (!rt) {
        rt = Runtime::create();
        rt->set_lanes(lanes);
    }
    return rt;
}

OffsetResult frame(int lanes, const std::string& method, const DeviceHeightField& f,
                   const GBuffer& gb, const PassSettings& s) {
    auto rt = runtime_with_lanes(lanes);
    DeviceGBuffer g = upload(*rt, gb);
    OffsetPass pass(rt, method);
    return run_offset(*rt, pass, g, f, s, 1);
}

std::vector<cl_uint> read_words(Runtime& rt, const DeviceHeightField& f, size_t& floats) {
    if (f.ready()) f.ready.wait();
    floats = mip_pyramid_floats(f.width, f.height, f.mip_levels);
    EXPECT_EQ(height_buffer_bytes(f), (f.packed ? 2 : 1) * floats * sizeof(float));
    std::vector<cl_uint> all(height_buffer_bytes(f) / sizeof(cl_uint));
    rt.queue().enqueueReadBuffer(f.heights, CL_TRUE, 0, all.size() * sizeof(cl_uint), all.data());
    return all;
}

// A Unorm16 field of `map`, and a float field holding its pyramid (every level), on one runtime.
struct FieldPair {
    DeviceHeightField packed, floats;
};

FieldPair field_pair(Runtime& rt, const HeightMap& map, const PassSettings& s) {
    FieldPair p;
    p.packed = upload(rt, map, s);
    EXPECT_TRUE(p.packed.packed);
    p.floats = p.packed;
    p.floats.packed = false;
    const size_t bytes = height_buffer_bytes(p.floats);
    p.floats.heights = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, bytes);
    std::vector<cl::Event> ready = {p.packed.ready};
    rt.queue().enqueueCopyBuffer(p.packed.heights, p.floats.heights, 0, 0, bytes, &ready,
                                 &p.floats.ready);
    return p;
}

TEST(HeightStorage, PackedWordsGiveTheFrameOfTheSameFloats) {
    // A float map (Unorm16 rounds it), 48 x 29: not a power of two either way, so both wrap paths
    // run, and random views put lanes at the wrap and clamp edges, where reads leave the words.
    const HeightMap map = noisy_map(48, 29);
    PassSettings wrap, other;
    wrap.scale = other.scale = 0.1f;
    wrap.heights = other.heights = HeightStorage::Unorm16;
    other.lod.enabled = other.lod.footprint = true;  // lanes at coarser levels: their words
    other.address = AddressMode::Clamp;
    std::map<int, FieldPair> fields;
    for (int lanes : {16, 1}) fields[lanes] = field_pair(*runtime_with_lanes(lanes), map, wrap);
    const GBuffer gb = make_scene(RandomScene{25, 11, 7, 0.5, 90.0});
    for (const auto& name : method_names())
        for (const PassSettings* s : {&wrap, &other}) {
            const OffsetResult want = frame(16, name, fields[16].floats, gb, *s);
            for (int lanes : {16, 1}) {
                if (lanes == 1 && s == &other) continue;  // one pixel per item: wrap is enough
                const OffsetResult got = frame(lanes, name, fields[lanes].packed, gb, *s);
                const std::string what = name + (s == &wrap ? " wrap" : " clamp, LOD") + " lanes " +
                                         std::to_string(lanes);
                for (size_t k = 0; k < gb.pixels(); ++k) {
                    ASSERT_EQ(std::memcmp(&got.uv[k], &want.uv[k], sizeof(cl_float2)), 0)
                        << what << " pixel " << k;
                    ASSERT_EQ(got.fetches[k], want.fetches[k]) << what << " pixel " << k;
                    ASSERT_EQ(got.flags[k], want.flags[k]) << what << " pixel " << k;
                }
            }
        }
}

TEST(HeightStorage, WordsHoldEachTexelAndTheOneBelowAtEveryLevel) {
    auto rt = runtime();
    const HeightMap map = noisy_map(37, 5);  // levels 37x37 ... 1x1, odd sides
    PassSettings s;
    s.heights = HeightStorage::Unorm16;
    const DeviceHeightField f = upload(*rt, map, s);
    size_t floats = 0;
    const std::vector<cl_uint> all = read_words(*rt, f, floats);
    std::vector<float> pyramid(floats);
    std::memcpy(pyramid.data(), all.data(), floats * sizeof(float));
    // Level 0 is the map rounded (|change| <= half a step), and every level is rounded.
    for (size_t k = 0; k < map.h.size(); ++k) {
        ASSERT_EQ(pyramid[k], rounded(map.h[k])) << k;
        ASSERT_LE(std::abs(pyramid[k] - map.h[k]), 0.5f / 65535.0f + 0x1p-24f) << k;
    }
    int w = f.width, h = f.height;
    size_t offset = 0;
    for (int level = 0; level < f.mip_levels; ++level) {
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const size_t at = offset + static_cast<size_t>(j) * w + i;
                const size_t below = offset + static_cast<size_t>(std::min(j + 1, h - 1)) * w + i;
                const cl_uint word = all[floats + at];
                ASSERT_EQ(static_cast<float>(word & 0xffffu) * OM_UNORM16_STEP, pyramid[at])
                    << "level " << level << " texel " << i << "," << j;
                ASSERT_EQ(static_cast<float>(word >> 16) * OM_UNORM16_STEP, pyramid[below])
                    << "level " << level << " texel " << i << "," << j;
            }
        offset += static_cast<size_t>(w) * h;
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
    }
}

// Whether the upload packed the field, once its device work is done.
template <typename Heights>
bool packs(Runtime& rt, const Heights& heights, const PassSettings& s) {
    const DeviceHeightField f = upload(rt, heights, s);
    if (f.ready()) f.ready.wait();
    return f.packed;
}

TEST(HeightStorage, AutoPacksOnlyMapsThatLoseNothing) {
    auto rt = runtime();
    PassSettings s;  // Auto
    const HeightMap floats = noisy_map(16, 3);
    const HeightMap sixteen = rounded_map(floats);
    // As an 8-bit file reads: c * (1 / 255) in one rounding, within 2^-24 of 257 c / 65535.
    const HeightMap eight = make_map(16, 16, [](int i, int j) {
        return static_cast<float>((i * 16 + j) % 256) * (1.0f / 255.0f);
    });
    EXPECT_FALSE(packs(*rt, floats, s));
    EXPECT_TRUE(packs(*rt, sixteen, s));
    EXPECT_TRUE(packs(*rt, eight, s));
    s.heights = HeightStorage::Float;
    EXPECT_FALSE(packs(*rt, sixteen, s));
    // Packing a map that holds them keeps its heights bit for bit.
    s.heights = HeightStorage::Auto;
    const DeviceHeightField f = upload(*rt, sixteen, s);
    size_t n = 0;
    const std::vector<cl_uint> all = read_words(*rt, f, n);
    EXPECT_EQ(std::memcmp(all.data(), sixteen.h.data(), sixteen.h.size() * sizeof(float)), 0);
    // Heights in the caller's memory: unorm8 and unorm16 buffers pack, float ones do not.
    for (Storage storage : {Storage::Unorm16, Storage::Unorm8, Storage::Float}) {
        DeviceHeights d;
        d.width = d.height = 4;
        d.texels.storage = storage;
        d.texels.buffer = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, 16 * storage_bytes(storage));
        rt->queue().enqueueFillBuffer(d.texels.buffer, cl_uchar(0), 0, 16 * storage_bytes(storage));
        EXPECT_EQ(packs(*rt, d, s), storage != Storage::Float) << static_cast<int>(storage);
    }
}

}  // namespace
}  // namespace omtest
