// The engine-shaped G-buffer: depth, camera, tangent frame and uv, in buffers or images, float,
// half or snorm16, reconstructed into tangent-space V and L on the device.
#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "offsetmap/engine_reference.hpp"
#include "support.hpp"

// GoogleTest finds a parameter's printer in the parameter's namespace.
namespace offsetmap::engine_ref {
void PrintTo(const Encoding& e, std::ostream* os) { *os << e.name; }
}  // namespace offsetmap::engine_ref

namespace omtest {
namespace {

using engine_ref::decode_error;
using engine_ref::Decoded;
using engine_ref::encoded_frame;
using engine_ref::Encoding;
using engine_ref::EngineFrame;
using engine_ref::Plane;
using engine_ref::plane_frame;
using engine_ref::randomise_frames;
using engine_ref::Reference;
using engine_ref::reference;
using engine_ref::stored_value;

constexpr double kU = 1.0 / (1 << 24);  // unit roundoff of float

// The engine frame's reference on the tests' runtime.
Decoded reconstruct(const EngineGBuffer& in, bool light,
                    const std::shared_ptr<Runtime>& rt = runtime()) {
    return engine_ref::reconstruct(rt, in, light);
}

// The reference's own half conversion (the device check has no Imath) against Imath's, bit for
// bit, over every half's neighbourhood: each half, the floats a hair either side of it and the
// ties halfway to the next, subnormals, overflow, infinities and NaN.
Imath::half half_of_bits(std::uint32_t bits) {
    Imath::half h;
    h.setBits(static_cast<std::uint16_t>(bits));
    return h;
}

TEST(EngineGBuffer, HalfConversionMatchesImath) {
    size_t checked = 0;
    for (std::uint32_t bits = 0; bits < 0x10000; ++bits) {
        const Imath::half h = half_of_bits(bits);
        const float x = h;
        if (std::isnan(x)) {
            EXPECT_TRUE(std::isnan(engine_ref::half_value(static_cast<std::uint16_t>(bits))));
            continue;
        }
        ASSERT_EQ(engine_ref::half_value(static_cast<std::uint16_t>(bits)), x) << bits;
        const float next = half_of_bits(bits + 1);
        for (float y : {x, std::nextafter(x, 0.0f), std::nextafter(x, 2 * x), 0.5f * (x + next),
                        std::nextafter(0.5f * (x + next), 0.0f),
                        std::nextafter(0.5f * (x + next), 2 * next)}) {
            if (!std::isfinite(y)) continue;
            ASSERT_EQ(engine_ref::half_bits(y), Imath::half(y).bits()) << y;
            ++checked;
        }
    }
    for (float y : {1e-10f, 65519.99f, 65520.0f, 65520.01f, -65520.0f, 1e6f, -INFINITY})
        EXPECT_EQ(engine_ref::half_bits(y), Imath::half(y).bits()) << y;
    EXPECT_EQ(engine_ref::half_bits(std::nanf("")) & 0x7e00u, 0x7e00u);
    EXPECT_GT(checked, 5u * 0xf800u);
}

// The two reconstructions are equal bit for bit (NaNs included).
void expect_same_bits(const Decoded& a, const Decoded& b, const std::string& what) {
    ASSERT_EQ(a.light.size(), b.light.size()) << what;
    EXPECT_EQ(0, std::memcmp(a.uv.data(), b.uv.data(), a.uv.size() * sizeof(cl_float2))) << what;
    EXPECT_EQ(0, std::memcmp(a.view.data(), b.view.data(), a.view.size() * sizeof(cl_float4)))
        << what;
    if (!a.light.empty()) {  // memcmp on an empty vector's null data() is undefined
        EXPECT_EQ(0,
                  std::memcmp(a.light.data(), b.light.data(), a.light.size() * sizeof(cl_float4)))
            << what;
    }
}

PlaneScene small_plane() {
    PlaneScene s;
    s.width = 102;  // not a multiple of 4: the offset pass's last block of each row is partial
    s.height = 64;
    s.pitch_deg = 25.0;  // the horizon in the frame: sky pixels too
    s.camera_x = 0.3;
    s.camera_y = -0.7;
    s.tile = 0.5;
    return s;
}

class Reconstruct : public ::testing::TestWithParam<Encoding> {};

// V (and L) from every encoding within the derived bound of the double reference; sky pixels
// empty, the rest keep their stored uv.
TEST_P(Reconstruct, ViewAndLightWithinTheDerivedBound) {
    const Encoding& e = GetParam();
    EngineFrame f = encoded_frame(small_plane(), e, 7);
    if (!engine_ref::device_reads_images(runtime()->context(), f))
        GTEST_SKIP() << runtime()->device_name() << " has no image format for " << e.name;
    EngineGBuffer in = f.to_device(runtime()->context());
    in.light = e.light;
    const bool lit = e.light.kind != LightKind::None;
    Decoded d = reconstruct(in, lit);
    size_t sky = 0, traced = 0;
    double worst = 0.0, worst_l = 0.0;
    for (size_t k = 0; k < in.pixels(); ++k) {
        Reference ref = reference(f, k, e.light);
        if (ref.sky) {
            ++sky;
            EXPECT_TRUE(std::isnan(d.uv[k].s[0]) && std::isnan(d.uv[k].s[1])) << k;
            continue;
        }
        ++traced;
        for (int i = 0; i < 2; ++i) {
            const double want = stored_value(f.uv.v[2 * k + i], f.uv.storage);
            EXPECT_LE(std::abs(d.uv[k].s[i] - want), decode_error(f.uv.storage) * std::abs(want))
                << k;
        }
        for (int i = 0; i < 3; ++i) {
            const double err = std::abs(d.view[k].s[i] - ref.v_ts[i]);
            ASSERT_LE(err, ref.bound) << e.name << " pixel " << k << " V[" << i << "]";
            worst = std::max(worst, err / ref.bound);
            if (lit) {
                const double lerr = std::abs(d.light[k].s[i] - ref.l_ts[i]);
                ASSERT_LE(lerr, ref.l_bound) << e.name << " pixel " << k << " L[" << i << "]";
                worst_l = std::max(worst_l, lerr / ref.l_bound);
            }
        }
    }
    EXPECT_GT(sky, in.pixels() / 40) << "the scene should show sky";
    EXPECT_GT(traced, in.pixels() / 2);
    record_figure(std::string("reconstruct.") + e.name + ".v_of_bound", worst);
    record_figure(std::string("reconstruct.") + e.name + ".l_of_bound", worst_l);
    std::printf("%s: worst V error %.3f of the bound, L %.3f\n", e.name, worst, worst_l);
}

const EngineLight kNoLight;
const EngineLight kSun{LightKind::Directional, {0.3f, -0.4f, 0.8f}};
const EngineLight kLamp{LightKind::Point, {0.2f, 0.1f, 0.6f}};

INSTANTIATE_TEST_SUITE_P(
    Encodings, Reconstruct,
    ::testing::Values(
        Encoding{"tangent_float_buffers", FrameForm::NormalTangent, DepthConvention::ZeroToOne,
                 FirstRow::Top, Storage::Float, Storage::Float, Storage::Float, false, kSun},
        Encoding{"tangent_float_images_gl", FrameForm::NormalTangent, DepthConvention::GL,
                 FirstRow::Bottom, Storage::Float, Storage::Float, Storage::Float, true, kLamp},
        Encoding{"tangent_snorm16_buffers_unorm16_depth", FrameForm::NormalTangent,
                 DepthConvention::GL, FirstRow::Top, Storage::Unorm16, Storage::Snorm16,
                 Storage::Half, false, kNoLight},
        Encoding{"tangent_half_images_reversed", FrameForm::NormalTangent,
                 DepthConvention::Reversed, FirstRow::Top, Storage::Float, Storage::Half,
                 Storage::Half, true, kSun},
        Encoding{"quaternion_float_buffers_reversed", FrameForm::Quaternion,
                 DepthConvention::Reversed, FirstRow::Bottom, Storage::Float, Storage::Float,
                 Storage::Float, false, kLamp},
        Encoding{"quaternion_half_buffers", FrameForm::Quaternion, DepthConvention::ZeroToOne,
                 FirstRow::Top, Storage::Float, Storage::Half, Storage::Float, false, kNoLight},
        Encoding{"quaternion_snorm16_images_gl", FrameForm::Quaternion, DepthConvention::GL,
                 FirstRow::Top, Storage::Unorm16, Storage::Snorm16, Storage::Float, true, kSun}),
    [](const ::testing::TestParamInfo<Encoding>& info) { return std::string(info.param.name); });

// A layer drawn only at some pixels: the pass with regions writes those pixels as the whole
// frame's pass does, bit for bit, on every lane count, and leaves the rows no region's work-groups
// reach (8 rows from each region's first) as they were. A region outside the frame is refused.
TEST(EngineGBuffer, RegionsReconstructTheirPixelsAlone) {
    EngineFrame f = plane_frame(small_plane(), DepthConvention::GL, FirstRow::Bottom);
    randomise_frames(f, FrameForm::NormalTangent, 5);
    EngineGBuffer in = f.to_device(runtime()->context());
    in.light = kLamp;
    const Decoded whole = reconstruct(in, true);
    const int w = in.width, h = in.height;
    in.regions = {{0, 3, 7, 2}, {95, 3, 7, 5}, {40, 30, 1, 1}, {60, 50, 42, 14}};
    auto inside = [&](int x, int y) {
        for (const PixelRegion& r : in.regions)
            if (x >= r.x && x < r.x + r.width && y >= r.y && y < r.y + r.height) return true;
        return false;
    };
    auto reached = [&](int y) {
        for (const PixelRegion& r : in.regions)
            if (y >= r.y && y < r.y + (r.height + 7) / 8 * 8) return true;
        return false;
    };
    for (int lanes : {1, 16}) {
        auto rt = std::make_shared<Runtime>(runtime()->context(), runtime()->device(),
                                            runtime()->queue());
        rt->set_lanes(lanes);
        DeviceGBuffer out = allocate_gbuffer(*rt, w, h, true, false);
        const size_t n = in.pixels();
        const float kept = 1234.5f;
        const cl::CommandQueue& q = rt->queue();
        q.enqueueFillBuffer(out.uv, kept, 0, n * sizeof(cl_float2));
        q.enqueueFillBuffer(out.view, kept, 0, n * sizeof(cl_float4));
        q.enqueueFillBuffer(out.light, kept, 0, n * sizeof(cl_float4));
        ReconstructPass(rt).enqueue(in, out).wait();
        Decoded d;
        d.uv.resize(n);
        d.view.resize(n);
        d.light.resize(n);
        q.enqueueReadBuffer(out.uv, CL_TRUE, 0, n * sizeof(cl_float2), d.uv.data());
        q.enqueueReadBuffer(out.view, CL_TRUE, 0, n * sizeof(cl_float4), d.view.data());
        q.enqueueReadBuffer(out.light, CL_TRUE, 0, n * sizeof(cl_float4), d.light.data());
        size_t written = 0, untouched = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t k = static_cast<size_t>(y) * w + x;
                if (inside(x, y)) {
                    ++written;
                    EXPECT_EQ(0, std::memcmp(&d.uv[k], &whole.uv[k], sizeof(cl_float2)))
                        << x << ", " << y << " lanes " << lanes;
                    EXPECT_EQ(0, std::memcmp(&d.view[k], &whole.view[k], sizeof(cl_float4)))
                        << x << ", " << y << " lanes " << lanes;
                    EXPECT_EQ(0, std::memcmp(&d.light[k], &whole.light[k], sizeof(cl_float4)))
                        << x << ", " << y << " lanes " << lanes;
                } else if (!reached(y)) {
                    ++untouched;
                    EXPECT_EQ(d.view[k].s[3], kept) << x << ", " << y << " lanes " << lanes;
                    EXPECT_EQ(d.uv[k].s[0], kept) << x << ", " << y << " lanes " << lanes;
                }
            }
        EXPECT_EQ(written, 14u + 35u + 1u + 42u * 14u);
        EXPECT_GT(untouched, static_cast<size_t>(w) * 20);
    }
    for (const PixelRegion& bad : {PixelRegion{-1, 0, 4, 4}, PixelRegion{100, 0, 3, 1},
                                   PixelRegion{0, 60, 1, 5}, PixelRegion{5, 5, 0, 1}}) {
        in.regions = {{0, 0, 1, 1}, bad};
        try {
            reconstruct(in, true);
            ADD_FAILURE() << "region " << bad.x << ", " << bad.y << " accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("region 1"), std::string::npos) << e.what();
        }
    }
}

// Bit for bit: the two image paths against the buffer paths of the same stored values.
TEST(EngineGBuffer, ImagesReadTheSameAsBuffers) {
    for (Storage storage : {Storage::Float, Storage::Half}) {
        EngineFrame f = plane_frame(small_plane(), DepthConvention::ZeroToOne, FirstRow::Top);
        randomise_frames(f, FrameForm::NormalTangent, 11);
        // Depth too: PoCL misreads one-channel half images, which the pass copies to a buffer.
        f.depth.storage = f.normal.storage = f.tangent.storage = f.uv.storage = storage;
        EngineGBuffer buffers = f.to_device(runtime()->context());
        buffers.light = kLamp;
        f.depth.image = f.normal.image = f.tangent.image = f.uv.image = true;
        EngineGBuffer images = f.to_device(runtime()->context());
        images.light = kLamp;
        expect_same_bits(reconstruct(buffers, true), reconstruct(images, true),
                         storage == Storage::Half ? "half" : "float");
    }
}

// The same frame from every lane count (16 or 8 pixels per work-item on a CPU, 1 on a GPU), bit
// for bit, on a width that leaves the last block of lanes of each row partial.
TEST(EngineGBuffer, EveryLaneCountGivesTheSameFrame) {
    EngineFrame f = plane_frame(small_plane(), DepthConvention::GL, FirstRow::Top);
    randomise_frames(f, FrameForm::NormalTangent, 3);
    f.normal.storage = Storage::Snorm16;
    f.uv.storage = Storage::Half;
    EngineGBuffer in = f.to_device(runtime()->context());
    in.light = kLamp;
    std::vector<Decoded> frames;
    for (int lanes : {1, 8, 16}) {
        auto rt = std::make_shared<Runtime>(runtime()->context(), runtime()->device(),
                                            runtime()->queue());
        rt->set_lanes(lanes);
        frames.push_back(reconstruct(in, true, rt));
    }
    for (size_t k = 1; k < frames.size(); ++k)
        expect_same_bits(frames[0], frames[k],
                         "lanes 1 against " + std::to_string(k == 1 ? 8 : 16));
}

// Half and snorm16 storage against float buffers holding the values they decode to: half
// decodes exactly (bit for bit); snorm16 within the decoding's rounding, which the reference's
// bound carries (the Reconstruct suite), so here only half.
TEST(EngineGBuffer, HalfStorageEqualsTheFloatPathOfItsValues) {
    EngineFrame f = plane_frame(small_plane(), DepthConvention::Reversed, FirstRow::Top);
    randomise_frames(f, FrameForm::Quaternion, 5);
    f.normal.storage = f.uv.storage = Storage::Half;
    EngineGBuffer half = f.to_device(runtime()->context());
    for (Plane* p : {&f.normal, &f.uv}) {
        for (float& x : p->v) x = static_cast<float>(stored_value(x, Storage::Half));
        p->storage = Storage::Float;
    }
    EngineGBuffer full = f.to_device(runtime()->context());
    expect_same_bits(reconstruct(half, false), reconstruct(full, false), "half");
}

// The plane scene as the library builds it (tangent-space V per pixel, from the camera in double)
// and as an engine writes it (depth, camera, frame, uv), through the same offset pass: parallax's
// uv' agrees within what float rounding of V allows, and the same pixels are empty.
// uv' = uv + s (H(uv) - r) V.xy / V.z (kernels/methods/parallax.cl) with the same uv and H on both
// sides, so |d uv'| <= s max(r, 1 - r) |d (V.xy / V.z)|. With each component of V off by at most
// dV (the reconstruction's bound plus the library scene's own rounding to float, u), and V.z at
// least z = max(V.z, min_vz) after the grazing rule, |d (V.x / V.z)| <= dV (1 + |V.x| / z) / z,
// doubled for the ray setup's renormalisation and the grazing raise (each Lipschitz within 2 near
// the unit sphere); plus both sides' own rounding of uv', 16 u (|uv'| + 1) each.
TEST(EngineGBuffer, SameSceneBothWaysWithinRounding) {
    PlaneScene s = small_plane();
    s.width = 320;
    s.height = 180;
    s.with_light = false;
    EngineFrame f = plane_frame(s, DepthConvention::Reversed, FirstRow::Top);
    auto rt = runtime();
    const size_t n = static_cast<size_t>(s.width) * s.height;
    HeightMap map = smooth_map(128);
    PassSettings settings;
    settings.scale = 0.05f;
    settings.reference_plane = 1.0f;
    DeviceHeightField field = upload(*rt, map, settings);
    OffsetPass pass(rt, "parallax");
    auto trace = [&](const DeviceGBuffer& g, std::vector<cl_float2>& uv,
                     std::vector<cl_uint>& flags, const std::vector<cl::Event>& wait) {
        OffsetTargets t;
        t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
        t.flags = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
        pass.enqueue(g, field, settings, t, wait).wait();
        uv.resize(n);
        flags.resize(n);
        rt->queue().enqueueReadBuffer(t.uv, CL_TRUE, 0, n * sizeof(cl_float2), uv.data());
        rt->queue().enqueueReadBuffer(t.flags, CL_TRUE, 0, n * sizeof(cl_uint), flags.data());
    };
    std::vector<cl_float2> uv_engine, uv_library;
    std::vector<cl_uint> flags_engine, flags_library;
    DeviceGBuffer decoded = allocate_gbuffer(*rt, s.width, s.height, false, false);
    ReconstructPass reconstruct_pass(rt);
    cl::Event done = reconstruct_pass.enqueue(f.to_device(runtime()->context()), decoded);
    trace(decoded, uv_engine, flags_engine, {done});
    GBuffer library = make_scene(s);
    trace(upload(*rt, library), uv_library, flags_library, {});

    const double min_vz = std::sin(settings.min_elevation_deg * M_PI / 180.0);
    const double reach =
        settings.scale * std::max(settings.reference_plane, 1.0f - settings.reference_plane);
    double worst_texels = 0.0, worst_ratio = 0.0;
    size_t traced = 0;
    for (size_t k = 0; k < n; ++k) {
        const bool empty = flags_library[k] & OM_FLAG_EMPTY;
        ASSERT_EQ(empty, (flags_engine[k] & OM_FLAG_EMPTY) != 0) << "pixel " << k;
        if (empty) continue;
        ++traced;
        const Reference ref = reference(f, k, kNoLight);
        const double dv = ref.bound + kU;
        const glm::dvec3 v(library.view[k].s[0], library.view[k].s[1], library.view[k].s[2]);
        const double z = std::max(v.z, min_vz);
        for (int i = 0; i < 2; ++i) {
            const double bound = reach * 2 * dv * (1 + std::abs(v[i]) / z) / z +
                                 2 * 16 * kU * (std::abs(uv_library[k].s[i]) + 1);
            const double err = std::abs(double(uv_engine[k].s[i]) - uv_library[k].s[i]);
            ASSERT_LE(err, bound) << "pixel " << k << " uv'[" << i << "]";
            worst_ratio = std::max(worst_ratio, err / bound);
            worst_texels = std::max(worst_texels, err * map.width);
        }
    }
    EXPECT_GT(traced, n / 2);
    record_figure("engine.both_ways.uv_texels", worst_texels);
    record_figure("engine.both_ways.of_bound", worst_ratio);
    std::printf(
        "%zu pixels traced both ways: uv' differs by at most %.3g texels (%.3f of the bound)\n",
        traced, worst_texels, worst_ratio);
}

// Sky is an empty pixel; a degenerate frame or a depth that is not finite is INVALID, its uv
// passed through, like a non-finite V in the explicit G-buffer.
TEST(EngineGBuffer, SkyIsEmptyAndDegenerateFramesAreInvalid) {
    auto rt = runtime();
    const float nan = std::nanf("");
    struct Pixel {
        float depth;
        std::array<float, 4> normal, tangent;
        cl_uint flag;
    };
    const std::vector<Pixel> pixels = {
        {0.5f, {0, 0, 1, 0}, {1, 0, 0, 1}, 0},                  // a good pixel
        {1.0f, {0, 0, 1, 0}, {1, 0, 0, 1}, OM_FLAG_EMPTY},      // the far plane: sky
        {0.5f, {0, 0, 0, 0}, {1, 0, 0, 1}, OM_FLAG_INVALID},    // zero normal
        {0.5f, {0, 0, 1, 0}, {0, 0, 2, 1}, OM_FLAG_INVALID},    // tangent along the normal
        {0.5f, {0, 0, 1, 0}, {0, 0, 0, 1}, OM_FLAG_INVALID},    // zero tangent
        {0.5f, {nan, 0, 1, 0}, {1, 0, 0, 1}, OM_FLAG_INVALID},  // NaN normal
        {0.5f, {0, 0, 1, 0}, {1, nan, 0, 1}, OM_FLAG_INVALID},  // NaN tangent
        {nan, {0, 0, 1, 0}, {1, 0, 0, 1}, OM_FLAG_INVALID},     // NaN depth
    };
    EngineFrame f;
    f.width = static_cast<int>(pixels.size());
    f.height = 1;
    // Looking down -z from z = 2 with an orthographic-free perspective: identity-like camera.
    const glm::dmat4 vp =
        glm::perspectiveZO(1.0, double(f.width), 0.1, 10.0) *
        glm::lookAt(glm::dvec3(0, 0, 2), glm::dvec3(0, 0, 0), glm::dvec3(0, 1, 0));
    const glm::dmat4 inv = glm::inverse(vp);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            f.camera.inverse_view_projection[4 * c + r] = static_cast<float>(inv[c][r]);
    f.camera.eye = {0, 0, 2};
    for (const Pixel& p : pixels) {
        f.depth.v.push_back(p.depth);
        f.normal.v.insert(f.normal.v.end(), p.normal.begin(), p.normal.end());
        f.tangent.v.insert(f.tangent.v.end(), p.tangent.begin(), p.tangent.end());
        f.uv.v.insert(f.uv.v.end(), {0.25f, 0.75f});
    }
    for (FrameForm form : {FrameForm::NormalTangent, FrameForm::Quaternion}) {
        EngineFrame g = f;
        g.form = form;
        if (form == FrameForm::Quaternion)  // the same cases as quaternions: identity, zero, NaN
            for (size_t k = 0; k < pixels.size(); ++k) {
                const bool bad = pixels[k].flag == OM_FLAG_INVALID && !std::isnan(pixels[k].depth);
                const std::array<float, 4> q = !bad    ? std::array<float, 4>{0, 0, 0, 1}
                                               : k % 2 ? std::array<float, 4>{0, 0, 0, 0}
                                                       : std::array<float, 4>{0, nan, 0, 1};
                std::copy(q.begin(), q.end(), g.normal.v.begin() + 4 * k);
            }
        DeviceGBuffer decoded = allocate_gbuffer(*rt, g.width, 1, false, false);
        ReconstructPass pass(rt);
        cl::Event done = pass.enqueue(g.to_device(runtime()->context()), decoded);
        OffsetPass offset(rt, "pom");
        OffsetTargets t;
        t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, pixels.size() * sizeof(cl_float2));
        t.flags = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, pixels.size() * sizeof(cl_uint));
        HeightMap map = smooth_map(32);
        PassSettings settings;
        offset.enqueue(decoded, upload(*rt, map, settings), settings, t, {done}).wait();
        std::vector<cl_float2> uv(pixels.size());
        std::vector<cl_uint> flags(pixels.size());
        rt->queue().enqueueReadBuffer(t.uv, CL_TRUE, 0, uv.size() * sizeof(cl_float2), uv.data());
        rt->queue().enqueueReadBuffer(t.flags, CL_TRUE, 0, flags.size() * 4, flags.data());
        for (size_t k = 0; k < pixels.size(); ++k) {
            const cl_uint kinds = OM_FLAG_EMPTY | OM_FLAG_INVALID;
            EXPECT_EQ(pixels[k].flag, flags[k] & kinds) << "pixel " << k;
            if (pixels[k].flag == OM_FLAG_INVALID) {
                EXPECT_EQ(0.25f, uv[k].s[0]) << "pixel " << k;
                EXPECT_EQ(0.75f, uv[k].s[1]) << "pixel " << k;
            }
        }
    }
}

// A G-buffer whose buffers or images have the wrong size, type, format or context: an Error
// naming the input, before anything is enqueued.
TEST(EngineGBuffer, WrongInputsAreRefusedByName) {
    auto rt = runtime();
    const cl::Context& context = rt->context();
    EngineFrame f = plane_frame(small_plane(), DepthConvention::ZeroToOne, FirstRow::Top);
    const EngineGBuffer good = f.to_device(runtime()->context());
    DeviceGBuffer out = allocate_gbuffer(*rt, f.width, f.height, false, false);
    ReconstructPass pass(rt);
    auto error = [&](const EngineGBuffer& in, const DeviceGBuffer& o) {
        return error_of([&] { pass.enqueue(in, o).wait(); });
    };
    ASSERT_EQ(error(good, out), "");
    const size_t n = good.pixels();

    EngineGBuffer in = good;
    in.normal.buffer = cl::Buffer(context, CL_MEM_READ_ONLY, n * 4 * 2);  // half-size for float
    EXPECT_TRUE(contains(error(in, out), "the engine G-buffer's normal buffer holds " +
                                             std::to_string(n * 8) + " bytes; it needs " +
                                             std::to_string(n * 16)));
    in = good;
    in.uv.storage = Storage::Half;  // the right size for half: accepted
    EXPECT_EQ(error(in, out), "");
    in = good;
    in.depth = Input();
    EXPECT_TRUE(contains(error(in, out), "the engine G-buffer's depth is not bound"));
    in = good;
    in.tangent.image = cl::Image2D(context, CL_MEM_READ_ONLY, cl::ImageFormat(CL_RGBA, CL_FLOAT),
                                   f.width, f.height);
    EXPECT_TRUE(contains(error(in, out), "the engine G-buffer's tangent has both a buffer and"));
    in.tangent.buffer = cl::Buffer();
    EXPECT_EQ(error(in, out), "");
    in.tangent.image = cl::Image2D(context, CL_MEM_READ_ONLY, cl::ImageFormat(CL_RGBA, CL_FLOAT),
                                   f.width / 2, f.height);
    EXPECT_TRUE(contains(error(in, out),
                         "the engine G-buffer's tangent image is 51x64; the "
                         "G-buffer is 102x64"));
    in.tangent.image =
        cl::Image2D(context, CL_MEM_READ_ONLY, cl::ImageFormat(CL_R, CL_FLOAT), f.width, f.height);
    EXPECT_TRUE(contains(error(in, out), "the engine G-buffer's tangent image needs 4 channel(s)"));
    in.tangent.image = cl::Image2D(context, CL_MEM_READ_ONLY,
                                   cl::ImageFormat(CL_RGBA, CL_SIGNED_INT16), f.width, f.height);
    EXPECT_TRUE(contains(error(in, out), "the engine G-buffer's tangent image's channel type"));
    cl::Context other(rt->device());
    in = good;
    in.uv.buffer = cl::Buffer(other, CL_MEM_READ_ONLY, n * 8);
    EXPECT_TRUE(contains(error(in, out), "the engine G-buffer's uv buffer belongs to another"));
    in = good;
    in.camera.eye[1] = std::nanf("");
    EXPECT_TRUE(contains(error(in, out), "inverse view-projection and eye must be finite"));
    in = good;
    in.light.kind = LightKind::Directional;
    EXPECT_TRUE(contains(error(in, out), "the reconstructed G-buffer's light buffer is a null"));
    in.light.vector = {0, 0, 0};
    EXPECT_TRUE(contains(error(in, allocate_gbuffer(*rt, f.width, f.height, true, false)),
                         "the engine light's direction is the zero vector"));
    EXPECT_TRUE(contains(error(good, allocate_gbuffer(*rt, f.width, f.height / 2, false, false)),
                         "the reconstructed G-buffer is 102x32; the engine G-buffer is 102x64"));
}

// prepare builds the variant and the driver's code: the first frame after it builds nothing.
TEST(EngineGBuffer, PrepareLeavesNothingToCompile) {
    auto rt =
        std::make_shared<Runtime>(runtime()->context(), runtime()->device(), runtime()->queue());
    EngineFrame f = plane_frame(small_plane(), DepthConvention::GL, FirstRow::Top);
    f.normal.image = true;
    EngineGBuffer in = f.to_device(runtime()->context());
    DeviceGBuffer out = allocate_gbuffer(*rt, f.width, f.height, false, false);
    ReconstructPass pass(rt);
    pass.prepare(in, out);
    const size_t built = rt->programs_built();
    EXPECT_EQ(built, 1u);
    pass.enqueue(in, out).wait();
    EXPECT_EQ(rt->programs_built(), built);
}

// The engine form of a G-buffer file: written and read back exactly (both frame forms, the
// camera and the light in the header), and load_gbuffer reconstructs it within the derived bound.
TEST(EngineGBuffer, EngineFormFilesRoundTrip) {
    const std::string dir = ::testing::TempDir();
    PlaneScene s = small_plane();
    EngineScene e = make_engine_scene(s, DepthConvention::GL, FirstRow::Bottom);
    e.light = {LightKind::Point, {0.25f, -1.5f, 0.75f}};
    for (FrameForm form : {FrameForm::NormalTangent, FrameForm::Quaternion}) {
        EngineScene w = e;
        if (form == FrameForm::Quaternion) {  // the plane's frame: the identity rotation
            w.frame = form;
            w.tangent.clear();
            for (size_t k = 0; k < w.pixels(); ++k)
                std::copy_n(std::array<float, 4>{0, 0, 0, 1}.begin(), 4, w.normal.begin() + 4 * k);
        }
        const std::string path = dir + "/engine_form.exr";
        save_engine_gbuffer(path, w);
        const EngineScene r = load_engine_gbuffer(path);
        EXPECT_EQ(r.camera.inverse_view_projection, w.camera.inverse_view_projection);
        EXPECT_EQ(r.camera.eye, w.camera.eye);
        EXPECT_EQ(r.camera.depth, w.camera.depth);
        EXPECT_EQ(r.camera.first_row, w.camera.first_row);
        EXPECT_EQ(r.light.kind, w.light.kind);
        EXPECT_EQ(r.light.vector, w.light.vector);
        EXPECT_EQ(r.frame, w.frame);
        EXPECT_EQ(0, std::memcmp(r.depth.data(), w.depth.data(), w.depth.size() * 4));
        EXPECT_EQ(0, std::memcmp(r.uv.data(), w.uv.data(), w.uv.size() * 4));  // NaN sky too
        EXPECT_EQ(r.normal, w.normal);
        EXPECT_EQ(r.tangent, w.tangent);

        // Through load_gbuffer: the reconstruct pass's V and L, within the reference's bound.
        const GBuffer g = load_gbuffer(path, kDefaultReadLimitBytes, runtime());
        EngineFrame f = plane_frame(s, DepthConvention::GL, FirstRow::Bottom);
        f.form = form;
        f.normal.v = w.normal;
        for (size_t k = 0; k < g.pixels(); ++k) {
            const Reference ref = reference(f, k, w.light);
            if (ref.sky) {
                EXPECT_TRUE(std::isnan(g.uv[k].s[0])) << k;
                continue;
            }
            for (int i = 0; i < 3; ++i) {
                ASSERT_LE(std::abs(g.view[k].s[i] - ref.v_ts[i]), ref.bound) << k;
                ASSERT_LE(std::abs(g.light[k].s[i] - ref.l_ts[i]), ref.l_bound) << k;
            }
        }
    }
}

TEST(EngineGBuffer, EngineFormFileErrorsNameTheAttribute) {
    const std::string path = ::testing::TempDir() + "/engine_form_bad.exr";
    EngineScene e = make_engine_scene(small_plane(), DepthConvention::ZeroToOne);
    save_engine_gbuffer(path, e);
    ASSERT_EQ(error_of([&] { load_engine_gbuffer(path); }), "");
    // Rewrite the header with one attribute spoiled, the pixels kept.
    auto spoil = [&](const std::string& name, const std::string& value) {
        auto in = OIIO::ImageInput::open(path);
        OIIO::ImageSpec spec = in->spec();
        std::vector<float> data(spec.image_pixels() * spec.nchannels);
        in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data());
        in->close();
        spec.attribute(name, value);
        const std::string bad = ::testing::TempDir() + "/engine_form_spoilt.exr";
        auto out = OIIO::ImageOutput::create(bad);
        out->open(bad, spec);
        out->write_image(OIIO::TypeDesc::FLOAT, data.data());
        out->close();
        return error_of([&] { load_gbuffer(bad, kDefaultReadLimitBytes, runtime()); });
    };
    EXPECT_TRUE(contains(spoil("offsetmap:depth", "d3d"),
                         "attribute offsetmap:depth must be gl, zero-one or reversed, got 'd3d'"));
    EXPECT_TRUE(contains(spoil("offsetmap:eye", "1 2"),
                         "attribute offsetmap:eye must hold 3 numbers, got '1 2'"));
    EXPECT_TRUE(
        contains(spoil("offsetmap:inverseViewProjection", "1 0 0 nan 0 1 0 0 0 0 1 0 0 0 0 1"),
                 "attribute offsetmap:inverseViewProjection"));
    EXPECT_TRUE(contains(spoil("offsetmap:light", "spot 0 0 1"),
                         "attribute offsetmap:light must start with directional or point"));
}

// An engine file's curvature reaches the pass: the reconstructed G-buffer carries it per pixel as
// it is, the stretch beside it (1 where the file has none).
TEST(EngineGBuffer, CurvatureReachesTheReconstructedGBuffer) {
    EngineScene e = make_engine_scene(small_plane(), DepthConvention::GL);
    for (size_t k = 0; k < e.pixels(); ++k)
        e.curvature.insert(e.curvature.end(), {0.5f * k, -1.0f, 2.0f});
    const std::string path = ::testing::TempDir() + "/engine_curvature_pass.exr";
    for (bool stretch : {false, true}) {
        if (stretch) e.uv_stretch.assign(e.pixels(), 1.25f);
        save_engine_gbuffer(path, e);
        const GBuffer gb = load_gbuffer(path, kDefaultReadLimitBytes, runtime());
        ASSERT_EQ(gb.curvature.size(), e.pixels());
        for (size_t k = 0; k < e.pixels(); ++k) {
            for (int a = 0; a < 3; ++a) EXPECT_EQ(gb.curvature[k].s[a], e.curvature[3 * k + a]);
            EXPECT_EQ(gb.curvature[k].s[3], stretch ? 1.25f : 1.0f);
        }
    }
}

// The curvature channels: all three or none, and finite; each error names the file.
TEST(EngineGBuffer, CurvatureChannelsAreAllOrNoneAndFinite) {
    EngineScene e = make_engine_scene(small_plane(), DepthConvention::ZeroToOne);
    e.curvature.assign(3 * e.pixels(), 0.25f);
    const std::string path = ::testing::TempDir() + "/engine_curvature.exr";
    save_engine_gbuffer(path, e);
    EXPECT_EQ(load_engine_gbuffer(path).curvature, e.curvature);
    e.curvature[3 * 5 + 1] = std::nanf("");
    save_engine_gbuffer(path, e);
    EXPECT_TRUE(contains(error_of([&] { load_engine_gbuffer(path); }),
                         "engine_curvature.exr': channel kuv is not finite at pixel (5, 0)"));
    // The uv's stretch beside it: kept, and finite.
    e.curvature.assign(3 * e.pixels(), 0.25f);
    e.uv_stretch.assign(e.pixels(), 1.5f);
    save_engine_gbuffer(path, e);
    EXPECT_EQ(load_engine_gbuffer(path).uv_stretch, e.uv_stretch);
    e.uv_stretch[7] = INFINITY;
    save_engine_gbuffer(path, e);
    EXPECT_TRUE(contains(error_of([&] { load_engine_gbuffer(path); }),
                         "engine_curvature.exr': channel stretch is not finite at pixel (7, 0)"));
    e.uv_stretch.clear();
    // The same file less its last channel (kvv).
    save_engine_gbuffer(path, e);
    auto in = OIIO::ImageInput::open(path);
    OIIO::ImageSpec spec = in->spec();
    std::vector<float> data(spec.image_pixels() * spec.nchannels);
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, data.data());
    in->close();
    const auto drop = std::find(spec.channelnames.begin(), spec.channelnames.end(), "kvv");
    ASSERT_NE(drop, spec.channelnames.end());
    const int c = static_cast<int>(drop - spec.channelnames.begin());
    OIIO::ImageSpec less = spec;
    less.nchannels = spec.nchannels - 1;
    less.channelnames.erase(less.channelnames.begin() + c);
    less.channelformats.clear();
    std::vector<float> kept;
    for (size_t k = 0; k < data.size(); ++k)
        if (static_cast<int>(k % spec.nchannels) != c) kept.push_back(data[k]);
    const std::string bad = ::testing::TempDir() + "/engine_curvature_two.exr";
    auto out = OIIO::ImageOutput::create(bad);
    out->open(bad, less);
    out->write_image(OIIO::TypeDesc::FLOAT, kept.data());
    out->close();
    EXPECT_TRUE(contains(error_of([&] { load_engine_gbuffer(bad); }),
                         "engine_curvature_two.exr': the curvature needs all three channels"));
}

}  // namespace
}  // namespace omtest
namespace omtest {
namespace {

// A directional light's view of the plane z = 0 (orthographic, as a shadow map sees it): every
// pixel's V is the one direction toward the light, in the plane's tangent frame (T = +x, B = +y,
// N = +z: tangent space is world space), and the file keeps the projection.
TEST(EngineGBuffer, OrthographicViewHasOneViewDirection) {
    const glm::dvec3 L = glm::normalize(glm::dvec3(0.6, -0.35, 0.45));
    const glm::dmat4 view = glm::lookAt(4.0 * L, glm::dvec3(0), glm::dvec3(0, 0, 1));
    const glm::dmat4 inv = glm::inverse(glm::orthoZO(-2.0, 2.0, -1.5, 1.5, 0.5, 8.0) * view);
    EngineScene e;
    e.width = 24;
    e.height = 18;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            e.camera.inverse_view_projection[4 * c + r] = static_cast<float>(inv[c][r]);
    e.camera.eye = {float(L.x), float(L.y), float(L.z)};
    e.camera.orthographic = true;
    e.camera.depth = DepthConvention::ZeroToOne;
    e.camera.first_row = FirstRow::Top;
    for (int y = 0; y < e.height; ++y)
        for (int x = 0; x < e.width; ++x) {
            // The pixel's ray from NDC z 0 to 1 meets z = 0 at the fraction s: its window depth.
            const double nx = 2.0 * (x + 0.5) / e.width - 1.0,
                         ny = 1.0 - 2.0 * (y + 0.5) / e.height;
            const glm::dvec4 a = inv * glm::dvec4(nx, ny, 0, 1), b = inv * glm::dvec4(nx, ny, 1, 1);
            const double s = a.z / (a.z - b.z);
            const glm::dvec3 p = glm::dvec3(a) + s * (glm::dvec3(b) - glm::dvec3(a));
            e.depth.push_back(static_cast<float>(s));
            e.normal.insert(e.normal.end(), {0, 0, 1, 0});
            e.tangent.insert(e.tangent.end(), {1, 0, 0, 1});
            e.uv.insert(e.uv.end(), {float(p.x), float(p.y)});
        }
    const std::string path = ::testing::TempDir() + "/engine_orthographic.exr";
    save_engine_gbuffer(path, e);
    const EngineScene r = load_engine_gbuffer(path);
    EXPECT_TRUE(r.camera.orthographic);
    const GBuffer g = reconstruct(runtime(), r);
    double worst = 0;
    for (size_t k = 0; k < g.pixels(); ++k)
        for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(g.view[k].s[i] - L[i]));
    EXPECT_LT(worst, 1e-6) << "one direction: float rounding of L alone";
    // The same file seen as a perspective camera at the point L: views fan out.
    EngineScene p = r;
    p.camera.orthographic = false;
    const GBuffer fan = reconstruct(runtime(), p);
    EXPECT_GT(std::abs(fan.view[0].s[0] - fan.view[g.pixels() - 1].s[0]), 0.1);
    EngineScene zero = r;
    zero.camera.eye = {0, 0, 0};
    EXPECT_TRUE(contains(error_of([&] { reconstruct(runtime(), zero); }), "is the zero vector"));
}

}  // namespace
}  // namespace omtest
namespace omtest {
namespace {

// A spot light is a point light within its cone: the light plane's L the point light's bits, its
// w the cone's share of the light's absence within the double reference's bound (the rate of the
// smoothstep over the cone's span times L's bound); the shade pass dims the light by it, so the
// pixels inside the inner cone shade as under the point light, bit for bit, and those outside the
// outer one as with no diffuse or specular term, bit for bit. A cone the pass cannot take is
// refused.
TEST(EngineGBuffer, SpotLightIsAPointLightWithinItsCone) {
    EngineFrame f = plane_frame(small_plane(), DepthConvention::ZeroToOne, FirstRow::Top);
    EngineGBuffer in = f.to_device(runtime()->context());
    const EngineLight point{LightKind::Point, {1.0f, -0.3f, 1.0f}};
    EngineLight spot = point;
    spot.kind = LightKind::Spot;
    spot.axis = {0.1f, 0.0f, -1.0f};
    spot.cone_inner = 0.25f;
    spot.cone_outer = 0.45f;
    in.light = point;
    const Decoded p = reconstruct(in, true);
    in.light = spot;
    const Decoded s = reconstruct(in, true);
    const size_t n = in.pixels();
    size_t whole = 0, fading = 0, none = 0;
    double worst = 0.0;
    for (size_t k = 0; k < n; ++k) {
        ASSERT_EQ(std::memcmp(&p.light[k], &s.light[k], 3 * sizeof(float)), 0) << k;
        ASSERT_EQ(p.light[k].s[3], 0.0f) << k;
        const Reference ref = reference(f, k, spot);
        if (ref.sky) continue;
        const double w = s.light[k].s[3], bound = ref.cone_slope * 4.0 * ref.l_bound + 1e-6;
        ASSERT_LE(std::abs(w - ref.cone_dark), bound) << k;
        worst = std::max(worst, std::abs(w - ref.cone_dark) / bound);
        whole += w == 0.0, none += w == 1.0, fading += w > 0.0 && w < 1.0;
    }
    std::printf("spot: %zu pixels whole, %zu fading, %zu outside; worst w %.3f of its bound\n",
                whole, fading, none, worst);
    EXPECT_GT(whole, n / 20);
    EXPECT_GT(fading, n / 20);
    EXPECT_GT(none, n / 20);

    // The shading: a flat field, the G-buffer's light as reconstructed.
    PassSettings settings;
    settings.scale = 0.05f;
    HeightMap flat;
    flat.width = flat.height = 8;
    flat.h.assign(64, 0.5f);
    const DeviceHeightField field = upload(*runtime(), flat, settings);
    auto shade = [&](const Decoded& d, const ShadeSettings& how) {
        DeviceGBuffer g = allocate_gbuffer(*runtime(), in.width, in.height, true, false);
        const cl::CommandQueue& q = runtime()->queue();
        q.enqueueWriteBuffer(g.uv, CL_TRUE, 0, n * sizeof(cl_float2), d.uv.data());
        q.enqueueWriteBuffer(g.view, CL_TRUE, 0, n * sizeof(cl_float4), d.view.data());
        q.enqueueWriteBuffer(g.light, CL_TRUE, 0, n * sizeof(cl_float4), d.light.data());
        const cl::Buffer rgba(runtime()->context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4));
        ShadeInputs inputs;
        inputs.uv = g.uv;
        ShadePass(runtime()).enqueue(g, field, inputs, settings, how, {rgba}).wait();
        std::vector<cl_float4> c(n);
        q.enqueueReadBuffer(rgba, CL_TRUE, 0, n * sizeof(cl_float4), c.data());
        return c;
    };
    ShadeSettings dark;
    dark.diffuse = dark.specular = 0.0f;
    const std::vector<cl_float4> under_point = shade(p, {}), under_spot = shade(s, {}),
                                 ambient = shade(s, dark);
    size_t compared = 0;
    for (size_t k = 0; k < n; ++k) {
        const float w = s.light[k].s[3];
        if (w == 0.0f) {
            ASSERT_EQ(std::memcmp(&under_spot[k], &under_point[k], sizeof(cl_float4)), 0) << k;
            ++compared;
        } else if (w == 1.0f) {
            ASSERT_EQ(std::memcmp(&under_spot[k], &ambient[k], sizeof(cl_float4)), 0) << k;
            ++compared;
        }
    }
    EXPECT_EQ(compared, n - fading);

    for (const auto& [inner, outer] : {std::pair{0.5f, 0.4f}, {-0.1f, 0.3f}, {0.2f, 1.6f}}) {
        spot.cone_inner = inner;
        spot.cone_outer = outer;
        in.light = spot;
        EXPECT_TRUE(contains(error_of([&] { reconstruct(in, true); }), "0 <= inner <= outer"));
    }
    spot.cone_inner = 0.2f;
    spot.axis = {0, 0, 0};
    in.light = spot;
    EXPECT_TRUE(contains(error_of([&] { reconstruct(in, true); }), "axis"));
}

}  // namespace
}  // namespace omtest
