// An engine's deferred frame with relief, shadows and the layer behind, through the installed
// package alone (docs/integrating.md walks through it). The engine's G-buffer passes are stood in
// for by a ray caster over its scene: a ground plane and a pillar (a cylinder, its curvature in the
// G-buffer) under a directional light. Per frame:
//   1. the camera's G-buffer -> ReconstructPass -> MaterialFrame (over the curved base);
//   2. where rays leave the pillar's relief (OM_FLAGS_SEE_BEHIND), the layer behind, drawn in
//      their rectangle only -> ReconstructPass -> MaterialFrame::enqueue_behind, take_behind;
//   3. DepthOffsetPass: the relief's depth into the depth buffer;
//   4. the light's G-buffer (orthographic) -> the same passes -> its displaced shadow map;
//   5. ShadowMaskPass: the frame's points against it; MaterialFrame::shade with the mask.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "offsetmap/offsetmap.hpp"

namespace {

using namespace offsetmap;
using Vec3 = std::array<float, 3>;
using Mat4 = std::array<float, 16>;  // column-major, GL's layout

Vec3 operator+(Vec3 a, Vec3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 operator-(Vec3 a, Vec3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 operator*(Vec3 a, float s) { return {a[0] * s, a[1] * s, a[2] * s}; }
float dot(Vec3 a, Vec3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(Vec3 a, Vec3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Vec3 normalize(Vec3 a) { return a * (1.0f / std::sqrt(dot(a, a))); }

Mat4 mul(const Mat4& a, const Mat4& b) {
    Mat4 m{};
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            for (int k = 0; k < 4; ++k) m[4 * c + r] += a[4 * k + r] * b[4 * c + k];
    return m;
}

// Gauss-Jordan in double: the engine has its own matrix library.
Mat4 inverse(const Mat4& m) {
    double a[4][8];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 8; ++c) a[r][c] = c < 4 ? m[4 * c + r] : (c - 4 == r);
    for (int c = 0; c < 4; ++c) {
        int p = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::fabs(a[r][c]) > std::fabs(a[p][c])) p = r;
        std::swap(a[c], a[p]);
        for (int r = 0; r < 4; ++r) {
            if (r == c) continue;
            const double f = a[r][c] / a[c][c];
            for (int k = 0; k < 8; ++k) a[r][k] -= f * a[c][k];
        }
    }
    Mat4 out;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) out[4 * c + r] = float(a[r][c + 4] / a[r][r]);
    return out;
}

Mat4 look_at(Vec3 eye, Vec3 target) {
    const Vec3 f = normalize(target - eye), s = normalize(cross(f, {0, 1, 0})), u = cross(s, f);
    return {s[0], u[0], -f[0], 0, s[1],         u[1],         -f[1],       0,
            s[2], u[2], -f[2], 0, -dot(s, eye), -dot(u, eye), dot(f, eye), 1};
}
Mat4 perspective(float fov_y, float aspect, float n, float f) {
    const float t = 1.0f / std::tan(0.5f * fov_y);
    return {t / aspect,          0, 0, 0, 0, t, 0, 0, 0, 0, (f + n) / (n - f), -1, 0, 0,
            2 * f * n / (n - f), 0};
}
Mat4 orthographic(float half, float n, float f) {
    return {1 / half,           0, 0, 0, 0, 1 / half, 0, 0, 0, 0, -2 / (f - n), 0, 0, 0,
            -(f + n) / (f - n), 1};
}

// The scene's surfaces, as the engine's meshes: the ground (id 1, a tile each 2 m) and a pillar of
// radius 0.5 m and 2 m high (id 2, six tiles around, square; its flat cap has no relief).
constexpr float kRadius = 0.5f, kHeight = 2.0f, kGround = 3.0f;
constexpr float kTile = 6.2831853f * kRadius / 6;  // the pillar's metres a uv unit

// What the engine's G-buffer pass writes at a pixel.
struct Sample {
    float t = INFINITY;  // along the ray
    Vec3 normal{}, tangent{};
    float handedness = 1, u = 0, v = 0, id = 0, density = 1;
    std::array<float, 4> curvature{0, 0, 0, 1};  // k_uu, k_uv, k_vv in uv units, stretch
};

// The nearest front-facing surface along o + t d with t > after.
Sample cast(Vec3 o, Vec3 d, float after) {
    Sample s;
    if (d[1] < 0) {  // the ground, y = 0, seen from above
        const float t = -o[1] / d[1];
        const Vec3 p = o + d * t;
        if (t > after && std::fabs(p[0]) < kGround && std::fabs(p[2]) < kGround) {
            s = {t, {0, 1, 0}, {1, 0, 0}, 1, 0.5f * p[0], -0.5f * p[2], 1, 2};
        }
    }
    // The pillar's side: |(x, z)| = R, 0 <= y <= H, its outside facing the ray.
    const float a = d[0] * d[0] + d[2] * d[2], b = o[0] * d[0] + o[2] * d[2];
    const float c = o[0] * o[0] + o[2] * o[2] - kRadius * kRadius, disc = b * b - a * c;
    if (a > 0 && disc > 0) {
        const float t = (-b - std::sqrt(disc)) / a;
        const Vec3 p = o + d * t;
        if (t > after && t < s.t && p[1] >= 0 && p[1] <= kHeight) {
            const float phi = std::atan2(p[2], p[0]);
            const Vec3 n = {p[0] / kRadius, 0, p[2] / kRadius};
            // u around, v down; k_TT = 1 / R around, times the density (uv units).
            s = {t, n, {-n[2], 0, n[0]}, 1, phi * kRadius / kTile, -p[1] / kTile, 2, kTile};
            s.curvature = {kTile / kRadius, 0, 0, 1};
        }
    }
    if (d[1] < 0) {  // the cap
        const float t = (kHeight - o[1]) / d[1];
        const Vec3 p = o + d * t;
        if (t > after && t < s.t && p[0] * p[0] + p[2] * p[2] <= kRadius * kRadius)
            s = {t, {0, 1, 0}, {1, 0, 0}, 1, p[0], -p[2], 0, 1};
    }
    return s;
}

// A view's G-buffer planes, rows top first, GL depth; `behind` the surfaces behind `first`.
struct Planes {
    std::vector<float> depth, normal, tangent, uv, id, density, curvature;
};
struct View {
    int w, h;
    Mat4 view_projection, inverse_view_projection;
    EngineCamera camera;
};

View make_view(int w, int h, const Mat4& projection, const Mat4& view, Vec3 eye, bool ortho) {
    View v{w, h, mul(projection, view), {}, {}};
    v.inverse_view_projection = inverse(v.view_projection);
    v.camera.inverse_view_projection = v.inverse_view_projection;
    v.camera.eye = eye;  // orthographic: the direction toward the viewer
    v.camera.orthographic = ortho;
    v.camera.depth = DepthConvention::GL;
    v.camera.first_row = FirstRow::Top;
    return v;
}

Vec3 unproject(const View& v, float nx, float ny, float nz) {
    const Mat4& m = v.inverse_view_projection;
    float p[4];
    for (int r = 0; r < 4; ++r) p[r] = m[r] * nx + m[4 + r] * ny + m[8 + r] * nz + m[12 + r];
    return {p[0] / p[3], p[1] / p[3], p[2] / p[3]};
}

// The engine's G-buffer pass over pixels where `draw` says (the layer behind: where the first
// layer's flags ask for it, behind the first layer's surface).
Planes draw(const View& v, const Planes* first, const std::vector<cl_uint>* flags) {
    const size_t n = size_t(v.w) * v.h;
    Planes p{std::vector<float>(n, 1.0f), std::vector<float>(4 * n), std::vector<float>(4 * n),
             std::vector<float>(2 * n),   std::vector<float>(n),     std::vector<float>(n, 1.0f),
             std::vector<float>(4 * n)};
    for (int y = 0; y < v.h; ++y)
        for (int x = 0; x < v.w; ++x) {
            const size_t k = size_t(y) * v.w + x;
            p.curvature[4 * k + 3] = 1;
            if (flags && !((*flags)[k] & OM_FLAGS_SEE_BEHIND)) continue;
            const float nx = (2 * x + 1.0f) / v.w - 1, ny = 1 - (2 * y + 1.0f) / v.h;
            const Vec3 o = unproject(v, nx, ny, -1), d = normalize(unproject(v, nx, ny, 1) - o);
            const float after = first ? cast(o, d, 0).t * 1.0001f : 0.0f;
            const Sample s = cast(o, d, after);
            if (!std::isfinite(s.t)) continue;
            const Vec3 q = o + d * s.t;
            const Mat4& m = v.view_projection;
            const float cz = m[2] * q[0] + m[6] * q[1] + m[10] * q[2] + m[14];
            const float cw = m[3] * q[0] + m[7] * q[1] + m[11] * q[2] + m[15];
            p.depth[k] = 0.5f * cz / cw + 0.5f;
            std::copy(s.normal.begin(), s.normal.end(), &p.normal[4 * k]);
            std::copy(s.tangent.begin(), s.tangent.end(), &p.tangent[4 * k]);
            p.tangent[4 * k + 3] = s.handedness;
            p.uv[2 * k] = s.u, p.uv[2 * k + 1] = s.v;
            p.id[k] = s.id, p.density[k] = s.density;
            std::copy(s.curvature.begin(), s.curvature.end(), &p.curvature[4 * k]);
        }
    return p;
}

}  // namespace

int main() try {
    cl::Device device = cl::Device::getDefault();
    cl::Context context(device);
    cl::CommandQueue queue(context, device);
    auto rt = std::make_shared<Runtime>(context, device, queue);
    auto buffer = [&](const std::vector<float>& v) {
        return cl::Buffer(context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, v.size() * 4,
                          const_cast<float*>(v.data()));
    };
    auto scratch = [&](size_t bytes) { return cl::Buffer(context, CL_MEM_READ_WRITE, bytes); };

    // The materials: a relief each, traced with POM.
    std::vector<FrameMaterial> table;
    for (int id : {1, 2}) {
        HeightMap map;
        map.width = map.height = 64;
        for (int k = 0; k < 64 * 64; ++k) {
            const float x = 6.2832f * (k % 64) / 64, y = 6.2832f * (k / 64) / 64;
            map.h.push_back(id == 1 ? 0.5f + 0.5f * std::sin(2 * x) * std::cos(2 * y)
                                    : 0.5f + 0.5f * std::sin(4 * y));
        }
        FrameMaterial m;
        m.id = id;
        m.name = id == 1 ? "ground" : "pillar";
        m.settings.scale = 0.08f;
        m.field = upload(*rt, map, m.settings);
        m.params = resolve_params(find_method("pom"), {});
        table.push_back(m);
    }
    MaterialFrame frame(rt, table);
    const Vec3 toward_light = normalize({0.6f, 0.7f, 0.4f});

    // 1. The camera's first layer.
    const int w = 320, h = 180;
    const size_t n = size_t(w) * h;
    const Vec3 eye = {0.4f, 1.2f, 4.0f};
    const View cam = make_view(w, h, perspective(0.9f, float(w) / h, 0.1f, 20.0f),
                               look_at(eye, {0, 0.8f, 0}), eye, false);
    const Planes first = draw(cam, nullptr, nullptr);
    auto engine_gbuffer = [&](const View& v, const Planes& p) {
        EngineGBuffer g;
        g.width = v.w, g.height = v.h, g.camera = v.camera;
        g.depth.buffer = buffer(p.depth), g.normal.buffer = buffer(p.normal);
        g.tangent.buffer = buffer(p.tangent), g.uv.buffer = buffer(p.uv);
        g.light = {LightKind::Directional, toward_light};
        return g;
    };
    auto targets = [&](size_t pixels) {
        return OffsetTargets{scratch(pixels * 8), scratch(pixels * 4), scratch(pixels * 4),
                             scratch(pixels * 4)};
    };
    ReconstructPass reconstruct(rt);
    const EngineGBuffer g1 = engine_gbuffer(cam, first);
    DeviceGBuffer d1 = allocate_gbuffer(*rt, w, h, true, false);
    d1.material = buffer(first.id), d1.curvature = buffer(first.curvature);
    const OffsetTargets t1 = targets(n);
    reconstruct.enqueue(g1, d1);
    frame.enqueue(d1, t1).wait();

    // 2. The layer behind, where the first layer's rays left the relief: drawn in their rectangle.
    std::vector<cl_uint> flags(n);
    queue.enqueueReadBuffer(t1.flags, CL_TRUE, 0, n * 4, flags.data());
    PixelRegion box{w, h, 0, 0};
    size_t see_behind = 0;
    for (int k = 0; k < int(n); ++k)
        if (flags[k] & OM_FLAGS_SEE_BEHIND) {
            ++see_behind;
            box.x = std::min(box.x, k % w), box.y = std::min(box.y, k / w);
            box.width = std::max(box.width, k % w + 1),
            box.height = std::max(box.height, k / w + 1);
        }
    box.width -= box.x, box.height -= box.y;
    cl::Buffer depth = buffer(first.depth), density = buffer(first.density);
    if (see_behind) {
        const Planes second = draw(cam, &first, &flags);
        EngineGBuffer g2 = engine_gbuffer(cam, second);
        g2.regions = {box};
        DeviceGBuffer d2 = allocate_gbuffer(*rt, w, h, true, false);
        d2.material = buffer(second.id), d2.curvature = buffer(second.curvature);
        const cl::Event drawn = reconstruct.enqueue(g2, d2);
        frame.enqueue_behind(d1, t1, LayerBehind{d2, targets(n)}, {drawn});
        frame.take_behind(t1.flags, buffer(second.depth), depth, n, 1);
        frame.take_behind(t1.flags, buffer(second.density), density, n, 1).wait();
    }

    // 3. The relief's depth into the depth buffer.
    DepthOffsetPass depth_offset(rt);
    const cl::Buffer depth_after = scratch(n * 4);
    depth_offset.enqueue({w, h, cam.camera, cam.view_projection, depth, t1.depth, density},
                         {depth_after});

    // 4. The light's view through the same passes: its displaced shadow map.
    const int m = 512;
    const Vec3 centre = {0, 0.8f, 0};
    const View light = make_view(m, m, orthographic(3.6f, 0.1f, 12.0f),
                                 look_at(centre + toward_light * 6.0f, centre), toward_light, true);
    const Planes seen = draw(light, nullptr, nullptr);
    DeviceGBuffer dl = allocate_gbuffer(*rt, m, m, true, false);
    dl.material = buffer(seen.id), dl.curvature = buffer(seen.curvature);
    const OffsetTargets tl = targets(size_t(m) * m);
    reconstruct.enqueue(engine_gbuffer(light, seen), dl);
    frame.enqueue(dl, tl);
    const cl::Buffer map = scratch(size_t(m) * m * 4);
    depth_offset.enqueue({m, m, light.camera, light.view_projection, buffer(seen.depth), tl.depth,
                          buffer(seen.density)},
                         {map});

    // 5. The receivers' test, and the shading with it.
    const cl::Buffer mask = scratch(n * 4), rgba = scratch(n * 16), visibility = scratch(n * 4);
    ShadowMaskInputs test;
    test.width = w, test.height = h, test.camera = cam.camera, test.depth = depth_after;
    test.map = {m, m, light.camera, light.view_projection, map};
    ShadowMaskPass(rt).enqueue(test, {mask});
    FrameShadeInputs in = frame_shade_inputs(t1);
    in.shadow_mask = mask;
    frame.shade(d1, in, ShadeSettings{}, {rgba, visibility}).wait();

    std::vector<cl_float4> color(n);
    std::vector<float> lit(n);
    queue.enqueueReadBuffer(rgba, CL_TRUE, 0, n * 16, color.data());
    queue.enqueueReadBuffer(t1.flags, CL_TRUE, 0, n * 4, flags.data());
    queue.enqueueReadBuffer(mask, CL_TRUE, 0, n * 4, lit.data());
    size_t shown = 0, behind = 0, shadowed = 0, bad = 0;
    for (size_t k = 0; k < n; ++k) {
        if (first.depth[k] >= 1.0f) continue;
        ++shown;
        behind += (flags[k] & OM_FLAG_BEHIND) != 0;
        shadowed += lit[k] < 0.5f;
        bad += !std::isfinite(color[k].s[0] + color[k].s[1] + color[k].s[2]);
    }
    std::printf(
        "engine frame: %zu pixels drawn, %zu left the pillar's relief, %zu show the layer "
        "behind, %zu in the pillar's shadow, %zu not finite, on %s\n",
        shown, see_behind, behind, shadowed, bad, rt->device_name().c_str());
    return shown > 0 && behind > 0 && shadowed > 0 && bad == 0 ? 0 : 1;
} catch (const std::exception& e) {
    std::fprintf(stderr, "engine frame: %s\n", e.what());
    return 1;
}
