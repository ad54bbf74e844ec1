#include "offsetmap/scenes.hpp"

#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <random>

#include "offsetmap/error.hpp"
#include "offsetmap/shared.h"

namespace offsetmap {
namespace {

constexpr double kDeg = M_PI / 180.0;

void check_elevations(double lo, double hi) {
    if (!(lo > 0.0 && lo <= hi && hi <= 90.0))
        throw Error("elevations must satisfy 0 < min <= max <= 90 degrees, got min " +
                    std::to_string(lo) + ", max " + std::to_string(hi));
}

cl_float4 f4(const glm::dvec3& v) {
    return {{static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z), 0.0f}};
}

// The plane scene's pinhole camera: the eye, its basis, and each pixel centre's ray.
struct PlaneCamera {
    glm::dvec3 eye, forward, right, up;
    double th, aspect;
    int width, height;

    explicit PlaneCamera(const PlaneScene& s) {
        if (!(s.camera_height > 0.0 && s.tile > 0.0 && s.fov_deg > 0.0 && s.fov_deg < 170.0))
            throw Error("plane scene needs camera height > 0, tile > 0 and 0 < fov < 170 degrees");
        check_gbuffer_size(s.width, s.height, "the G-buffer");
        const double yaw = s.yaw_deg * kDeg, pitch = s.pitch_deg * kDeg;
        eye = glm::dvec3(s.camera_x, s.camera_y, s.camera_height);
        forward = glm::dvec3(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                             -std::sin(pitch));
        right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
        up = glm::cross(right, forward);
        th = std::tan(0.5 * s.fov_deg * kDeg);
        aspect = static_cast<double>(s.width) / s.height;
        width = s.width;
        height = s.height;
    }
    // Unit direction through pixel (x, y)'s centre; row 0 at the top.
    glm::dvec3 ray(int x, int y) const {
        const double px = (2.0 * (x + 0.5) / width - 1.0) * th * aspect;
        const double py = (1.0 - 2.0 * (y + 0.5) / height) * th;
        return glm::normalize(forward + px * right + py * up);
    }
};

}  // namespace

GBuffer make_scene(const PlaneScene& s) {
    const PlaneCamera cam(s);
    GBuffer gb;
    gb.resize(s.width, s.height, s.with_light, false);
    const glm::dvec3 light = glm::normalize(glm::dvec3(s.light[0], s.light[1], s.light[2]));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            size_t k = static_cast<size_t>(y) * s.width + x;
            const glm::dvec3 d = cam.ray(x, y);
            if (d.z >= -1e-9) {
                gb.uv[k] = {{nan, nan}};
                continue;
            }
            glm::dvec3 hit = cam.eye + d * (s.camera_height / -d.z);
            gb.uv[k] = {{static_cast<float>(hit.x / s.tile), static_cast<float>(hit.y / s.tile)}};
            gb.view[k] = f4(-d);
            if (s.with_light) gb.light[k] = f4(light);
        }
    return gb;
}

EngineScene make_engine_scene(const PlaneScene& s, DepthConvention depth, FirstRow first_row) {
    const PlaneCamera cam(s);
    EngineScene e;
    e.width = s.width;
    e.height = s.height;
    const glm::dmat4 view = glm::lookAt(cam.eye, cam.eye + cam.forward, glm::dvec3(0, 0, 1));
    const double fov = s.fov_deg * kDeg, near = 0.01, far = 1.0e4;
    glm::dmat4 projection =
        depth == DepthConvention::GL          ? glm::perspectiveNO(fov, cam.aspect, near, far)
        : depth == DepthConvention::ZeroToOne ? glm::perspectiveZO(fov, cam.aspect, near, far)
                                              : glm::perspectiveZO(fov, cam.aspect, far, near);
    // Row 0 at NDC y = -1: the same picture through a projection flipped in y.
    if (first_row == FirstRow::Bottom)
        projection = glm::scale(glm::dmat4(1.0), glm::dvec3(1, -1, 1)) * projection;
    const glm::dmat4 vp = projection * view;
    const glm::dmat4 inverse = glm::inverse(vp);
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            e.camera.inverse_view_projection[4 * c + r] = static_cast<float>(inverse[c][r]);
    e.camera.eye = {static_cast<float>(cam.eye.x), static_cast<float>(cam.eye.y),
                    static_cast<float>(cam.eye.z)};
    e.camera.depth = depth;
    e.camera.first_row = first_row;
    if (s.with_light)  // the plane's frame is the world's: the tangent-space light as it is
        e.light = {LightKind::Directional,
                   {static_cast<float>(s.light[0]), static_cast<float>(s.light[1]),
                    static_cast<float>(s.light[2])}};
    const size_t n = static_cast<size_t>(s.width) * s.height;
    const bool reversed = depth == DepthConvention::Reversed;
    e.depth.assign(n, reversed ? 0.0f : 1.0f);
    e.uv.assign(2 * n, std::numeric_limits<float>::quiet_NaN());
    e.normal.assign(4 * n, 0.0f);
    e.tangent.assign(4 * n, 0.0f);
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const size_t k = static_cast<size_t>(y) * s.width + x;
            e.normal[4 * k + 2] = 1.0f;  // the plane's frame is the world's
            e.tangent[4 * k] = 1.0f;
            e.tangent[4 * k + 3] = 1.0f;
            const glm::dvec3 d = cam.ray(x, y);
            if (d.z >= -1e-9) continue;
            const glm::dvec3 hit = cam.eye + d * (s.camera_height / -d.z);
            const glm::dvec4 clip = vp * glm::dvec4(hit, 1.0);
            const double z = clip.z / clip.w;
            const double window = depth == DepthConvention::GL ? 0.5 * (z + 1.0) : z;
            if (!(reversed ? window > 0.0 : window < 1.0)) continue;  // past the far plane
            e.depth[k] = static_cast<float>(window);
            e.uv[2 * k] = static_cast<float>(hit.x / s.tile);
            e.uv[2 * k + 1] = static_cast<float>(hit.y / s.tile);
        }
    return e;
}

GBuffer make_scene(const SweepScene& s) {
    if (s.elevations < 1 || s.azimuths < 1 || s.patch < 1)
        throw Error("sweep scene needs at least 1 elevation, 1 azimuth and a patch of 1");
    check_elevations(s.min_elevation_deg, s.max_elevation_deg);
    GBuffer gb;
    gb.resize(s.azimuths * s.patch, s.elevations * s.patch, false, false);
    for (int e = 0; e < s.elevations; ++e) {
        double f = s.elevations > 1 ? static_cast<double>(e) / (s.elevations - 1) : 0.0;
        double elev =
            (s.max_elevation_deg + f * (s.min_elevation_deg - s.max_elevation_deg)) * kDeg;
        for (int a = 0; a < s.azimuths; ++a) {
            double az = 2.0 * M_PI * a / s.azimuths;
            glm::dvec3 v(std::cos(elev) * std::cos(az), std::cos(elev) * std::sin(az),
                         std::sin(elev));
            for (int py = 0; py < s.patch; ++py)
                for (int px = 0; px < s.patch; ++px) {
                    size_t k = static_cast<size_t>(e * s.patch + py) * gb.width + a * s.patch + px;
                    gb.uv[k] = {{static_cast<float>((px + 0.5) / s.patch),
                                 static_cast<float>((py + 0.5) / s.patch)}};
                    gb.view[k] = f4(v);
                }
        }
    }
    return gb;
}

HeightMap bench_map(int n) {
    HeightMap m;
    m.width = m.height = n;
    m.h.resize(static_cast<size_t>(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double u = (i + 0.5) / n, v = (j + 0.5) / n, h = 0.5;
            for (int k = 0; k < 5; ++k) {
                double f = std::pow(2.0, k + 1), a = 0.22 / (k + 1);
                h += a * std::sin(2 * M_PI * f * u + k) * std::sin(2 * M_PI * (f + 1) * v + 2 * k);
            }
            const double code = std::floor(std::clamp(h, 0.0, 1.0) * 65535.0 + 0.5);
            m.h[static_cast<size_t>(j) * n + i] = static_cast<float>(code) * OM_UNORM16_STEP;
        }
    return m;
}

GBuffer make_scene(const RandomScene& s) {
    check_elevations(s.min_elevation_deg, s.max_elevation_deg);
    GBuffer gb;
    gb.resize(s.width, s.height, false, false);
    std::mt19937_64 rng(s.seed);
    // 53-bit uniform in [0,1) from the raw engine output, the same on every standard library.
    auto uniform = [&rng]() { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
    double zlo = std::sin(s.min_elevation_deg * kDeg), zhi = std::sin(s.max_elevation_deg * kDeg);
    for (size_t k = 0; k < gb.pixels(); ++k) {
        double u = uniform(), v = uniform();
        double z = zlo + (zhi - zlo) * uniform(), az = 2.0 * M_PI * uniform();
        double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        gb.uv[k] = {{static_cast<float>(u), static_cast<float>(v)}};
        gb.view[k] = f4(glm::dvec3(r * std::cos(az), r * std::sin(az), z));
    }
    return gb;
}

GBuffer reconstruct(std::shared_ptr<Runtime> runtime, const EngineScene& e) {
    Runtime& rt = *runtime;
    const size_t n = e.pixels();
    const bool quaternion = e.frame == FrameForm::Quaternion;
    if (e.depth.size() != n || e.normal.size() != 4 * n ||
        (!quaternion && e.tangent.size() != 4 * n) || e.uv.size() != 2 * n)
        throw Error("the engine scene's planes do not match its size " + std::to_string(e.width) +
                    "x" + std::to_string(e.height));
    auto input = [&](const std::vector<float>& v) {
        Input in;
        in.buffer = cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               v.size() * sizeof(float), const_cast<float*>(v.data()));
        return in;
    };
    EngineGBuffer g;
    g.width = e.width;
    g.height = e.height;
    g.camera = e.camera;
    g.depth = input(e.depth);
    g.frame = e.frame;
    g.normal = input(e.normal);
    if (!quaternion) g.tangent = input(e.tangent);
    g.uv = input(e.uv);
    g.light = e.light;
    const bool lit = e.light.kind != LightKind::None;
    DeviceGBuffer out = allocate_gbuffer(rt, e.width, e.height, lit, false);
    ReconstructPass(runtime).enqueue(g, out).wait();
    GBuffer gb;
    gb.resize(e.width, e.height, lit, false);
    rt.queue().enqueueReadBuffer(out.uv, CL_TRUE, 0, n * sizeof(cl_float2), gb.uv.data());
    rt.queue().enqueueReadBuffer(out.view, CL_TRUE, 0, n * sizeof(cl_float4), gb.view.data());
    if (lit)
        rt.queue().enqueueReadBuffer(out.light, CL_TRUE, 0, n * sizeof(cl_float4), gb.light.data());
    // The curvature is per pixel in the frame the reconstruction keeps: carried over as it is.
    if (!e.curvature.empty()) {
        if (e.curvature.size() != 3 * n || (!e.uv_stretch.empty() && e.uv_stretch.size() != n))
            throw Error("the engine scene's curvature planes do not match its size " +
                        std::to_string(e.width) + "x" + std::to_string(e.height));
        gb.curvature.resize(n);
        for (size_t k = 0; k < n; ++k)
            gb.curvature[k] = {{e.curvature[3 * k], e.curvature[3 * k + 1], e.curvature[3 * k + 2],
                                e.uv_stretch.empty() ? 1.0f : e.uv_stretch[k]}};
    }
    return gb;
}

}  // namespace offsetmap
