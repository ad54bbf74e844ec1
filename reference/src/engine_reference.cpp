// The engine frame's reference: its storage, and the reconstruct pass's formula in double with the
// bound of its float evaluation.
#include "offsetmap/engine_reference.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <random>

#include "offsetmap/passes.hpp"

namespace offsetmap::engine_ref {

namespace {

constexpr double kU = 1.0 / (1 << 24);  // unit roundoff of float

}  // namespace

// Rounds the float's 24-bit significand to half's 11 (or fewer, subnormal) bits, to nearest even.
std::uint16_t half_bits(float x) {
    std::uint32_t f;
    std::memcpy(&f, &x, 4);
    const std::uint32_t sign = (f >> 16) & 0x8000u;
    const std::uint32_t mag = f & 0x7fffffffu;
    if (mag >= 0x7f800000u)  // infinity, NaN (a quiet NaN's payload top bit kept)
        return static_cast<std::uint16_t>(sign | 0x7c00u | (mag > 0x7f800000u ? 0x200u : 0u));
    if (mag >= 0x477ff000u) return static_cast<std::uint16_t>(sign | 0x7c00u);  // rounds past max
    const int exp = static_cast<int>(mag >> 23) - 127;
    std::uint32_t significand = (mag & 0x7fffffu) | 0x800000u;
    int shift = 13;   // 23 fraction bits down to 10
    if (exp < -14) {  // subnormal half (or zero)
        shift += -14 - exp;
        if (shift > 24) return static_cast<std::uint16_t>(sign);
    }
    std::uint32_t h = significand >> shift;
    const std::uint32_t rest = significand & ((1u << shift) - 1), half = 1u << (shift - 1);
    if (rest > half || (rest == half && (h & 1u))) ++h;
    if (exp < -14) return static_cast<std::uint16_t>(sign | h);  // a carry into 0x400 is right
    // h holds the implicit bit at 0x400; a carry to 0x800 moves into the exponent.
    return static_cast<std::uint16_t>(sign |
                                      ((static_cast<std::uint32_t>(exp + 15) << 10) + h - 0x400u));
}

float half_value(std::uint16_t bits) {
    const int e = (bits >> 10) & 0x1f, m = bits & 0x3ff;
    const float sign = (bits & 0x8000u) ? -1.0f : 1.0f;
    if (e == 0) return sign * std::ldexp(static_cast<float>(m), -24);
    if (e == 31) return m ? std::numeric_limits<float>::quiet_NaN() : sign * INFINITY;
    return sign * std::ldexp(static_cast<float>(m | 0x400), e - 25);
}

Plane with_values(int values) {
    Plane p;
    p.values = values;
    return p;
}

double stored_value(float x, Storage s) {
    switch (s) {
        case Storage::Half:
            return half_value(half_bits(x));
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
            const std::uint16_t bits = half_bits(x);
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

namespace {

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

}  // namespace

bool device_has_image_format(const cl::Context& context, const Plane& p) {
    std::vector<cl::ImageFormat> formats;
    context.getSupportedImageFormats(CL_MEM_READ_ONLY, CL_MEM_OBJECT_IMAGE2D, &formats);
    const cl_channel_order order = p.values == 1 ? CL_R : CL_RGBA;
    for (const cl::ImageFormat& f : formats)
        if (f.image_channel_order == order && f.image_channel_data_type == image_type(p.storage))
            return true;
    return false;
}

Input to_device(const cl::Context& context, const Plane& p, int w, int h) {
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

EngineGBuffer EngineFrame::to_device(const cl::Context& context) const {
    EngineGBuffer g;
    g.width = width;
    g.height = height;
    g.camera = camera;
    g.frame = form;
    g.depth = engine_ref::to_device(context, depth, width, height);
    g.normal = engine_ref::to_device(context, normal, width, height);
    if (form == FrameForm::NormalTangent)
        g.tangent = engine_ref::to_device(context, tangent, width, height);
    g.uv = engine_ref::to_device(context, uv, width, height);
    return g;
}

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

EngineFrame encoded_frame(const PlaneScene& scene, const Encoding& e, std::uint64_t seed) {
    EngineFrame f = plane_frame(scene, e.projection, e.first_row);
    randomise_frames(f, e.form, seed);
    f.depth.storage = e.depth;
    f.normal.storage = f.tangent.storage = e.frame;
    f.uv.storage = e.uv;
    f.depth.image = f.normal.image = f.tangent.image = f.uv.image = e.images;
    return f;
}

bool device_reads_images(const cl::Context& context, const EngineFrame& f) {
    for (const Plane* p : {&f.depth, &f.normal, &f.tangent, &f.uv})
        if (p->image && !device_has_image_format(context, *p)) return false;
    return true;
}

void randomise_frames(EngineFrame& f, FrameForm form, std::uint64_t seed) {
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

namespace {

glm::dvec4 stored4(const Plane& p, size_t k) {
    glm::dvec4 out(0.0);
    for (int i = 0; i < p.values; ++i) out[i] = stored_value(p.v[p.values * k + i], p.storage);
    return out;
}

}  // namespace

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
        const bool at_point = light.kind == LightKind::Point || light.kind == LightKind::Spot;
        l = at_point ? glm::normalize(l - p) : glm::normalize(l);
        out.l_ts = {glm::dot(l, t), glm::dot(l, b), glm::dot(l, n)};
        // A directional light's error is its normalisation's; a point light's adds p's, as V's.
        const double dl =
            at_point
                ? (std::sqrt(dp2) + u * glm::length(l)) /
                          glm::length(
                              glm::dvec3(light.vector[0], light.vector[1], light.vector[2]) - p) +
                      8 * u
                : 8 * u;
        out.l_bound = dl + std::max({df[0], df[1], df[2]}) + g3;
        if (light.kind == LightKind::Spot) {
            const glm::dvec3 axis =
                glm::normalize(glm::dvec3(light.axis[0], light.axis[1], light.axis[2]));
            const double outer = std::cos(double(light.cone_outer));
            const double span = std::max(std::cos(double(light.cone_inner)) - outer, 1e-6);
            const double s = std::clamp((-glm::dot(l, axis) - outer) / span, 0.0, 1.0);
            out.cone_dark = 1.0 - s * s * (3.0 - 2.0 * s);
            out.cone_slope = 1.5 / span;
        }
    }
    return out;
}

Decoded reconstruct(const std::shared_ptr<Runtime>& rt, const EngineGBuffer& in, bool light) {
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

}  // namespace offsetmap::engine_ref
