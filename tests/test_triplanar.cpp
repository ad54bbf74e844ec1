// Triplanar relief: the reconstruct pass's split into projections, the material frame's traces of
// each and the shading's blend, against a definition of the projections written here.
#include <cmath>
#include <cstring>
#include <random>

#include "offsetmap/engine_reference.hpp"
#include "offsetmap/scenes.hpp"
#include "support.hpp"

namespace omtest {
namespace {

using engine_ref::EngineFrame;
using engine_ref::plane_frame;

// The projections' frames as docs/design.md defines them: p = 2 axis + (normal's component < 0).
struct Frame {
    glm::dvec3 t, b, n;
};
Frame frame_of(int p) {
    const double s = (p & 1) ? -1.0 : 1.0;
    switch (p >> 1) {
        case 0:
            return {{0, 0, -s}, {0, 1, 0}, {s, 0, 0}};
        case 1:
            return {{1, 0, 0}, {0, 0, -s}, {0, s, 0}};
        default:
            return {{s, 0, 0}, {0, 1, 0}, {0, 0, s}};
    }
}

// The weights in double: |n_a|^k normalised, lowered by the cutoff, clamped, normalised again.
glm::dvec3 weights_of(const glm::dvec3& n, double k, double cutoff) {
    glm::dvec3 a(std::pow(std::abs(n.x), k), std::pow(std::abs(n.y), k),
                 std::pow(std::abs(n.z), k));
    a /= a.x + a.y + a.z;
    a = glm::max(a - cutoff, glm::dvec3(0));
    return a / (a.x + a.y + a.z);
}

int projection_of(const glm::dvec3& n, int axis) { return 2 * axis + (n[axis] < 0 ? 1 : 0); }

// A pixel of the blend plane as the kernels pack it: x = 2 c + w1 (c = p0 + 6 where the second
// projection is on the axis of the first's B; -1: not triplanar), y = w2, z and w the normal's x
// and y in the first projection's frame.
struct Blend {
    bool on = false;
    float w[3] = {1, 0, 0};
    int p0 = 0;
    bool b_first = false;
    float nx = 0, ny = 0;
};
Blend unpack(const cl_float4& b) {
    Blend r;
    r.on = b.s[0] >= 0;
    if (!r.on) return r;
    const float c = std::floor(0.5f * b.s[0]);
    r.w[1] = b.s[0] - 2 * c;
    r.w[2] = b.s[1];
    r.w[0] = 1.0f - r.w[1] - r.w[2];
    r.p0 = static_cast<int>(c) % 6;
    r.b_first = c >= 6;
    r.nx = b.s[2];
    r.ny = b.s[3];
    return r;
}

// The pixel's world point from the engine frame's stored depth (zero-one, rows top first), and the
// bound a float evaluation of it keeps to on each component: p = (M ndc).xyz / (M ndc).w, each
// dot product of four terms within 4u of the sum of its terms' magnitudes, the division within u.
struct WorldPoint {
    glm::dvec3 p;
    double bound;
};
WorldPoint world_point(const EngineFrame& f, int x, int y) {
    const double d = f.depth.v[static_cast<size_t>(y) * f.width + x];
    const auto& m = f.camera.inverse_view_projection;
    const glm::dvec4 ndc(2.0 * (x + 0.5) / f.width - 1.0, 1.0 - (2.0 * y + 1.0) / f.height, d, 1);
    glm::dvec4 p(0), mag(0);
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            p[r] += m[4 * c + r] * ndc[c];
            mag[r] += std::abs(m[4 * c + r] * ndc[c]);
        }
    const double u = 1.0 / (1 << 24);
    const glm::dvec3 q = glm::dvec3(p) / p.w;
    double bound = 0;
    for (int i = 0; i < 3; ++i)
        bound = std::max(bound, (5 * u * mag[i] + 5 * u * mag.w * std::abs(q[i])) / std::abs(p.w) +
                                    u * std::abs(q[i]));
    return {q, bound};
}

EngineFrame small_plane() {
    PlaneScene scene;
    scene.width = 96;
    scene.height = 64;
    scene.tile = 0.25;
    return plane_frame(scene, DepthConvention::ZeroToOne, FirstRow::Top);
}

// Unit normals spread over the sphere, per pixel.
void random_normals(EngineFrame& f, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    for (size_t k = 0; k < f.pixels(); ++k) {
        const glm::dvec3 n = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
        for (int i = 0; i < 3; ++i) f.normal.v[4 * k + i] = static_cast<float>(n[i]);
    }
}

Image4 constant_albedo(float r, float g, float b) {
    Image4 img;
    img.width = img.height = 4;
    img.texels.assign(16, cl_float4{{r, g, b, 1.0f}});
    return img;
}

Image4 checker_like() {
    Image4 img;
    img.width = img.height = 8;
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
            const float c = ((i / 2 + j / 2) & 1) ? 0.9f : 0.2f;
            img.texels.push_back({{c, 0.5f, 1.0f - c, 1.0f}});
        }
    return img;
}

OffsetTargets t_all(Runtime& rt, size_t n) {
    OffsetTargets t;
    t.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    t.depth = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(float));
    t.fetches = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    t.flags = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    return t;
}

// One frame of one material (id 1 on every pixel) from an engine frame, with or without the
// triplanar split, and what it wrote.
struct TriRun {
    std::vector<cl_float2> uv, uv_out, uv2, uv3;
    std::vector<cl_float4> view, view2, view3, light, rgba, blend;
    std::vector<float> depth, ids2, ids3, ray_scale;
    std::vector<cl_uint> fetches, flags;
    // Triplanar: each projection's own trace (the dominant's again without the planes).
    std::vector<float> depth1, depth2, depth3;
    std::vector<cl_uint> fetches1, fetches2, fetches3, flags2;
};

struct FrameSetup {
    HeightMap map = smooth_map(64);
    std::string method = "pom";
    Triplanar triplanar;
    ShadeSettings shading;
    Image4 albedo;
};

TriRun run_frame(const EngineFrame& f, const FrameSetup& s, bool triplanar,
                 const EngineLight& light) {
    auto rt = runtime();
    const cl::Context& ctx = rt->context();
    EngineGBuffer in = f.to_device(ctx);
    in.light = light;
    const size_t n = f.pixels();
    const bool lit = light.kind != LightKind::None;
    DeviceGBuffer g = allocate_gbuffer(*rt, f.width, f.height, lit, false);
    const std::vector<float> ones(n, 1.0f);
    g.material = cl::Buffer(ctx, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, n * sizeof(float),
                            const_cast<float*>(ones.data()));
    FrameMaterial m;
    m.id = 1;
    m.name = "rocks";
    m.settings = wrap_settings(0.05f, 1.0f);
    m.field = upload(*rt, s.map, m.settings);
    m.params = resolve_params(find_method(s.method), {});
    if (s.albedo.width) m.albedo = upload(*rt, s.albedo);
    if (triplanar) m.triplanar = s.triplanar;
    MaterialFrame frame(rt, {m});
    const OffsetTargets t = t_all(*rt, n);
    cl::Buffer rgba(ctx, CL_MEM_READ_WRITE, n * sizeof(cl_float4));
    ReconstructPass reconstruct(rt);
    TriRun r;
    if (triplanar) {
        const TriplanarPlanes planes = allocate_triplanar(*rt, f.width, f.height);
        reconstruct.enqueue(in, g, frame.triplanar_table(), planes);
        frame.enqueue(g, t, planes);
        frame.shade(g, frame_shade_inputs(t, &planes), s.shading, {rgba});
        r.blend = read_plane<cl_float4>(*rt, planes.blend, n);
        r.uv2 = read_plane<cl_float2>(*rt, planes.second.uv, n);
        r.uv3 = read_plane<cl_float2>(*rt, planes.third.uv, n);
        r.view2 = read_plane<cl_float4>(*rt, planes.second.view, n);
        r.view3 = read_plane<cl_float4>(*rt, planes.third.view, n);
        r.ray_scale = read_plane<float>(*rt, planes.ray_scale, n);
        r.ids2 = read_plane<float>(*rt, planes.second.material, n);
        r.ids3 = read_plane<float>(*rt, planes.third.material, n);
        r.depth2 = read_plane<float>(*rt, planes.second_targets.depth, n);
        r.depth3 = read_plane<float>(*rt, planes.third_targets.depth, n);
        r.fetches2 = read_plane<cl_uint>(*rt, planes.second_targets.fetches, n);
        r.fetches3 = read_plane<cl_uint>(*rt, planes.third_targets.fetches, n);
        r.flags2 = read_plane<cl_uint>(*rt, planes.second_targets.flags, n);
        // The dominant projection alone: the same table without the projection.
        FrameMaterial plain = m;
        plain.triplanar.enabled = false;
        MaterialFrame uv_frame(rt, {plain});
        const OffsetTargets alone = t_all(*rt, n);
        uv_frame.enqueue(g, alone);
        r.depth1 = read_plane<float>(*rt, alone.depth, n);
        r.fetches1 = read_plane<cl_uint>(*rt, alone.fetches, n);
    } else {
        reconstruct.enqueue(in, g);
        frame.enqueue(g, t);
        frame.shade(g, frame_shade_inputs(t), s.shading, {rgba});
    }
    r.uv = read_plane<cl_float2>(*rt, g.uv, n);
    r.view = read_plane<cl_float4>(*rt, g.view, n);
    if (lit) r.light = read_plane<cl_float4>(*rt, g.light, n);
    r.uv_out = read_plane<cl_float2>(*rt, t.uv, n);
    r.depth = read_plane<float>(*rt, t.depth, n);
    r.fetches = read_plane<cl_uint>(*rt, t.fetches, n);
    r.flags = read_plane<cl_uint>(*rt, t.flags, n);
    r.rgba = read_plane<cl_float4>(*rt, rgba, n);
    return r;
}

template <typename T>
size_t bits_apart(const std::vector<T>& a, const std::vector<T>& b) {
    size_t d = 0;
    for (size_t k = 0; k < a.size(); ++k) d += std::memcmp(&a[k], &b[k], sizeof(T)) != 0;
    return d;
}

EngineLight sun() {
    EngineLight l;
    l.kind = LightKind::Directional;
    l.vector = {0.45f, -0.3f, 0.84f};
    return l;
}

glm::dvec3 sun_direction() {
    const EngineLight l = sun();
    return glm::normalize(glm::dvec3(l.vector[0], l.vector[1], l.vector[2]));
}

// The floor (z = 0, normal +z exactly) projected from above is the uv-mapped frame whose uv is
// the projection's: every output bit for bit, with soft self-shadows, and the projection's uv is
// the world point's x and y times world_scale.
TEST(Triplanar, AnAxisAlignedPlaneIsTheUvMappedFrameBitForBit) {
    EngineFrame f = small_plane();
    FrameSetup s;
    s.triplanar.enabled = true;
    s.triplanar.world_scale = 4.0f;
    s.shading.shadow = ShadowMode::Soft;
    s.albedo = checker_like();
    const TriRun tri = run_frame(f, s, true, sun());
    size_t surface = 0;
    double worst_uv = 0;
    for (int y = 0; y < f.height; ++y)
        for (int x = 0; x < f.width; ++x) {
            const size_t k = static_cast<size_t>(y) * f.width + x;
            if (!std::isfinite(f.uv.v[2 * k])) continue;
            ++surface;
            // +Z alone, the normal (0, 0, 1): the plane holds 2 c (c = 4 or 10) and zeros.
            const Blend b = unpack(tri.blend[k]);
            ASSERT_TRUE(b.on && b.p0 == 4 && b.w[0] == 1.0f && b.nx == 0 && b.ny == 0) << k;
            ASSERT_EQ(tri.ids2[k], 0.0f);
            ASSERT_EQ(tri.ids3[k], 0.0f);
            const WorldPoint w = world_point(f, x, y);
            // uv = 4 p, rounded once more.
            const double tol = 4.0 * w.bound + 1e-7 * (std::abs(tri.uv[k].s[0]) + 1.0);
            for (int i = 0; i < 2; ++i) {
                const double e = std::abs(tri.uv[k].s[i] - 4.0 * w.p[i]);
                worst_uv = std::max(worst_uv, e / tol);
                ASSERT_LE(e, tol) << k << " component " << i;
            }
        }
    ASSERT_GT(surface, f.pixels() / 2);
    // The uv-mapped frame given the projection's uv.
    for (size_t k = 0; k < f.pixels(); ++k)
        if (std::isfinite(f.uv.v[2 * k])) {
            f.uv.v[2 * k] = tri.uv[k].s[0];
            f.uv.v[2 * k + 1] = tri.uv[k].s[1];
        }
    const TriRun uv = run_frame(f, s, false, sun());
    EXPECT_EQ(bits_apart(tri.view, uv.view), 0u);
    EXPECT_EQ(bits_apart(tri.light, uv.light), 0u);
    EXPECT_EQ(bits_apart(tri.uv_out, uv.uv_out), 0u);
    EXPECT_EQ(bits_apart(tri.depth, uv.depth), 0u);
    EXPECT_EQ(bits_apart(tri.fetches, uv.fetches), 0u);
    EXPECT_EQ(bits_apart(tri.flags, uv.flags), 0u);
    EXPECT_EQ(bits_apart(tri.rgba, uv.rgba), 0u);
    std::printf("[ floor ] %zu pixels, uv against the world point at most %.3g of its bound\n",
                surface, worst_uv);
}

// Normals over the whole sphere on the floor's points: the weights are the definition's (float
// rounding of the powers, whole exponents by squaring and 3.5 by exp2 and log2, and the two
// normalisations), sum to one, are zero exactly where the
// definition's are, come largest first with their projections' codes, and the second and third
// projections carry the pixel's id exactly where they weigh; their uv is the world point's in the
// projection's frame, V the view's over the surface in it and L the light's (a swapped or unsigned
// axis moves them by whole units).
TEST(Triplanar, WeightsAndProjectionsAreTheDefinitions) {
    EngineFrame f = small_plane();
    random_normals(f, 7);
    const glm::dvec3 l = sun_direction();
    const glm::dvec3 eye(f.camera.eye[0], f.camera.eye[1], f.camera.eye[2]);
    for (const auto& [k_exp, cutoff] :
         {std::pair{4.0f, 0.05f}, {8.0f, 0.2f}, {1.0f, 0.0f}, {3.5f, 0.1f}}) {
        FrameSetup s;
        s.triplanar.enabled = true;
        s.triplanar.world_scale = 3.0f;
        s.triplanar.sharpness = k_exp;
        s.triplanar.cutoff = cutoff;
        const TriRun r = run_frame(f, s, true, sun());
        size_t counts[3] = {0, 0, 0};
        double worst_w = 0, worst_uv = 0, worst_v = 0;
        for (int y = 0; y < f.height; ++y)
            for (int x = 0; x < f.width; ++x) {
                const size_t k = static_cast<size_t>(y) * f.width + x;
                const glm::dvec3 n(f.normal.v[4 * k], f.normal.v[4 * k + 1], f.normal.v[4 * k + 2]);
                const glm::dvec3 w = weights_of(n, k_exp, cutoff);
                const Blend b = unpack(r.blend[k]);
                ASSERT_TRUE(b.on) << k;
                // The second and third on the axes of the first's T and B, in the order the
                // plane says, each signed as the normal on its axis.
                const Frame f0 = frame_of(b.p0);
                auto axis_of = [](const glm::dvec3& v) { return v.x != 0 ? 0 : v.y != 0 ? 1 : 2; };
                const int at = axis_of(f0.t), ab = axis_of(f0.b);
                const int p[3] = {b.p0, projection_of(n, b.b_first ? ab : at),
                                  projection_of(n, b.b_first ? at : ab)};
                ASSERT_EQ(p[0], projection_of(n, b.p0 >> 1)) << k;
                ASSERT_GE(b.w[0], b.w[1]);
                ASSERT_GE(b.w[1], b.w[2]);
                // The normal in the first projection's frame (float normalisation of the stored
                // normal).
                ASSERT_NEAR(b.nx, glm::dot(n, f0.t), 1e-6) << k;
                ASSERT_NEAR(b.ny, glm::dot(n, f0.b), 1e-6) << k;
                for (int j = 0; j < 3; ++j) {
                    const int axis = p[j] >> 1;
                    const double e = std::abs(b.w[j] - w[axis]);
                    // The powers (a few ulps each) over a sum of three, w1 kept to 2^-20 in the
                    // plane, w0 = 1 - w1 - w2.
                    worst_w = std::max(worst_w, e);
                    ASSERT_LE(e, 2e-5 * k_exp) << k << " weight " << j;
                    if (w[axis] == 0) {
                        ASSERT_EQ(b.w[j], 0.0f) << k;
                    }
                }
                ++counts[(b.w[1] > 0) + (b.w[2] > 0)];
                ASSERT_EQ(r.ids2[k], b.w[1] > 0 ? 1.0f : 0.0f) << k;
                ASSERT_EQ(r.ids3[k], b.w[2] > 0 ? 1.0f : 0.0f) << k;
                // The dominant projection in the G-buffer, the second in its planes.
                const WorldPoint wp = world_point(f, x, y);
                const glm::dvec3 v = glm::normalize(eye - wp.p);
                for (int j = 0; j < 2; ++j) {
                    if (j == 1 && !(b.w[1] > 0)) continue;
                    const Frame fr = frame_of(p[j]);
                    const cl_float2 uv = j == 0 ? r.uv[k] : r.uv2[k];
                    const cl_float4 vv = j == 0 ? r.view[k] : r.view2[k];
                    const double tol = 3.0 * (3.0 * wp.bound + 1e-6 * (glm::length(wp.p) + 1));
                    const double eu = std::max(std::abs(uv.s[0] - 3.0 * glm::dot(wp.p, fr.t)),
                                               std::abs(uv.s[1] - 3.0 * glm::dot(wp.p, fr.b)));
                    worst_uv = std::max(worst_uv, eu / tol);
                    ASSERT_LE(eu, tol) << k << " projection " << j;
                    // V over the surface: its T and B components less its normal share, its
                    // depth along the normal, normalised. From the float point (its error over
                    // the distance to the eye) and the float normal, both divided by the sheared
                    // length the normalisation undoes (at least the normal's share on the axis).
                    const double vn = glm::dot(v, n);
                    const glm::dvec3 ve(glm::dot(v, fr.t) - vn * glm::dot(n, fr.t),
                                        glm::dot(v, fr.b) - vn * glm::dot(n, fr.b), vn);
                    const double len = glm::length(ve);
                    const glm::dvec3 want = ve / len;
                    const double tv = 2.0 * (wp.bound / glm::length(eye - wp.p) + 1e-6) / len;
                    const double ev =
                        std::max({std::abs(vv.s[0] - want.x), std::abs(vv.s[1] - want.y),
                                  std::abs(vv.s[2] - want.z)});
                    worst_v = std::max(worst_v, ev / tv);
                    ASSERT_LE(ev, tv) << k << " projection " << j;
                    // Its t scale, 1 / the sheared length, to the same relative bound.
                    const double scale = j == 0 ? r.ray_scale[k] : vv.s[3];
                    ASSERT_LE(std::abs(scale * len - 1.0), tv) << k << " projection " << j;
                    if (j == 0) {
                        const cl_float4 lv = r.light[k];
                        ASSERT_NEAR(lv.s[0], glm::dot(l, fr.t), 1e-6);
                        ASSERT_NEAR(lv.s[1], glm::dot(l, fr.b), 1e-6);
                        ASSERT_NEAR(lv.s[2], glm::dot(l, fr.n), 1e-6);
                    }
                }
            }
        std::printf(
            "[ k %g cutoff %g ] one projection %zu, two %zu, three %zu pixels; weights "
            "within %.2g, uv at most %.2g and V %.2g of their bounds\n",
            k_exp, cutoff, counts[0], counts[1], counts[2], worst_w, worst_uv, worst_v);
        if (cutoff > 0) {
            EXPECT_GT(counts[0], 0u);
            EXPECT_GT(counts[1], 0u);
        } else {
            EXPECT_EQ(counts[2], f.pixels()) << "no cutoff: every projection weighs";
        }
        if (cutoff < 0.1f) {
            EXPECT_GT(counts[2], 0u);
        }
    }
}

// A flat relief (constant heights: every projection's normal is its axis, uv' is uv) shades each
// pixel as its surface normal alone: the reoriented normals of the projections, turned into the
// dominant frame and blended, are the normal itself. So the colour is albedo (ambient + diffuse
// max(N.L, 0)) at every pixel of any normal, where a swapped or unsigned axis in the frames, the
// reorientation or the blend tilts it.
TEST(Triplanar, AFlatReliefShadesAsItsNormal) {
    EngineFrame f = small_plane();
    random_normals(f, 19);
    FrameSetup s;
    s.map = constant_map(1.0f, 16, 16);
    s.triplanar.enabled = true;
    s.triplanar.world_scale = 2.0f;
    s.triplanar.cutoff = 0.02f;
    s.shading.specular = 0.0f;
    const float albedo[3] = {0.8f, 0.6f, 0.4f};
    s.albedo = constant_albedo(albedo[0], albedo[1], albedo[2]);
    const glm::dvec3 l = sun_direction();
    const TriRun r = run_frame(f, s, true, sun());
    double worst = 0;
    size_t blended = 0;
    for (size_t k = 0; k < f.pixels(); ++k) {
        const glm::dvec3 n(f.normal.v[4 * k], f.normal.v[4 * k + 1], f.normal.v[4 * k + 2]);
        const double lit = s.shading.ambient + s.shading.diffuse * std::max(glm::dot(n, l), 0.0);
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, std::abs(r.rgba[k].s[c] - albedo[c] * lit));
        blended += unpack(r.blend[k]).w[1] > 0;
    }
    std::printf("[ flat relief ] %zu of %zu pixels blended; colour within %.2g of the normal's\n",
                blended, f.pixels(), worst);
    EXPECT_GT(blended, f.pixels() / 4);
    // The normals' float rounding through two frames and a normalisation.
    EXPECT_LT(worst, 2e-5);
}

// Where a pixel blends, its depth is the weighted depth of its projections' traces and its fetches
// their sum; where one projection covers it, its dominant trace's alone, bit for bit. A
// projection whose plane the view meets from behind (V.z <= 0 in its frame: random normals face
// every way) is the pass's BACKFACING pixel: uv passed through, nothing fetched.
TEST(Triplanar, ABlendMergesDepthAndFetches) {
    EngineFrame f = small_plane();
    random_normals(f, 23);
    FrameSetup s;
    s.triplanar.enabled = true;
    s.triplanar.world_scale = 3.0f;
    const TriRun r = run_frame(f, s, true, sun());
    size_t blended = 0, traced = 0;
    for (size_t k = 0; k < f.pixels(); ++k) {
        const Blend b = unpack(r.blend[k]);
        // Each projection's t along its unit ray over the surface, times that ray's scale: t
        // along the world ray.
        const float s0 = r.ray_scale[k], s1 = r.view2[k].s[3], s2 = r.view3[k].s[3];
        ASSERT_GT(s0, 0.0f) << k;
        if (!(b.w[1] > 0)) {
            const float want = r.depth1[k] * s0;
            ASSERT_EQ(std::memcmp(&r.depth[k], &want, sizeof(float)), 0) << k;
            ASSERT_EQ(r.fetches[k], r.fetches1[k]) << k;
            continue;
        }
        ++blended;
        const double want = double(b.w[0]) * r.depth1[k] * s0 + double(b.w[1]) * r.depth2[k] * s1 +
                            (b.w[2] > 0 ? double(b.w[2]) * r.depth3[k] * s2 : 0.0);
        const double mag = std::abs(b.w[0] * r.depth1[k] * s0) +
                           std::abs(b.w[1] * r.depth2[k] * s1) +
                           (b.w[2] > 0 ? std::abs(b.w[2] * r.depth3[k] * s2) : 0.0);
        ASSERT_NEAR(r.depth[k], want, 4e-7 * mag + 1e-12) << k;
        ASSERT_EQ(r.fetches[k], r.fetches1[k] + r.fetches2[k] + (b.w[2] > 0 ? r.fetches3[k] : 0u))
            << k;
        const bool behind = (r.flags2[k] & OM_FLAG_BACKFACING) != 0;
        ASSERT_EQ(r.fetches2[k] == 0, behind) << k;
        traced += !behind;
    }
    std::printf("[ blend ] %zu pixels blended, %zu of them traced in their second projection\n",
                blended, traced);
    EXPECT_GT(blended, f.pixels() / 4);
    EXPECT_GT(traced, blended / 4);
}

// A parameter out of range, clamp addressing, or an engine G-buffer without the planes a
// triplanar material reads, is refused naming the material and what is wrong.
TEST(Triplanar, BadInputIsNamed) {
    auto rt = runtime();
    auto cliff = [&] {
        FrameMaterial m;
        m.id = 3;
        m.name = "cliff";
        m.settings = wrap_settings(0.05f, 1.0f);
        m.field = upload(*rt, smooth_map(16), m.settings);
        m.params = resolve_params(find_method("pom"), {});
        m.triplanar.enabled = true;
        return m;
    };
    auto table_error = [&](auto edit) {
        FrameMaterial m = cliff();
        edit(m);
        return error_of([&] { MaterialFrame frame(rt, {m}); });
    };
    EXPECT_TRUE(contains(table_error([](FrameMaterial& m) { m.triplanar.world_scale = 0; }),
                         "material 3 (cliff): world_scale 0"));
    EXPECT_TRUE(contains(table_error([](FrameMaterial& m) { m.triplanar.world_scale = NAN; }),
                         "world_scale nan"));
    EXPECT_TRUE(contains(table_error([](FrameMaterial& m) { m.triplanar.sharpness = 0.5f; }),
                         "material 3 (cliff): sharpness 0.5"));
    EXPECT_TRUE(
        contains(table_error([](FrameMaterial& m) { m.triplanar.cutoff = 0.5f; }), "cutoff 0.5"));
    EXPECT_TRUE(
        contains(table_error([](FrameMaterial& m) { m.settings.address = AddressMode::Clamp; }),
                 "needs wrap addressing"));
    // A disabled projection's parameters are not read.
    EXPECT_EQ(table_error([](FrameMaterial& m) {
                  m.triplanar.enabled = false;
                  m.triplanar.sharpness = 0;
              }),
              "");

    MaterialFrame frame(rt, {cliff()});
    const EngineFrame f = small_plane();
    DeviceGBuffer g = allocate_gbuffer(*rt, f.width, f.height, false, false);
    g.material = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, f.pixels() * sizeof(float));
    const TriplanarPlanes planes = allocate_triplanar(*rt, f.width, f.height);
    ReconstructPass pass(rt);
    auto reconstruct_error = [&](auto edit) {
        EngineGBuffer in = f.to_device(rt->context());
        edit(in);
        return error_of([&] { pass.enqueue(in, g, frame.triplanar_table(), planes); });
    };
    EXPECT_TRUE(contains(reconstruct_error([](EngineGBuffer& in) { in.normal = Input(); }),
                         "material 3 (cliff) is triplanar: it needs the engine G-buffer's normal"));
    EXPECT_TRUE(contains(reconstruct_error([](EngineGBuffer& in) { in.depth = Input(); }),
                         "material 3 (cliff) is triplanar: it needs the engine G-buffer's depth"));
    // Neither uv nor a tangent is needed.
    EXPECT_EQ(reconstruct_error([](EngineGBuffer& in) {
                  in.uv = Input();
                  in.tangent = Input();
              }),
              "");
    DeviceGBuffer no_ids = g;
    no_ids.material = cl::Buffer();
    EXPECT_TRUE(contains(error_of([&] {
                             pass.enqueue(f.to_device(rt->context()), no_ids,
                                          frame.triplanar_table(), planes);
                         }),
                         "material ids"));
    // Without the planes the frame would trace and shade its pixels with no uv of theirs.
    OffsetTargets all = t_all(*rt, f.pixels());
    EXPECT_TRUE(contains(error_of([&] { frame.enqueue(g, all); }),
                         "material 3 (cliff) is triplanar: the material frame's enqueue needs its "
                         "projections"));
    cl::Buffer rgba(rt->context(), CL_MEM_READ_WRITE, f.pixels() * sizeof(cl_float4));
    EXPECT_TRUE(contains(error_of([&] { frame.shade(g, frame_shade_inputs(all), {}, {rgba}); }),
                         "the material frame's shade needs its projections"));
    EXPECT_TRUE(contains(error_of([&] {
                             frame.enqueue(g, all, LayerBehind{g, all});
                         }),
                         "the layer behind does not trace triplanar materials: material 3"));
    const TriplanarPlanes small = allocate_triplanar(*rt, 8, 8);
    OffsetTargets t;
    t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, f.pixels() * sizeof(cl_float2));
    EXPECT_TRUE(
        contains(error_of([&] { frame.enqueue(g, t, small); }), "the triplanar planes are 8x8"));
    // The splits above that were accepted ran: finished before their buffers go.
    rt->queue().finish();
}

}  // namespace
}  // namespace omtest
