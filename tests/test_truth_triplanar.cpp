// The truth of a triplanar material: its meshes cut along the world's lattice planes (every
// projection's texel centres) and displaced along the normal by the blended height. The mesh is
// the definition vertex by vertex, closed where its base is, each piece in one bilinear cell of
// every projection; on an axis-aligned floor it is the uv-mapped floor's truth, and over a tilted
// plane the frame's exact trace (the ray over the surface) meets it.
#include <algorithm>
#include <cstring>
#include <glm/glm.hpp>
#include <map>
#include <tuple>

#include "offsetmap/oracle.hpp"
#include "offsetmap/triplanar.hpp"
#include "support.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/truth.hpp"
#include "truth_support.hpp"
#endif

namespace omtest {
namespace {

#ifdef OFFSETMAP_HAVE_RENDERER
using namespace offsetmap::renderer;

// A map of zero bilinear twist (H = f(i) + g(j), under wrap too): each cell's bilinear patch is a
// plane, so a lattice of any diagonals displaces it exactly and two truths cut differently are
// one surface. Not square: z's planes come in two families.
HeightMap untwisted_map() {
    return make_map(16, 12, [](int i, int j) {
        return 0.5f + 0.25f * std::sin(0.9f * float(i)) + 0.2f * std::cos(1.3f * float(j));
    });
}

LoadedMaterial triplanar_material(const HeightMap& map, float world_scale, float sharpness,
                                  float cutoff) {
    LoadedMaterial m;
    m.spec.id = 1;
    m.spec.name = "tri";
    m.spec.method = "exact";
    m.spec.settings.scale = 0.05f;
    m.spec.settings.reference_plane = 0.7f;
    m.spec.settings.address = AddressMode::Wrap;
    m.spec.triplanar.enabled = true;
    m.spec.triplanar.world_scale = world_scale;
    m.spec.triplanar.sharpness = sharpness;
    m.spec.triplanar.cutoff = cutoff;
    m.map = map;
    return m;
}

// A sphere of shared vertices (an octahedron's faces subdivided `levels` times, pushed out to
// the radius), normals radial: closed, smooth, with no uv.
Mesh octasphere(glm::dvec3 centre, double radius, int levels) {
    std::vector<glm::dvec3> dirs = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                    {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    std::vector<std::array<std::uint32_t, 3>> faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                                       {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            const auto key = std::minmax(a, b);
            auto it = middle.find(key);
            if (it != middle.end()) return it->second;
            dirs.push_back(glm::normalize(dirs[a] + dirs[b]));
            return middle[key] = static_cast<std::uint32_t>(dirs.size() - 1);
        };
        std::vector<std::array<std::uint32_t, 3>> next;
        for (const auto& f : faces) {
            const std::uint32_t ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
            next.push_back({f[0], ab, ca});
            next.push_back({ab, f[1], bc});
            next.push_back({ca, bc, f[2]});
            next.push_back({ab, bc, ca});
        }
        faces = std::move(next);
    }
    Mesh m{"sphere", 1, {}, {}};
    for (const glm::dvec3& d : dirs) {
        Vertex v;
        const glm::dvec3 p = centre + radius * d;
        v.position = {float(p.x), float(p.y), float(p.z)};
        v.normal = {float(d.x), float(d.y), float(d.z)};
        m.vertices.push_back(v);
    }
    for (const auto& f : faces) m.indices.insert(m.indices.end(), f.begin(), f.end());
    return m;
}

glm::dvec3 position_of(const Vertex& v) { return {v.position[0], v.position[1], v.position[2]}; }

TEST(Renderer, TriplanarTruthIsTheBlendedReliefCutAlongTheWorldLattice) {
    const float ws = 2.0f;
    const LoadedMaterial m = triplanar_material(untwisted_map(), ws, 4.0f, 0.05f);
    const std::vector<LoadedMaterial> table = {m};
    for (const float tpq : {1.0f, 0.5f}) {
        SCOPED_TRACE(tpq);
        Scene scene;
        scene.name = "sphere";
        scene.meshes.push_back(octasphere({0.13, 0.71, -2.07}, 0.6, 3));
        project_from_world(scene.meshes[0], ws);
        TessellationOptions o;
        o.texels_per_quad = tpq;  // no view: nothing culled
        const Tessellation t = displace_scene(scene, table, o);
        ASSERT_EQ(t.meshes.size(), 1u);
        EXPECT_TRUE(t.meshes[0].triplanar);
        EXPECT_TRUE(std::isnan(t.meshes[0].height_bound));
        const Mesh& out = t.scene.meshes[0];
        ASSERT_EQ(out.indices.size(), 3 * t.meshes[0].triangles);

        // Every vertex the definition at its base point P (the tangent's xyz): displaced along
        // the unit normal by (1 / world_scale) s (sum of w_a H_a - r), each projection's H the
        // map's bilinear height at world_scale (P.T, P.B) of its frame. Float storage of P, the
        // normal and the position: 1e-6 of the sphere's 3 m reach, and the weights' slope.
        double worst = 0;
        for (const Vertex& v : out.vertices) {
            const glm::dvec3 p(v.tangent[0], v.tangent[1], v.tangent[2]);
            const glm::dvec3 n(v.normal[0], v.normal[1], v.normal[2]);
            ASSERT_NEAR(glm::length(n), 1.0, 1e-6);
            const std::array<double, 3> na = {n.x, n.y, n.z};
            const std::array<double, 3> w = triplanar_weights(na, 4.0, 0.05);
            double h = 0;
            for (int a = 0; a < 3; ++a) {
                if (w[a] == 0) continue;
                const TriplanarFrame f = triplanar_frame(triplanar_projection(na, a));
                h += w[a] * bilinear_height(m.map,
                                            ws * glm::dot(p, glm::dvec3(f.t[0], f.t[1], f.t[2])),
                                            ws * glm::dot(p, glm::dvec3(f.b[0], f.b[1], f.b[2])),
                                            AddressMode::Wrap);
            }
            const glm::dvec3 want = p + n * (1.0 / ws * 0.05 * (h - 0.7));
            const double e = glm::length(position_of(v) - want);
            worst = std::max(worst, e);
            ASSERT_LE(e, 2e-6) << "vertex at base point (" << p.x << ", " << p.y << ", " << p.z
                               << ")";
            // The base point on the base sphere: within the chord's sag of its radius.
            const double r = glm::length(p - glm::dvec3(0.13, 0.71, -2.07));
            ASSERT_LE(r, 0.6 + 1e-6);
            ASSERT_GE(r, 0.6 * std::cos(M_PI / 16) - 1e-6);
            EXPECT_EQ(v.uv_density, 1.0f / ws);
        }

        // Closed as its base: every edge, by its corners' positions bit for bit, is drawn once
        // each way (a crack or a T-junction leaves an edge once).
        using Key = std::array<float, 6>;
        std::map<Key, int> edges;
        for (size_t i = 0; i < out.indices.size(); i += 3)
            for (int e = 0; e < 3; ++e) {
                const Vertex& a = out.vertices[out.indices[i + e]];
                const Vertex& b = out.vertices[out.indices[i + (e + 1) % 3]];
                ASSERT_NE(a.position, b.position) << "a degenerate triangle";
                ++edges[{a.position[0], a.position[1], a.position[2], b.position[0], b.position[1],
                         b.position[2]}];
            }
        for (const auto& [k, count] : edges) {
            ASSERT_EQ(count, 1) << "an edge drawn twice the same way";
            const Key back = {k[3], k[4], k[5], k[0], k[1], k[2]};
            const auto it = edges.find(back);
            ASSERT_TRUE(it != edges.end())
                << "an open edge at (" << k[0] << ", " << k[1] << ", " << k[2] << ")";
        }

        // Each piece in one bilinear cell of every projection: its corners' lattice coordinates
        // (u D - 1/2) / texels_per_quad along x (u of +-Y, +-Z: width), y (v of +-X, +-Z:
        // height) and z (u of +-X: width; v of +-Y: height) within one whole interval, less the
        // float base points' rounding (|P| ws D 2^-24 / tpq, under 1e-4).
        const std::pair<int, int> families[4] = {
            {0, m.map.width}, {1, m.map.height}, {2, m.map.width}, {2, m.map.height}};
        for (size_t i = 0; i < out.indices.size(); i += 3)
            for (const auto& [axis, size] : families) {
                double lo = HUGE_VAL, hi = -HUGE_VAL;
                for (int c = 0; c < 3; ++c) {
                    const double l =
                        (out.vertices[out.indices[i + c]].tangent[axis] * ws * size - 0.5) / tpq;
                    lo = std::min(lo, l);
                    hi = std::max(hi, l);
                }
                ASSERT_LE(hi, std::floor(lo + 1e-4) + 1.0 + 1e-4)
                    << "triangle " << i / 3 << " crosses a plane of axis " << axis << " (" << lo
                    << " to " << hi << ")";
            }
        std::printf(
            "[ %g texels a quad ] %zu base triangles -> %zu, %zu vertices; worst |vertex - "
            "definition| %.2g m\n",
            tpq, t.meshes[0].base_triangles, t.meshes[0].triangles, out.vertices.size(), worst);
    }
}

// The truth of a scene at texels_per_quad 1, culled to a w x h view, with a triplanar pixel's uv
// in the projection `run` gave it first.
GeometryFrame truth_of(FrameRenderer& r, const FrameRun& run, const Scene& scene,
                       const std::vector<LoadedMaterial>& table, int w, int h) {
    TessellationOptions o;
    o.texels_per_quad = 1.0f;
    o.width = w;
    o.height = h;
    const Tessellation t = displace_scene(scene, table, o);
    return triplanar_truth_uv(r.render_geometry(t.scene, 1), run.first_projection, table);
}

// A floor facing +y in the +Y projection's frame (T = +x, B = -z), from the world's origin: as a
// uv-mapped quad (uv = world_scale (x, -z)) and as a triplanar one. The map is untwisted, so the
// two truths (cut along uv's lattice and along the world's) are one surface: at every pixel the
// same depth and, in the projection the triplanar frame traces (+Y everywhere), the same uv. And
// the triplanar frame's exact trace meets it.
TEST(Renderer, TriplanarTruthOfAnAxisAlignedFloorIsTheUvMappedFloors) {
    const float ws = 2.0f, side = 4.0f;
    LoadedMaterial tri = triplanar_material(untwisted_map(), ws, 4.0f, 0.05f);
    LoadedMaterial uv = tri;
    uv.spec.triplanar.enabled = false;
    const int w = 160, h = 120;
    GeometryFrame truths[2];
    FrameRun tri_run;
    EngineScene tri_base;
    for (int k = 0; k < 2; ++k) {
        Scene scene;
        scene.name = "floor";
        scene.meshes.push_back(make_quad("floor", 1, {0.0f, 0.0f, 0.0f}, {side, 0.0f, 0.0f},
                                         {0.0f, 0.0f, -side}, ws * side, ws * side));
        if (k == 0) project_from_world(scene.meshes[0], ws);
        scene.camera = looking_at({2.1f, 0.9f, 0.6f}, {1.9f, 0.0f, -2.4f});
        scene.light.kind = LightKind::None;
        const std::vector<LoadedMaterial> table = {k == 0 ? tri : uv};
        FrameRenderer r(runtime(), scene, table, {resolve_params(find_method("exact"), {})}, w, h,
                        ShadeSettings{});
        const FrameRun run = r.render(FrameMode::Deferred, false, 1);
        truths[k] = truth_of(r, run, scene, table, w, h);
        if (k == 0) {
            tri_run = run;
            tri_base = r.gbuffer();
        }
    }
    const std::vector<std::uint8_t> band =
        silhouette_band(tri_base.material, tri_base.depth, tri_run.offset.flags, w, h);
    size_t compared = 0;
    double worst_truths = 0, worst_depth = 0, worst_frame = 0;
    const double texels = 16;  // u's and v's texels a tile (16 x 12: hypot in each's own)
    for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k) {
        ASSERT_EQ(truths[0].depth[k] < 1.0f, truths[1].depth[k] < 1.0f) << k;
        if (truths[0].depth[k] >= 1.0f) continue;
        const double du = truths[0].uv[2 * k] - truths[1].uv[2 * k],
                     dv = truths[0].uv[2 * k + 1] - truths[1].uv[2 * k + 1];
        const double e = std::hypot(du * texels, dv * 12);
        worst_truths = std::max(worst_truths, e);
        ASSERT_LE(e, kFloatTexels) << "pixel (" << k % w << ", " << k / w << ")";
        worst_depth =
            std::max(worst_depth, double(std::fabs(truths[0].depth[k] - truths[1].depth[k])));
        if (band[k] || (tri_run.offset.flags[k] & OM_FLAG_GRAZING) || tri_base.depth[k] >= 1.0f)
            continue;
        ASSERT_EQ(tri_run.first_projection[k], 2) << k;
        const double fu = tri_run.offset.uv[k].s[0] - truths[0].uv[2 * k],
                     fv = tri_run.offset.uv[k].s[1] - truths[0].uv[2 * k + 1];
        const double ef = std::hypot(fu * texels, fv * 12);
        worst_frame = std::max(worst_frame, ef);
        ASSERT_LE(ef, kFloatTexels) << "pixel (" << k % w << ", " << k / w << ")";
        ++compared;
    }
    EXPECT_GT(compared, static_cast<size_t>(w) * h / 3);
    // Two rasters of one surface: their depths agree to the depth buffer's rounding.
    EXPECT_LE(worst_depth, 1e-6);
    std::printf(
        "[ floor ] %zu pixels: truths apart at most %.3g texels (depth %.2g), the exact frame "
        "%.3g texels from the truth\n",
        compared, worst_truths, worst_depth, worst_frame);
}

// A plane tilted off the y axis (normal (0.24, 0.93, 0.28), normalised) keeps one projection (+Y:
// the others' weights fall under the cutoff) but is not the projection's plane: the relief lies
// over the tilted plane, lifted along its normal, each point's uv its base point's in +Y's frame.
// The frame's exact method traces the ray over that surface (a step x along the ray moves uv by
// world_scale (x.T - (x.n)(n.T), x.B - (x.n)(n.B)) and the depth by world_scale x.n): on an
// untwisted map the truth is that relief exactly, so every interior pixel meets it within float
// rounding; a ray traced over the axis plane instead misses it by texels.
TEST(Renderer, TriplanarFrameOverATiltedPlaneMeetsItsTruth) {
    const float ws = 2.0f, side = 4.0f;
    const glm::dvec3 n = glm::normalize(glm::dvec3(0.24, 0.93, 0.28));
    const LoadedMaterial m = triplanar_material(untwisted_map(), ws, 4.0f, 0.05f);
    const std::array<double, 3> na = {n.x, n.y, n.z};
    const std::array<double, 3> wt = triplanar_weights(na, 4.0, 0.05);
    ASSERT_EQ(wt[0], 0.0);
    ASSERT_EQ(wt[2], 0.0);
    const std::vector<LoadedMaterial> table = {m};
    // Edges orthogonal to n: (1, -nx/ny, 0) and (0, nz/ny, -1), whose cross product is n / ny.
    const float a = float(n.x / n.y), c = float(n.z / n.y);
    Scene scene;
    scene.name = "tilted";
    scene.meshes.push_back(make_quad("tilted", 1, {0.0f, 0.0f, 0.0f}, {side, -side * a, 0.0f},
                                     {0.0f, side * c, -side}, 1.0f, 1.0f));
    project_from_world(scene.meshes[0], ws);
    scene.camera = looking_at({2.3f, 0.6f, 0.7f}, {1.7f, -0.3f, -2.2f});
    scene.light.kind = LightKind::None;
    const int w = 160, h = 120;
    FrameRenderer r(runtime(), scene, table, {resolve_params(find_method("exact"), {})}, w, h,
                    ShadeSettings{});
    const FrameRun run = r.render(FrameMode::Deferred, false, 1);
    const EngineScene base = r.gbuffer();
    const GeometryFrame truth = truth_of(r, run, scene, table, w, h);
    const std::vector<std::uint8_t> band =
        silhouette_band(base.material, base.depth, run.offset.flags, w, h);
    const glm::dvec3 eye(scene.camera.eye[0], scene.camera.eye[1], scene.camera.eye[2]);
    size_t compared = 0, grazing = 0;
    double worst = 0, worst_depth = 0;
    for (size_t k = 0; k < static_cast<size_t>(w) * h; ++k) {
        if (band[k] || base.depth[k] >= 1.0f || truth.depth[k] >= 1.0f) continue;
        if (run.offset.flags[k] & OM_FLAG_GRAZING) {
            ++grazing;
            continue;
        }
        ASSERT_EQ(run.first_projection[k], 2) << k;
        ASSERT_EQ(run.projection_count[k], 1.0f) << k;
        const double du = (run.offset.uv[k].s[0] - truth.uv[2 * k]) * 16,
                     dv = (run.offset.uv[k].s[1] - truth.uv[2 * k + 1]) * 12;
        const double e = std::hypot(du, dv);
        worst = std::max(worst, e);
        ASSERT_LE(e, kFloatTexels) << "pixel (" << k % w << ", " << k / w << "): truth ("
                                   << truth.uv[2 * k] << ", " << truth.uv[2 * k + 1] << "), exact ("
                                   << run.offset.uv[k].s[0] << ", " << run.offset.uv[k].s[1] << ")";
        // The depth offset puts the pixel's point at the truth's on the eye ray x (t along the
        // unit ray over the surface, times its scale, is t along x). Two points of the ray a
        // distance q apart have uv q world_scale (x_s.T, x_s.B) apart (x_s = x - (x.n) n), so
        // the uv error e allows e / |that per unit q| in texels; and three window depths are
        // floats (the base the frame starts from, its result and the truth's): a step of 2^-24
        // in d is 2^-23 z^2 / (2 near) along the view axis, up to 1.5 times that along a ray of
        // the frame.
        const int x = static_cast<int>(k % w), y = static_cast<int>(k / w);
        const glm::dvec3 pf = unproject(base, x, y, run.depth_after[k]),
                         pt = unproject(base, x, y, truth.depth[k]);
        const glm::dvec3 ray = glm::normalize(eye - pt), xs = ray - glm::dot(ray, n) * n;
        const double per_unit = ws * std::hypot(16 * xs.x, 12 * -xs.z);  // +Y: T = +x, B = -z
        const double z = glm::length(pt - eye);
        const double step = std::ldexp(1.0, -23) * z * z / (2.0 * scene.camera.near_plane);
        const double allowed = e / per_unit + 3.0 * 1.5 * step;
        const double ed = glm::length(pf - pt);
        worst_depth = std::max(worst_depth, ed / allowed);
        ASSERT_LE(ed, allowed) << "pixel (" << x << ", " << y << ")";
        ++compared;
    }
    EXPECT_GT(compared, static_cast<size_t>(w) * h / 3);
    std::printf(
        "[ tilted ] %zu pixels compared (%zu grazing skipped): worst |truth - exact| %.3g "
        "texels, depth at most %.3g of its bound\n",
        compared, grazing, worst, worst_depth);
}
#endif

}  // namespace
}  // namespace omtest
