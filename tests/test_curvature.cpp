// The base surface's curvature per vertex (derive_curvature) against the primitives' analytic
// second fundamental form: exact on a sphere and a cylinder (their vertex normals are a linear
// function of the position, so every face's fit is the surface's own tensor), first order with a
// second-order rate on a torus, and k_TB's sign on a cylinder whose uv runs diagonally; core's
// helper (mesh_curvature.hpp) on an engine's packed arrays, and what it refuses.
#include <algorithm>
#include <glm/glm.hpp>
#include <vector>

#include "offsetmap/image_io.hpp"
#include "offsetmap/mesh_curvature.hpp"
#include "support.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/mesh.hpp"
#endif

namespace omtest {
namespace {

#ifdef OFFSETMAP_HAVE_RENDERER
using namespace offsetmap::renderer;

glm::dvec3 g(const Vec3& v) { return {v[0], v[1], v[2]}; }

// The shortest and longest edge of a mesh, leaving out the edges of a pole's degenerate
// triangles (copies of one point, apart by float rounding alone).
std::pair<double, double> edge_range(const Mesh& m) {
    std::vector<double> edges;
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3)
        for (int i = 0; i < 3; ++i)
            edges.push_back(glm::length(g(m.vertices[m.indices[t + i]].position) -
                                        g(m.vertices[m.indices[t + (i + 1) % 3]].position)));
    const double hi = *std::max_element(edges.begin(), edges.end());
    double lo = hi;
    for (double e : edges)
        if (e > 1e-4 * hi) lo = std::min(lo, e);
    return {lo, hi};
}

// The vertex's (T, B) frame as the G-buffer stores it.
std::pair<glm::dvec3, glm::dvec3> frame(const Vertex& v) {
    const glm::dvec3 n = glm::normalize(g(v.normal));
    const glm::dvec3 t = glm::normalize(glm::dvec3(v.tangent[0], v.tangent[1], v.tangent[2]));
    return {t, (v.tangent[3] < 0.0f ? -1.0 : 1.0) * glm::cross(n, t)};
}

// The largest difference between a vertex's curvature and the world tensor K seen in its own
// frame (so the frame's own derivation, a chord's angle off the analytic tangent, is not counted).
double error_against(const Vertex& v, const glm::dmat3& K) {
    const auto [t, b] = frame(v);
    return std::max({std::fabs(v.curvature[0] - glm::dot(t, K * t)),
                     std::fabs(v.curvature[1] - glm::dot(t, K * b)),
                     std::fabs(v.curvature[2] - glm::dot(b, K * b))});
}

// Float rounding alone: positions and normals each within half an ulp of |p| (and of 1), so a
// normal's difference over an edge of h is off by about 2^-23 (1 + |p|) in 2^-23-scaled units,
// relative to its size h k: 16 ulps over the shortest edge, as a curvature.
double float_tolerance(const Mesh& m, double reach) {
    return 16.0 * std::ldexp(1.0, -23) * (1.0 + reach) / edge_range(m).first;
}

TEST(Curvature, SphereIsOneOverItsRadiusEverywhere) {
    const float R = 0.55f;
    const Mesh s = make_sphere("sphere", 1, {0.25f, 0.55f, -1.0f}, R, 64, 32, 4.0f, 2.0f);
    const double tol = float_tolerance(s, 1.5);
    double worst = 0.0;
    for (const Vertex& v : s.vertices) {
        const double e = error_against(v, glm::dmat3(1.0) / double(R));  // 1 / R every way
        ASSERT_LE(e, tol);
        worst = std::max(worst, e);
    }
    std::printf("sphere R = %.2f: worst |k - 1/R| %.2e (tolerance %.2e) 1/m\n", R, worst, tol);
    record_figure("curvature.sphere.worst", worst);
}

TEST(Curvature, CylinderBendsAroundAndNotAlong) {
    const float R = 0.45f;
    const Mesh c = make_cylinder("cylinder", 1, {1.45f, 0.0f, -2.3f}, R, 1.4f, 64, 3.0f, 1.5f);
    const double tol = float_tolerance(c, 4.0);
    size_t side = 0;
    for (const Vertex& v : c.vertices) {
        if (std::fabs(v.normal[1]) > 0.5f) {  // the caps: flat
            ASSERT_EQ(v.curvature, (std::array<float, 3>{0.0f, 0.0f, 0.0f}));
            continue;
        }
        const glm::dvec3 around = glm::cross(glm::dvec3(0.0, 1.0, 0.0), g(v.normal));
        ASSERT_LE(error_against(v, glm::outerProduct(around, around) / double(R)), tol);
        ++side;
    }
    EXPECT_EQ(side, 2u * 65u);
}

// The side's uv turned 45 degrees: T = (s + y) / sqrt 2, B = (y - s) / sqrt 2 over the principal
// directions s (around, 1 / R) and y (along, 0), so k_TT = k_BB = 1 / 2R and k_TB = -1 / 2R; with
// u mirrored the frame's handedness flips B and k_TB's sign with it.
TEST(Curvature, DiagonalUvGivesTheCrossTermWithItsSign) {
    const float R = 0.5f;
    for (const float mirror : {1.0f, -1.0f}) {
        SCOPED_TRACE(mirror);
        Mesh c = make_cylinder("cylinder", 1, {0.0f, 0.0f, 0.0f}, R, 1.0f, 96, 1.0f, 1.0f);
        for (Vertex& v : c.vertices) {
            if (std::fabs(v.normal[1]) > 0.5f) continue;
            const double arc = R * (double(v.uv[0]) * 2.0 * M_PI);  // uv u from 0 to 1 around
            const double y = v.position[1];
            v.uv = {float(mirror * (arc + y) / std::sqrt(2.0)), float((y - arc) / std::sqrt(2.0))};
        }
        derive_tangents(c);
        const double tol = float_tolerance(c, 2.0);
        for (const Vertex& v : c.vertices) {
            if (std::fabs(v.normal[1]) > 0.5f) continue;
            // About 1 / 2R each, the frame a chord's angle off the diagonal.
            ASSERT_NEAR(v.curvature[0], 0.5 / R, 0.01 / R);
            ASSERT_NEAR(v.curvature[1], -0.5 * mirror / R, 0.01 / R);
            ASSERT_NEAR(v.curvature[2], 0.5 / R, 0.01 / R);
            const glm::dvec3 n = glm::normalize(g(v.normal));
            const glm::dvec3 around = glm::cross(glm::dvec3(0.0, 1.0, 0.0), n);
            ASSERT_LE(error_against(v, glm::outerProduct(around, around) / double(R)), tol);
        }
    }
}

// The uv's stretch sqrt(|dP/du| / |dP/dv|): exact on a quad (2 m by 1 m in 4 by 1 tiles: 0.5 m
// per u, 1 m per v, log2 -1/2), none on a square one; on a cylinder's side (R 0.5 in 2 tiles
// around, 1 m in 3 along) sqrt(pi R 3) within the polygon's chord factor (sin x / x and cos x for
// x = pi / 96 together shrink dP/du by 7e-4: 1e-3 in the stretch); its caps' planar uv has none.
TEST(Curvature, UvStretchIsTheDensitiesRatio) {
    const Mesh quad = make_quad("quad", 1, {0, 0, 0}, {2, 0, 0}, {0, 1, 0}, 4.0f, 1.0f, false);
    for (const Vertex& v : quad.vertices) ASSERT_NEAR(v.uv_log_stretch, -0.5, 1e-6);
    const Mesh square = make_quad("square", 1, {0, 0, 0}, {2, 0, 0}, {0, 1, 0}, 2.0f, 1.0f, false);
    for (const Vertex& v : square.vertices) ASSERT_EQ(v.uv_log_stretch, 0.0f);
    const float R = 0.5f;
    const Mesh c = make_cylinder("cylinder", 1, {0.0f, 0.0f, 0.0f}, R, 1.0f, 96, 2.0f, 3.0f);
    const double want = std::sqrt(M_PI * R * 3.0);
    for (const Vertex& v : c.vertices) {
        const double a = std::exp2(double(v.uv_log_stretch));
        if (std::fabs(v.normal[1]) > 0.5f)
            ASSERT_NEAR(a, 1.0, 1e-5) << "a cap";
        else
            ASSERT_NEAR(a, want, 1e-3 * want);
    }
}

// A torus (R from the axis to the tube's centre, r the tube): at the tube angle theta the
// principal curvatures are cos(theta) / (R + r cos(theta)) around the axis (T) and 1 / r around
// the tube (B), k_TB = 0. The fit is first order: each face gives the tensor at a point of the
// face, so a vertex is within h max|dK/ds| of the truth, h the longest edge, |dK/ds| at most
// R / (r (R - r)^2) (k_TT's change along the tube). On a regular grid the faces around a vertex
// are symmetric and the first-order terms cancel: twice the resolution must take the error down
// at least 3 times.
TEST(Curvature, TorusIsItsPrincipalCurvaturesToSecondOrder) {
    const double R = 1.0, r = 0.3;
    double previous = 0.0;
    for (const int n : {32, 64}) {
        SCOPED_TRACE(n);
        const Mesh t =
            make_torus("torus", 1, {0.0f, 0.0f, 0.0f}, float(R), float(r), 2 * n, n, 4.0f, 1.0f);
        const double bound = edge_range(t).second * R / (r * (R - r) * (R - r));
        double worst = 0.0;
        for (const Vertex& v : t.vertices) {
            const glm::dvec3 n = glm::normalize(g(v.normal));
            const glm::dvec3 out = glm::normalize(glm::dvec3(v.position[0], 0.0, v.position[2]));
            const double cos_theta = glm::dot(n, out);
            const glm::dvec3 around = glm::cross(glm::dvec3(0.0, 1.0, 0.0), out);
            const glm::dvec3 tube = glm::cross(n, around);
            const glm::dmat3 K =
                cos_theta / (R + r * cos_theta) * glm::outerProduct(around, around) +
                glm::outerProduct(tube, tube) / r;
            const double e = error_against(v, K);
            const double theta = std::atan2(n.y, cos_theta);
            ASSERT_LE(e, bound) << "theta " << theta;
            worst = std::max(worst, e);
        }
        if (previous > 0.0) {
            EXPECT_LE(worst, previous / 3.0);
        }
        std::printf("torus %d x %d: worst error %.2e 1/m (first-order bound %.2e)\n", 2 * n, n,
                    worst, bound);
        record_figure("curvature.torus" + std::to_string(n) + ".worst", worst);
        previous = worst;
    }
}

// The G-buffer's curvature plane: the raster interpolates the vertices' tensors and scales them by
// the uv density into uv units. With one density per mesh, the sphere's pixels hold (d / R, 0,
// d / R) and the cylinder's side (d / R, 0, 0) up to the interpolation's float rounding; its caps
// and the sky hold zero. The cylinder's side holds its uv's stretch, its caps none, the sky 0. The
// engine G-buffer file keeps both bit for bit.
TEST(Renderer, GBufferCurvatureIsTheSurfaces) {
    const float Rs = 0.5f, Rc = 0.35f, ds = 0.8f, dc = 0.6f;
    Scene scene;
    scene.name = "curved";
    Mesh sphere = make_sphere("sphere", 1, {-0.45f, 0.5f, -2.0f}, Rs, 48, 24, 2.0f, 1.0f);
    Mesh cylinder = make_cylinder("cylinder", 2, {0.55f, 0.0f, -2.2f}, Rc, 1.0f, 48, 1.0f, 1.0f);
    for (Vertex& v : sphere.vertices) v.uv_density = ds;
    for (Vertex& v : cylinder.vertices) v.uv_density = dc;
    scene.meshes = {sphere, cylinder};
    scene.camera.eye = {0.0f, 1.2f, 0.4f};
    scene.camera.target = {0.0f, 0.4f, -2.0f};
    scene.light.kind = LightKind::None;
    std::vector<LoadedMaterial> table(2);
    for (int i = 0; i < 2; ++i) {
        table[i].spec.id = i + 1;
        table[i].spec.name = i ? "cylinder" : "sphere";
        table[i].map = make_map(8, 8, [](int, int) { return 0.5f; });
    }
    const int w = 160, h = 120;
    FrameRenderer r(runtime(), scene, table,
                    std::vector<MethodParams>(2, resolve_params(find_method("none"), {})), w, h,
                    ShadeSettings{});
    r.render(FrameMode::Deferred, false, 1);
    const EngineScene& e = r.gbuffer();
    ASSERT_EQ(e.curvature.size(), 3 * e.pixels());
    ASSERT_EQ(e.uv_stretch.size(), e.pixels());
    const double eps = 1e-5;  // a few float roundings of the barycentric blend, relative
    size_t on_sphere = 0, on_side = 0;
    for (size_t k = 0; k < e.pixels(); ++k) {
        const float* c = &e.curvature[3 * k];
        if (e.depth[k] >= 1.0f) {
            ASSERT_EQ(c[0], 0.0f);
            ASSERT_EQ(c[1], 0.0f);
            ASSERT_EQ(c[2], 0.0f);
            ASSERT_EQ(e.uv_stretch[k], 0.0f);
        } else if (e.material[k] == 1.0f) {
            ASSERT_NEAR(c[0], ds / Rs, eps * ds / Rs) << k;
            ASSERT_NEAR(c[1], 0.0, eps * ds / Rs) << k;
            ASSERT_NEAR(c[2], ds / Rs, eps * ds / Rs) << k;
            ++on_sphere;
        } else if (std::fabs(e.normal[4 * k + 1]) < 0.5f) {
            ASSERT_NEAR(c[0], dc / Rc, eps * dc / Rc) << k;
            ASSERT_NEAR(c[1], 0.0, eps * dc / Rc) << k;
            ASSERT_NEAR(c[2], 0.0, eps * dc / Rc) << k;
            // 2 pi Rc m around in one tile, 1 m along in one: the 48-gon's chord factor, 3e-3.
            ASSERT_NEAR(e.uv_stretch[k], std::sqrt(2.0 * M_PI * Rc), 3e-3) << k;
            ++on_side;
        } else {
            ASSERT_EQ(c[0], 0.0f) << "a cap, pixel " << k;
            ASSERT_NEAR(e.uv_stretch[k], 1.0f, 1e-5) << "a cap, pixel " << k;
        }
    }
    EXPECT_GT(on_sphere, 1000u);
    EXPECT_GT(on_side, 1000u);
    const std::string path = ::testing::TempDir() + "/curved_gbuffer.exr";
    save_engine_gbuffer(path, e);
    const EngineScene back = load_engine_gbuffer(path);
    EXPECT_EQ(back.curvature, e.curvature);
    EXPECT_EQ(back.uv_stretch, e.uv_stretch);
}

TEST(Curvature, FlatAndHardEdgedMeshesHaveNone) {
    const Mesh box = make_box("box", 1, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 1.0f);
    for (const Vertex& v : box.vertices)
        ASSERT_EQ(v.curvature, (std::array<float, 3>{0.0f, 0.0f, 0.0f}));
}

// The installed helper as an engine's import calls it, on packed arrays of its own: the same
// values the renderer's interleaved vertices get, bit for bit.
TEST(Curvature, PackedArraysGiveTheInterleavedVerticesValues) {
    const Mesh sphere = make_sphere("sphere", 1, {0.5f, 1, -2}, 0.8f, 24, 12, 2, 1);
    std::vector<float> positions, normals, tangents;
    for (const Vertex& v : sphere.vertices) {
        positions.insert(positions.end(), v.position.begin(), v.position.end());
        normals.insert(normals.end(), v.normal.begin(), v.normal.end());
        tangents.insert(tangents.end(), v.tangent.begin(), v.tangent.end());
    }
    offsetmap::CurvatureMesh mesh;
    mesh.positions = positions.data();
    mesh.normals = normals.data();
    mesh.tangents = tangents.data();
    mesh.vertex_count = sphere.vertices.size();
    mesh.indices = sphere.indices.data();
    mesh.index_count = sphere.indices.size();
    const std::vector<std::array<float, 3> > k = offsetmap::derive_curvature(mesh);
    ASSERT_EQ(k.size(), sphere.vertices.size());
    for (size_t v = 0; v < k.size(); ++v) ASSERT_EQ(k[v], sphere.vertices[v].curvature) << v;
}
#endif

TEST(Curvature, TheHelperRefusesWhatIsNotAMesh) {
    const float p[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0}, n[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    const float t[12] = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    const std::uint32_t tri[4] = {0, 1, 2, 3};
    offsetmap::CurvatureMesh m;
    m.positions = p;
    m.normals = n;
    m.tangents = t;
    m.vertex_count = 3;
    m.indices = tri;
    m.index_count = 3;
    const std::vector<std::array<float, 3> > flat = offsetmap::derive_curvature(m);
    ASSERT_EQ(flat.size(), 3u);
    for (const auto& k : flat) EXPECT_EQ(k, (std::array<float, 3>{0.0f, 0.0f, 0.0f}));
    offsetmap::CurvatureMesh bad = m;
    bad.index_count = 4;
    EXPECT_TRUE(contains(error_of([&] { offsetmap::derive_curvature(bad); }), "whole triangles"));
    bad.index_count = 3;
    bad.indices = tri + 1;
    EXPECT_TRUE(contains(error_of([&] { offsetmap::derive_curvature(bad); }),
                         "index 2 is 3, past the mesh's 3 vertices"));
    bad = m;
    bad.normals = nullptr;
    EXPECT_TRUE(contains(error_of([&] { offsetmap::derive_curvature(bad); }), "no positions"));
    EXPECT_TRUE(offsetmap::derive_curvature({}).empty());
}

}  // namespace
}  // namespace omtest
