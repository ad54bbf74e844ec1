// The receivers' shadow test (ShadowMaskPass) on analytic scenes: the ground y = 0 seen by a
// perspective camera, and a directional light's orthographic map of the ground alone (every
// pixel lit at any light angle: the receiver's plane is the bias) or of the ground under a roof
// of known height (the shadow's edge where the roof's edge casts it).
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "camera_forms.hpp"
#include "offsetmap/shadow_mask_pass.hpp"
#include "support.hpp"

namespace omtest {
namespace {

// Where the ray of pixel (x, y) (rows bottom first) of a w x h view meets the plane y = level
// within x in [x0, x1], as the fraction s from its near point (NDC z -1) to its far one (+1);
// 2 where it does not.
double ray_meets(const glm::dmat4& inverse, int x, int y, int w, int h, double level, double x0,
                 double x1) {
    const double nx = (2.0 * x + 1.0) / w - 1.0, ny = (2.0 * y + 1.0) / h - 1.0;
    const glm::dvec4 a4 = inverse * glm::dvec4(nx, ny, -1.0, 1.0);
    const glm::dvec4 b4 = inverse * glm::dvec4(nx, ny, 1.0, 1.0);
    const glm::dvec3 a = glm::dvec3(a4) / a4.w, b = glm::dvec3(b4) / b4.w;
    if (a.y == b.y) return 2.0;
    const double s = (a.y - level) / (a.y - b.y);
    const double hx = a.x + s * (b.x - a.x);
    return s >= 0.0 && s <= 1.0 && hx >= x0 && hx <= x1 ? s : 2.0;
}

struct ShadowScene {
    int w = 160, h = 120, n = 128;  // the frame, the map (square)
    double half = 6.0;              // the light's half extent, m
    double elevation = 0.0;         // radians
    glm::dmat4 camera, camera_inverse, light;
    std::vector<float> depth, map;   // GL window depth, rows bottom first
    std::vector<glm::dvec3> points;  // each pixel's ground point (x NaN on sky)
};

// The light comes from +x at `elevation_deg`; a roof of `roof` m (0: none) over x in [0, 10].
ShadowScene shadow_scene(double elevation_deg, double roof, int w = 160, int h = 120, int n = 128,
                         double half = 6.0) {
    ShadowScene s;
    s.w = w;
    s.h = h;
    s.n = n;
    s.half = half;
    s.elevation = elevation_deg * M_PI / 180.0;
    const glm::dvec3 toward(std::cos(s.elevation), std::sin(s.elevation), 0.0);
    const glm::dvec3 centre(-2.0, 0.0, 0.0);
    const glm::dvec3 up = elevation_deg > 89.0 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    s.light = glm::ortho(-s.half, s.half, -s.half, s.half, 1.0, 40.0) *
              glm::lookAt(centre + 20.0 * toward, centre, up);
    s.camera =
        glm::perspective(glm::radians(60.0), double(s.w) / s.h, 0.1, 50.0) *
        glm::lookAt(glm::dvec3(-3.0, 3.0, 6.0), glm::dvec3(-1.5, 0.0, 0.0), glm::dvec3(0, 1, 0));
    s.camera_inverse = glm::inverse(s.camera);
    const glm::dmat4 light_inverse = glm::inverse(s.light);
    for (int y = 0; y < s.h; ++y)
        for (int x = 0; x < s.w; ++x) {
            const double t = ray_meets(s.camera_inverse, x, y, s.w, s.h, 0.0, -1e9, 1e9);
            if (t > 1.0) {
                s.depth.push_back(1.0f);
                s.points.push_back(glm::dvec3(NAN));
                continue;
            }
            const double nx = (2.0 * x + 1.0) / s.w - 1.0, ny = (2.0 * y + 1.0) / s.h - 1.0;
            const glm::dvec4 a4 = s.camera_inverse * glm::dvec4(nx, ny, -1.0, 1.0);
            const glm::dvec4 b4 = s.camera_inverse * glm::dvec4(nx, ny, 1.0, 1.0);
            const glm::dvec3 p =
                glm::dvec3(a4) / a4.w + t * (glm::dvec3(b4) / b4.w - glm::dvec3(a4) / a4.w);
            const glm::dvec4 c = s.camera * glm::dvec4(p, 1.0);
            s.depth.push_back(static_cast<float>(0.5 * c.z / c.w + 0.5));
            s.points.push_back(p);
        }
    // An orthographic map's window depth is linear along its rays: the fraction itself.
    for (int j = 0; j < s.n; ++j)
        for (int i = 0; i < s.n; ++i) {
            double d = ray_meets(light_inverse, i, j, s.n, s.n, 0.0, -1e9, 1e9);
            if (roof > 0.0)
                d = std::min(d, ray_meets(light_inverse, i, j, s.n, s.n, roof, 0.0, 10.0));
            s.map.push_back(static_cast<float>(std::min(d, 1.0)));
        }
    return s;
}

// The test of the scene's frame against its map, the frame's camera in `form` and the map's in
// `map_form`: the mask in GL's rows (bottom first).
std::vector<float> shadow_mask(const ShadowScene& s, int radius, const CameraForm& form = {},
                               const CameraForm& map_form = {}) {
    auto rt = runtime();
    ShadowMaskInputs p;
    p.width = s.w;
    p.height = s.h;
    p.camera = form.camera(s.camera);
    p.depth = device_floats(*rt, form.depth_plane(s.depth, s.w, s.h));
    p.map.width = p.map.height = s.n;
    p.map.camera = map_form.camera(s.light);
    p.map.view_projection = map_form.view_projection(s.light);
    p.map.depth = device_floats(*rt, map_form.depth_plane(s.map, s.n, s.n));
    p.pcf_radius = radius;
    cl::Buffer out(rt->context(), CL_MEM_WRITE_ONLY, s.depth.size() * sizeof(float));
    ShadowMaskPass(rt).enqueue(p, {out}).wait();
    std::vector<float> mask(s.depth.size());
    rt->queue().enqueueReadBuffer(out, CL_TRUE, 0, mask.size() * sizeof(float), mask.data());
    return form.rows(mask, s.w, s.h);
}

// The map's texel along the ground: its world size over sin(elevation).
double ground_texel(const ShadowScene& s) { return 2.0 * s.half / s.n / std::sin(s.elevation); }

// Each camera form (tests/camera_forms.hpp) with the map in another: GL's own, and every depth
// convention and row order for both, paired so that each form meets a map of a different one.
std::vector<std::pair<CameraForm, CameraForm>> form_pairs() {
    const std::vector<CameraForm> forms = camera_forms();
    std::vector<std::pair<CameraForm, CameraForm>> pairs;
    for (size_t k = 0; k < forms.size(); ++k)
        pairs.push_back({forms[k], forms[k == 0 ? 0 : (k + 3) % forms.size()]});
    return pairs;
}

std::string form_trace(const std::pair<CameraForm, CameraForm>& f) {
    return "camera " + f.first.name() + ", map " + f.second.name();
}

// The receiver's plane is the bias: a lit plane meets its own map entry at every light angle, in
// every convention (a test that compared the wrong way round in a reversed map, or unprojected a
// row flipped, would darken the ground).
TEST(ShadowMask, LitGroundHasNoAcneAtAnyLightAngle) {
    for (double elevation : {5.0, 12.0, 30.0, 60.0, 90.0}) {
        SCOPED_TRACE(elevation);
        const ShadowScene s = shadow_scene(elevation, 0.0);
        for (const auto& forms : form_pairs())
            for (int radius : {0, 1, 2}) {
                SCOPED_TRACE(form_trace(forms));
                if (radius != 1 && forms.first.name() != "gl/bottom") continue;
                const std::vector<float> mask = shadow_mask(s, radius, forms.first, forms.second);
                size_t ground = 0, dark = 0;
                for (size_t k = 0; k < mask.size(); ++k) {
                    if (s.depth[k] >= 1.0f) {
                        EXPECT_EQ(mask[k], 1.0f) << "sky " << k;
                        continue;
                    }
                    ++ground;
                    dark += mask[k] < 1.0f;
                }
                EXPECT_GT(ground, mask.size() / 3);
                EXPECT_EQ(dark, 0u) << "radius " << radius << ": pixels of a lit plane in shadow";
            }
    }
}

TEST(ShadowMask, RoofCastsItsEdgeWhereTheLightPutsIt) {
    const double roof = 0.5;
    for (double elevation : {20.0, 45.0}) {
        SCOPED_TRACE(elevation);
        const ShadowScene s = shadow_scene(elevation, roof);
        // A ground point x is under the roof's shadow for x in [0, 10] - roof cot(elevation).
        const double edge = -roof / std::tan(s.elevation);
        for (const auto& forms : form_pairs())
            for (int radius : {0, 1}) {
                SCOPED_TRACE(form_trace(forms));
                const std::vector<float> mask = shadow_mask(s, radius, forms.first, forms.second);
                // The map holds the roof's edge to half a texel; the filter reaches r texels more.
                const double reach = (radius + 0.5) * ground_texel(s) + 1e-3;
                size_t lit = 0, shadowed = 0, between = 0;
                for (size_t k = 0; k < mask.size(); ++k) {
                    const glm::dvec3 p = s.points[k];
                    if (std::isnan(p.x) || std::abs(p.z) > 5.0 || p.x > 4.0) continue;
                    if (p.x < edge - reach) {
                        EXPECT_EQ(mask[k], 1.0f) << "x " << p.x << " before the edge " << edge;
                        ++lit;
                    } else if (p.x > edge + reach) {
                        EXPECT_EQ(mask[k], 0.0f) << "x " << p.x << " past the edge " << edge;
                        ++shadowed;
                    } else {
                        ++between;
                        if (radius > 0 && std::abs(p.x - edge) < 0.2 * ground_texel(s)) {
                            EXPECT_GT(mask[k], 0.0f) << "the filter's penumbra at " << p.x;
                        }
                    }
                }
                EXPECT_GT(lit, 500u);
                EXPECT_GT(shadowed, 500u);
                EXPECT_GT(between, 0u);
            }
    }
}

// A small frame whose map covers only part of it (taps past the map's edges are lit) and a wide
// filter: what Oclgrind runs (tests/portability/oclgrind_check.sh).
TEST(ShadowMask, SmallFrameWithTapsPastTheMapsEdges) {
    const ShadowScene s = shadow_scene(35.0, 0.5, 19, 13, 16, 2.5);
    const std::vector<float> mask = shadow_mask(s, 2);
    size_t partly = 0, sky = 0;
    for (size_t k = 0; k < mask.size(); ++k) {
        ASSERT_GE(mask[k], 0.0f);
        ASSERT_LE(mask[k], 1.0f);
        if (s.depth[k] >= 1.0f) {
            EXPECT_EQ(mask[k], 1.0f);
            ++sky;
        }
        partly += mask[k] > 0.0f && mask[k] < 1.0f;
    }
    EXPECT_GT(sky, 0u);
    EXPECT_GT(partly, 0u) << "the roof's penumbra or the map's edge";
}

// A spot light's perspective map: the ground points in front of the light and inside its view
// meet a map whose every texel is at the near plane (in shadow); those behind the light (clip w
// <= 0, which the projection would flip into the map) and those outside its view are lit, as a
// tap past the map's edge is: the spot's cone darkens them in the shading.
TEST(ShadowMask, PointsBehindASpotLightAreOutsideItsMap) {
    ShadowScene s = shadow_scene(35.0, 0.0);
    const glm::dvec3 lamp(-1.5, 0.5, 0.0);
    s.light = glm::perspective(glm::radians(50.0), 1.0, 0.1, 30.0) *
              glm::lookAt(lamp, lamp + glm::dvec3(1.0, 0.2, 0.0), glm::dvec3(0, 1, 0));
    s.map.assign(size_t(s.n) * s.n, 0.0f);
    const std::vector<float> mask = shadow_mask(s, 0);
    size_t behind = 0, inside = 0, mirrored = 0;
    for (size_t k = 0; k < mask.size(); ++k) {
        if (s.depth[k] >= 1.0f) continue;
        const glm::dvec4 c = s.light * glm::dvec4(s.points[k], 1.0);
        mirrored += c.w < 0.0 && std::abs(c.x) < -c.w && std::abs(c.y) < -c.w;
        const bool in_view = c.w > 0.0 && std::abs(c.x) < 0.99 * c.w && std::abs(c.y) < 0.99 * c.w;
        if (c.w <= 0.0) {
            ++behind;
            ASSERT_EQ(mask[k], 1.0f) << "behind the light: " << k;
        } else if (in_view && c.w > 0.2) {
            ++inside;
            ASSERT_EQ(mask[k], 0.0f) << "in its view: " << k;
        }
    }
    EXPECT_GT(behind, mask.size() / 20);
    EXPECT_GT(mirrored, mask.size() / 50) << "points whose flipped projection lands in the map";
    EXPECT_GT(inside, mask.size() / 50);
    std::printf(
        "spot map: %zu points behind the light (%zu of them flipped into the map), %zu "
        "inside its view\n",
        behind, mirrored, inside);
}

TEST(ShadowMask, BadParametersAreRefused) {
    auto rt = runtime();
    cl::Buffer b(rt->context(), CL_MEM_READ_WRITE, 16);
    ShadowMaskPass pass(rt);
    ShadowMaskInputs in;
    in.width = in.height = 2;
    in.depth = b;
    in.map.width = in.map.height = 2;
    in.map.view_projection = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    in.map.depth = b;
    EXPECT_EQ(error_of([&] { pass.enqueue(in, {b}).wait(); }), "");
    ShadowMaskInputs wide = in;
    wide.pcf_radius = 9;
    EXPECT_TRUE(
        contains(error_of([&] { pass.enqueue(wide, {b}); }), "filter radius must be in [0, 8]"));
    ShadowMaskInputs empty = in;
    empty.map.width = 0;
    EXPECT_TRUE(contains(error_of([&] { pass.enqueue(empty, {b}); }), "at least 1x1"));
    ShadowMaskInputs small = in;
    small.map.width = small.map.height = 3;
    EXPECT_TRUE(contains(error_of([&] { pass.enqueue(small, {b}); }), "shadow map's depth buffer"));
    ShadowMaskInputs odd = in;
    odd.map.camera.first_row = static_cast<FirstRow>(0);
    EXPECT_TRUE(contains(error_of([&] { pass.enqueue(odd, {b}); }), "first row"));
}
}  // namespace
}  // namespace omtest
