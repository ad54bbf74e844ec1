// The engine-shaped G-buffer: depth, camera, tangent frame and uv, in buffers or images, float,
// half or snorm16, reconstructed into tangent-space V and L on the device.
#include <Imath/half.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "support.hpp"

namespace omtest {
namespace {

constexpr double kU = 1.0 / (1 << 24);  // unit roundoff of float

// ---- An engine's frame, in double, and its storage as the engine would write it. ----

// Values per pixel as floats before storage, and how the engine stores them.
struct Plane {
    int values = 1;
    std::vector<float> v;  // pixels * values
    Storage storage = Storage::Float;
    bool image = false;
};

// The value the device reads back from `x` stored as `s` (exact for float and half; the unorm and
// snorm forms are the nearest code, decoded here in double: the device's division may differ from
// it by its rounding, which the bounds below carry).
double stored_value(float x, Storage s) {
    switch (s) {
        case Storage::Half:
            return static_cast<float>(Imath::half(x));
        case Storage::Snorm16:
            return std::max(std::lround(std::clamp(x, -1.0f, 1.0f) * 32767.0) / 32767.0, -1.0);
        case Storage::Unorm16:
            return std::lround(std::clamp(x, 0.0f, 1.0f) * 65535.0) / 65535.0;
        case Storage::Unorm8:
            return std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0) / 255.0;
        case Storage::Float:
            break;
    }
    return x;
}

// Relative error of the device's decoding of one stored value (OpenCL's division: 2.5 ulp, an ulp
// being at most 2 u of the value; exact for float and half).
double decode_error(Storage s) {
    return (s == Storage::Float || s == Storage::Half) ? 0.0 : 5.0 * kU;
}

std::vector<unsigned char> encode(const Plane& p) {
    const size_t bytes = storage_bytes(p.storage);
    std::vector<unsigned char> out(p.v.size() * bytes);
    for (size_t k = 0; k < p.v.size(); ++k) {
        const float x = p.v[k];
        unsigned char* dst = out.data() + k * bytes;
        if (p.storage == Storage::Float) {
            std::memcpy(dst, &x, 4);
        } else if (p.storage == Storage::Half) {
            uint16_t bits = Imath::half(x).bits();
            std::memcpy(dst, &bits, 2);
        } else if (p.storage == Storage::Snorm16) {
            int16_t c = static_cast<int16_t>(std::lround(std::clamp(x, -1.0f, 1.0f) * 32767.0));
            std::memcpy(dst, &c, 2);
        } else if (p.storage == Storage::Unorm16) {
            uint16_t c = static_cast<uint16_t>(std::lround(std::clamp(x, 0.0f, 1.0f) * 65535.0));
            std::memcpy(dst, &c, 2);
        } else {
            *dst = static_cast<unsigned char>(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0));
        }
    }
    return out;
}

Plane with_values(int values) {
    Plane p;
    p.values = values;
    return p;
}

cl_channel_type image_type(Storage s) {
    switch (s) {
        case Storage::Half:
            return CL_HALF_FLOAT;
        case Storage::Snorm16:
            return CL_SNORM_INT16;
        case Storage::Unorm16:
            return CL_UNORM_INT16;
        case Storage::Unorm8:
            return CL_UNORM_INT8;
        case Storage::Float:
            break;
    }
    return CL_FLOAT;
}

// Whether the device reads an image of the plane's format (rusticl over llvmpipe has no
// CL_RGBA / CL_SNORM_INT16).
bool device_has_image_format(const Plane& p) {
    std::vector<cl::ImageFormat> formats;
    runtime()->context().getSupportedImageFormats(CL_MEM_READ_ONLY, CL_MEM_OBJECT_IMAGE2D,
                                                  &formats);
    const cl_channel_order order = p.values == 1 ? CL_R : CL_RGBA;
    for (const cl::ImageFormat& f : formats)
        if (f.image_channel_order == order && f.image_channel_data_type == image_type(p.storage))
            return true;
    return false;
}

Input to_device(const Plane& p, int w, int h) {
    const cl::Context& context = runtime()->context();
    std::vector<unsigned char> bytes = encode(p);
    Input in;
    in.storage = p.storage;
    if (!p.image) {
        in.buffer = cl::Buffer(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes.size(),
                               bytes.data());
        return in;
    }
    // One channel, or four (PoCL has no two-channel images; uv takes the first two of RGBA).
    const cl_channel_order order = p.values == 1 ? CL_R : CL_RGBA;
    if (p.values == 2) {
        Plane four = p;
        four.values = 4;
        four.v.assign(p.v.size() * 2, 0.0f);
        for (size_t k = 0; k < p.v.size() / 2; ++k) {
            four.v[4 * k] = p.v[2 * k];
            four.v[4 * k + 1] = p.v[2 * k + 1];
        }
        bytes = encode(four);
    }
    in.image = cl::Image2D(context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                           cl::ImageFormat(order, image_type(p.storage)), w, h, 0, bytes.data());
    return in;
}

// An engine's frame: its planes as floats before storage, and how each is stored.
struct EngineFrame {
    int width = 0, height = 0;
    EngineCamera camera;
    Plane depth = with_values(1), normal = with_values(4), tangent = with_values(4),
          uv = with_values(2);
    FrameForm form = FrameForm::NormalTangent;

    EngineGBuffer to_device() const {
        EngineGBuffer g;
        g.width = width;
        g.height = height;
        g.camera = camera;
        g.frame = form;
        g.depth = omtest::to_device(depth, width, height);
        g.normal = omtest::to_device(normal, width, height);
        if (form == FrameForm::NormalTangent) g.tangent = omtest::to_device(tangent, width, height);
        g.uv = omtest::to_device(uv, width, height);
        return g;
    }
};

// The plane scene as the library's engine scene writes it.
EngineFrame plane_frame(const PlaneScene& s, DepthConvention depth, FirstRow first_row) {
    EngineScene e = make_engine_scene(s, depth, first_row);
    EngineFrame f;
    f.width = e.width;
    f.height = e.height;
    f.camera = e.camera;
    f.depth.v = e.depth;
    f.normal.v = e.normal;
    f.tangent.v = e.tangent;
    f.uv.v = e.uv;
    return f;
}

// Random tangent frames on the plane frame's pixels: unnormalised, the tangent leaning toward the
// normal, half of them mirrored (or quaternions of random length and sign carrying it).
void randomise_frames(EngineFrame& f, FrameForm form, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> gauss;
    std::uniform_real_distribution<double> uniform(0.5, 2.0);
    f.form = form;
    for (size_t k = 0; k < f.depth.v.size(); ++k) {
        glm::dquat q = glm::normalize(glm::dquat(gauss(rng), gauss(rng), gauss(rng), gauss(rng)));
        if (std::abs(q.w) < 0.05) {  // keep the handedness sign through 16 bits
            q.w = 0.05;
            q = glm::normalize(q);
        }
        const bool mirrored = rng() & 1;
        const glm::dmat3 r = glm::mat3_cast(q);
        float* n = &f.normal.v[4 * k];
        float* t = &f.tangent.v[4 * k];
        if (form == FrameForm::Quaternion) {
            const double len = uniform(rng), sign = (q.w < 0) == mirrored ? 1.0 : -1.0;
            const double c[4] = {q.x, q.y, q.z, q.w};
            for (int i = 0; i < 4; ++i) n[i] = static_cast<float>(sign * len * c[i] * 0.45);
            continue;
        }
        const double ln = uniform(rng), lt = uniform(rng) * 0.5, lean = 0.6 * gauss(rng);
        for (int i = 0; i < 3; ++i) {
            n[i] = static_cast<float>(ln * r[2][i] * 0.5);
            t[i] = static_cast<float>(lt * (r[0][i] + lean * r[2][i]) * 0.5);
        }
        n[3] = 0.0f;
        t[3] = mirrored ? -1.0f : 1.0f;
    }
}

// ---- The reference: the kernel's formula in double, from the stored values, and its bound. ----

struct Reference {
    bool sky = false, valid = true;
    glm::dvec3 v_ts{0.0}, l_ts{0.0};
    double bound = 0.0;  // on each component of V (and of L for a directional light)
    double l_bound = 0.0;
};

glm::dvec4 stored4(const Plane& p, size_t k) {
    glm::dvec4 out(0.0);
    for (int i = 0; i < p.values; ++i) out[i] = stored_value(p.v[p.values * k + i], p.storage);
    return out;
}

// Forward error analysis of kernels/gbuffer/reconstruct.cl in float (u = 2^-24; +, -, * round
// within u; OpenCL's division within 2.5 ulp and rsqrt within 2 ulp, an ulp at most 2 u of the
// value; dot products of n terms within gamma_n = n u / (1 - n u) of the sum of |terms|), to first
// order, per pixel:
//   ndc x, y: (2x + 1) / W - 1, within 6 u; z: d (or 2 d - 1), within 2 u plus d's decoding error.
//   c = M (ndc, 1): |dc_i| <= sum_j |M_ij| |d ndc_j| + gamma_4 sum_j |M_ij| |ndc_j|.
//   p = c.xyz / c.w: |dp_i| <= (|dc_i| + |p_i| |dc_w|) / |c_w| + 5 u |p_i|.
//   e = eye - p: |de_i| <= |dp_i| + u |e_i|; V = e rsqrt(e.e): |dV| <= |de| / |e| + 8 u (the
//   normalisation's derivative has norm 1 / |e|; 1.5 u from the dot, 4 u from rsqrt, u the
//   product). Frame: n = n rsqrt(n.n): |dn| <= decode + 8 u; t_p = t - n (n.t): |dt_p| <= (2 |dn| +
//   6 u + decode) |t|; t = t_p / |t_p|: |dt| <= |dt_p| / |t_p| + 8 u; b = n x t: |db| <= |dn| +
//   |dt| + 6 u. Quaternion: |dq| <= decode + 8 u; each entry of the rotation is a quadratic form in
//   q whose gradient has norm at most 4, plus 4 roundings of values <= 2: |dcolumn| <= sqrt 3 (4
//   |dq| + 8 u). V_ts_i = V . f_i: |dV_ts_i| <= |dV| + |df_i| + gamma_3.
Reference reference(const EngineFrame& f, size_t k, const EngineLight& light) {
    Reference out;
    const int x = static_cast<int>(k % f.width), y = static_cast<int>(k / f.width);
    const double d = stored_value(f.depth.v[k], f.depth.storage);
    const auto& cam = f.camera;
    out.sky = cam.depth == DepthConvention::Reversed ? d <= 0.0 : d >= 1.0;
    if (out.sky) return out;
    const double u = kU, g3 = 3 * u / (1 - 3 * u), g4 = 4 * u / (1 - 4 * u);
    const double row = static_cast<int>(cam.first_row);
    const glm::dvec4 ndc((2.0 * x + 1) / f.width - 1.0, row * (1.0 - (2.0 * y + 1) / f.height),
                         cam.depth == DepthConvention::GL ? 2 * d - 1 : d, 1.0);
    const double dz_decode =
        decode_error(f.depth.storage) * d * (cam.depth == DepthConvention::GL ? 2 : 1);
    const double dndc[4] = {6 * u, 6 * u, 2 * u + dz_decode, 0.0};
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = cam.inverse_view_projection[4 * c + r];
    const glm::dvec4 c = m * ndc;
    double dc[4];
    for (int i = 0; i < 4; ++i) {
        double sum = 0.0, mag = 0.0;
        for (int j = 0; j < 4; ++j) {
            sum += std::abs(m[j][i]) * dndc[j];
            mag += std::abs(m[j][i]) * std::abs(ndc[j]);
        }
        dc[i] = sum + g4 * mag;
    }
    const glm::dvec3 p = glm::dvec3(c) / c.w;
    const glm::dvec3 eye(cam.eye[0], cam.eye[1], cam.eye[2]);
    const glm::dvec3 e = eye - p;
    double de2 = 0.0, dp2 = 0.0;
    for (int i = 0; i < 3; ++i) {
        const double dp = (dc[i] + std::abs(p[i]) * dc[3]) / std::abs(c.w) + 5 * u * std::abs(p[i]);
        const double dei = dp + u * std::abs(e[i]);
        dp2 += dp * dp;
        de2 += dei * dei;
    }
    const glm::dvec3 v = glm::normalize(e);
    const double dv = std::sqrt(de2) / glm::length(e) + 8 * u;

    glm::dvec3 t, b, n;
    double df[3];
    const glm::dvec4 fa = stored4(f.normal, k);
    if (f.form == FrameForm::Quaternion) {
        const glm::dvec4 q = fa / glm::length(fa);
        const glm::dmat3 r = glm::mat3_cast(glm::dquat(q.w, q.x, q.y, q.z));
        t = r[0];
        b = fa.w < 0 ? -r[1] : r[1];
        n = r[2];
        const double dq = decode_error(f.normal.storage) + 8 * u;
        df[0] = df[1] = df[2] = std::sqrt(3.0) * (4 * dq + 8 * u);
    } else {
        const glm::dvec4 ta = stored4(f.tangent, k);
        n = glm::normalize(glm::dvec3(fa));
        const glm::dvec3 tp = glm::dvec3(ta) - n * glm::dot(n, glm::dvec3(ta));
        t = glm::normalize(tp);
        b = glm::cross(n, t) * (ta.w < 0 ? -1.0 : 1.0);
        const double dn = decode_error(f.normal.storage) + 8 * u;
        const double dtp =
            (2 * dn + 6 * u + decode_error(f.tangent.storage)) * glm::length(glm::dvec3(ta));
        const double dt = dtp / glm::length(tp) + 8 * u;
        df[0] = dt;
        df[1] = dn + dt + 6 * u;
        df[2] = dn;
    }
    out.v_ts = {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)};
    double worst = 0.0;
    for (int i = 0; i < 3; ++i) worst = std::max(worst, dv + df[i] + g3);
    out.bound = worst;
    if (light.kind != LightKind::None) {
        glm::dvec3 l(light.vector[0], light.vector[1], light.vector[2]);
        l = light.kind == LightKind::Point ? glm::normalize(l - p) : glm::normalize(l);
        out.l_ts = {glm::dot(l, t), glm::dot(l, b), glm::dot(l, n)};
        // A directional light's error is its normalisation's; a point light's adds p's, as V's.
        const double dl =
            light.kind == LightKind::Point
                ? (std::sqrt(dp2) + u * glm::length(l)) /
                          glm::length(
                              glm::dvec3(light.vector[0], light.vector[1], light.vector[2]) - p) +
                      8 * u
                : 8 * u;
        out.l_bound = dl + std::max({df[0], df[1], df[2]}) + g3;
    }
    return out;
}

// Reads the reconstructed G-buffer back.
struct Decoded {
    std::vector<cl_float2> uv;
    std::vector<cl_float4> view, light;
};

Decoded reconstruct(const EngineGBuffer& in, bool light,
                    const std::shared_ptr<Runtime>& rt = runtime()) {
    DeviceGBuffer out = allocate_gbuffer(*rt, in.width, in.height, light, false);
    ReconstructPass pass(rt);
    pass.enqueue(in, out).wait();
    Decoded d;
    const size_t n = in.pixels();
    d.uv.resize(n);
    d.view.resize(n);
    rt->queue().enqueueReadBuffer(out.uv, CL_TRUE, 0, n * sizeof(cl_float2), d.uv.data());
    rt->queue().enqueueReadBuffer(out.view, CL_TRUE, 0, n * sizeof(cl_float4), d.view.data());
    if (light) {
        d.light.resize(n);
        rt->queue().enqueueReadBuffer(out.light, CL_TRUE, 0, n * sizeof(cl_float4), d.light.data());
    }
    return d;
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

struct Encoding {
    const char* name;
    FrameForm form;
    DepthConvention projection;
    FirstRow first_row;
    Storage depth, frame, uv;
    bool images;
    EngineLight light;
};

void PrintTo(const Encoding& e, std::ostream* os) { *os << e.name; }

class Reconstruct : public ::testing::TestWithParam<Encoding> {};

// V (and L) from every encoding within the derived bound of the double reference; sky pixels
// empty, the rest keep their stored uv.
TEST_P(Reconstruct, ViewAndLightWithinTheDerivedBound) {
    const Encoding& e = GetParam();
    EngineFrame f = plane_frame(small_plane(), e.projection, e.first_row);
    randomise_frames(f, e.form, 7);
    f.depth.storage = e.depth;
    f.normal.storage = f.tangent.storage = e.frame;
    f.uv.storage = e.uv;
    f.depth.image = f.normal.image = f.tangent.image = f.uv.image = e.images;
    for (const Plane* p : {&f.depth, &f.normal, &f.tangent, &f.uv})
        if (p->image && !device_has_image_format(*p))
            GTEST_SKIP() << runtime()->device_name() << " has no image format for " << e.name;
    EngineGBuffer in = f.to_device();
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

// Bit for bit: the two image paths against the buffer paths of the same stored values.
TEST(EngineGBuffer, ImagesReadTheSameAsBuffers) {
    for (Storage storage : {Storage::Float, Storage::Half}) {
        EngineFrame f = plane_frame(small_plane(), DepthConvention::ZeroToOne, FirstRow::Top);
        randomise_frames(f, FrameForm::NormalTangent, 11);
        // Depth too: PoCL misreads one-channel half images, which the pass copies to a buffer.
        f.depth.storage = f.normal.storage = f.tangent.storage = f.uv.storage = storage;
        EngineGBuffer buffers = f.to_device();
        buffers.light = kLamp;
        f.depth.image = f.normal.image = f.tangent.image = f.uv.image = true;
        EngineGBuffer images = f.to_device();
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
    EngineGBuffer in = f.to_device();
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
    EngineGBuffer half = f.to_device();
    for (Plane* p : {&f.normal, &f.uv}) {
        for (float& x : p->v) x = static_cast<float>(stored_value(x, Storage::Half));
        p->storage = Storage::Float;
    }
    EngineGBuffer full = f.to_device();
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
    cl::Event done = reconstruct_pass.enqueue(f.to_device(), decoded);
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
        cl::Event done = pass.enqueue(g.to_device(), decoded);
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
    const EngineGBuffer good = f.to_device();
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
    EngineGBuffer in = f.to_device();
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

}  // namespace
}  // namespace omtest