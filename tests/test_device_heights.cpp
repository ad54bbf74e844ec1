// Heights from the caller's device memory (buffer or image; unorm8, unorm16, half, float) give the
// field the host upload gives for the values they decode to.
#include <Imath/half.h>

#include <cstring>

#include "support.hpp"

namespace omtest {
namespace {

std::vector<float> read_floats(Runtime& rt, const cl::Buffer& b, size_t n) {
    std::vector<float> out(n);
    rt.queue().enqueueReadBuffer(b, CL_TRUE, 0, n * sizeof(float), out.data());
    return out;
}

// The field's pyramid and normals, after its ready event.
struct FieldData {
    std::vector<float> pyramid, normals;
};

FieldData read_field(Runtime& rt, const DeviceHeightField& f) {
    if (f.ready()) f.ready.wait();
    FieldData d;
    d.pyramid = read_floats(rt, f.heights, mip_pyramid_floats(f.width, f.height, f.mip_levels));
    d.normals = read_floats(rt, f.normals, static_cast<size_t>(f.width) * f.height * 4);
    return d;
}

struct Case {
    Storage storage;
    bool image;
};

// The heights `map` as the caller would hold them: stored as `c.storage` in a buffer or an image,
// and the map of the values they decode to.
DeviceHeights store(const cl::Context& context, const HeightMap& map, Case c, HeightMap* decoded) {
    const size_t n = map.h.size();
    std::vector<unsigned char> bytes(n * storage_bytes(c.storage));
    *decoded = map;
    for (size_t k = 0; k < n; ++k) {
        const float h = map.h[k];
        if (c.storage == Storage::Half) {
            const Imath::half x(h);
            const uint16_t bits = x.bits();
            std::memcpy(&bytes[2 * k], &bits, 2);
            decoded->h[k] = x;
        } else if (c.storage == Storage::Unorm16) {
            const uint16_t code = static_cast<uint16_t>(std::lround(h * 65535.0));
            std::memcpy(&bytes[2 * k], &code, 2);
            decoded->h[k] = static_cast<float>(code / 65535.0);
        } else if (c.storage == Storage::Unorm8) {
            bytes[k] = static_cast<unsigned char>(std::lround(h * 255.0));
            decoded->h[k] = static_cast<float>(bytes[k] / 255.0);
        } else {
            std::memcpy(&bytes[4 * k], &h, 4);
        }
    }
    DeviceHeights d;
    d.width = map.width;
    d.height = map.height;
    d.texels.storage = c.storage;
    const cl_mem_flags flags = CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR;
    if (!c.image) {
        d.texels.buffer = cl::Buffer(context, flags, bytes.size(), bytes.data());
        return d;
    }
    const cl_channel_type type = c.storage == Storage::Half      ? CL_HALF_FLOAT
                                 : c.storage == Storage::Unorm16 ? CL_UNORM_INT16
                                 : c.storage == Storage::Unorm8  ? CL_UNORM_INT8
                                                                 : CL_FLOAT;
    d.texels.image = cl::Image2D(context, flags, cl::ImageFormat(CL_R, type), map.width, map.height,
                                 0, bytes.data());
    return d;
}

// Float and half decode exactly: the field is the host upload's, bit for bit. unorm codes decode
// by a division (buffers: OpenCL's, within 2.5 ulp; images: the format's conversion, within 1.5
// ulp), so level 0 is within 2.5 ulp of the correctly rounded quotient. Built on an out-of-order
// queue where the device has one: the import, mips and normals are ordered by events alone.
TEST(DeviceHeights, EveryStorageGivesTheHostUploadsField) {
    cl::Device device = runtime()->device();
    cl::Context context(device);
    cl::CommandQueue queue = out_of_order_queue(context, device);
    auto rt = std::make_shared<Runtime>(context, device, queue);
    const HeightMap map = make_map(75, 42, [](int i, int j) {
        return 0.5f + 0.45f * std::sin(0.31f * i + 0.1f) * std::cos(0.23f * j + 0.4f);
    });
    PassSettings s;
    s.scale = 0.06f;
    for (Case c :
         {Case{Storage::Float, false}, Case{Storage::Float, true}, Case{Storage::Half, false},
          Case{Storage::Half, true}, Case{Storage::Unorm16, false}, Case{Storage::Unorm16, true},
          Case{Storage::Unorm8, false}, Case{Storage::Unorm8, true}}) {
        const std::string what = std::string(c.image ? "image " : "buffer ") +
                                 std::to_string(static_cast<int>(c.storage));
        HeightMap decoded;
        DeviceHeights heights = store(context, map, c, &decoded);
        cl::Buffer clamped;
        FieldData got = read_field(*rt, upload(*rt, heights, s, nullptr, {}, &clamped));
        FieldData want = read_field(*rt, upload(*rt, decoded, s));
        const bool exact = c.storage == Storage::Float || c.storage == Storage::Half;
        if (exact) {
            EXPECT_EQ(got.pyramid, want.pyramid) << what;
            EXPECT_EQ(got.normals, want.normals) << what;
        } else {
            for (size_t k = 0; k < map.h.size(); ++k)
                ASSERT_LE(std::abs(got.pyramid[k] - want.pyramid[k]),
                          2.5f * (std::nextafter(want.pyramid[k], 2.0f) - want.pyramid[k]))
                    << what << " texel " << k;
        }
        cl_uint count = 1;
        rt->queue().enqueueReadBuffer(clamped, CL_TRUE, 0, sizeof count, &count);
        EXPECT_EQ(count, 0u) << what;
    }
}

// Depth maps become heights; values outside [0,1] are clamped and NaN read as 0, and counted.
TEST(DeviceHeights, DepthMapsAndOutOfRangeValues) {
    auto rt = runtime();
    const float nan = std::nanf("");
    std::vector<float> values = {0.25f, -0.5f, 1.5f, nan, 0.75f, 1.0f};
    DeviceHeights d;
    d.width = 3;
    d.height = 2;
    d.texels.buffer = cl::Buffer(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                 values.size() * sizeof(float), values.data());
    cl::Buffer clamped;
    PassSettings s;
    FieldData f = read_field(*rt, upload(*rt, d, s, nullptr, {}, &clamped));
    EXPECT_EQ(std::vector<float>(f.pyramid.begin(), f.pyramid.begin() + 6),
              (std::vector<float>{0.25f, 0.0f, 1.0f, 0.0f, 0.75f, 1.0f}));
    cl_uint count = 0;
    rt->queue().enqueueReadBuffer(clamped, CL_TRUE, 0, sizeof count, &count);
    EXPECT_EQ(count, 3u);
    d.depth_map = true;
    f = read_field(*rt, upload(*rt, d, s));
    EXPECT_EQ(std::vector<float>(f.pyramid.begin(), f.pyramid.begin() + 6),
              (std::vector<float>{0.75f, 1.0f, 0.0f, 1.0f, 0.25f, 0.0f}));
}

TEST(DeviceHeights, WrongMemoryIsRefusedByName) {
    auto rt = runtime();
    PassSettings s;
    DeviceHeights d;
    d.width = 64;
    d.height = 32;
    d.texels.storage = Storage::Unorm16;
    d.texels.buffer = cl::Buffer(rt->context(), CL_MEM_READ_ONLY, 64 * 32);  // unorm8's size
    EXPECT_TRUE(contains(error_of([&] { upload(*rt, d, s); }),
                         "the device heights buffer holds 2048 bytes; it needs 4096"));
    d.texels.buffer = cl::Buffer();
    EXPECT_TRUE(contains(error_of([&] { upload(*rt, d, s); }), "the device heights is not bound"));
    d.width = 0;
    EXPECT_TRUE(contains(error_of([&] { upload(*rt, d, s); }),
                         "the device heights are 0x32; a height map has 1 to 268435456 texels"));
}

}  // namespace
}  // namespace omtest
