// The renderer: tangent frames derived from uv, the OpenGL G-buffer against the scene's geometry,
// the depth offset written back, and the forward peer (the methods in GLSL) against the deferred
// pass at equal parameters. The GL tests run wherever the renderer was built (Mesa's llvmpipe
// through EGL on a machine without a GPU); they skip only in a build without EGL and OpenGL.
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "support.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/renderer/glsl_peer.hpp"
#include "offsetmap/renderer/gltf.hpp"
#endif

namespace omtest {
namespace {

#ifndef OFFSETMAP_HAVE_RENDERER
TEST(Renderer, Built) { GTEST_SKIP() << "built without EGL and OpenGL: no renderer to test"; }
#else
using namespace offsetmap::renderer;

glm::dvec3 g(const Vec3& v) { return {v[0], v[1], v[2]}; }

// Every vertex: a unit tangent orthogonal to the normal, along dP/du, with the handedness that
// puts w N x T along dP/dv; `dpdu` and `dpdv` give the surface's own derivatives at a vertex.
// `cos_min` bounds the angle to the analytic dP/du: the per-triangle gradients are chords, at
// most one segment's angle from the tangent.
void check_frames(const Mesh& m, double cos_min,
                  const std::function<std::pair<glm::dvec3, glm::dvec3>(const Vertex&)>& d) {
    for (const Vertex& v : m.vertices) {
        const glm::dvec3 n = g(v.normal), t(v.tangent[0], v.tangent[1], v.tangent[2]);
        ASSERT_NEAR(glm::length(t), 1.0, 1e-6) << m.name;
        ASSERT_NEAR(glm::dot(n, t), 0.0, 1e-6) << m.name;
        const auto [dpdu, dpdv] = d(v);
        if (glm::length(dpdu) < 1e-9) continue;  // a pole: any tangent
        EXPECT_GE(glm::dot(t, glm::normalize(dpdu)), cos_min) << m.name;
        const glm::dvec3 b = double(v.tangent[3]) * glm::cross(n, t);
        EXPECT_GT(glm::dot(b, dpdv), 0.0) << m.name;
    }
}

TEST(Tangents, QuadIsExact) {
    const Mesh q = make_quad("q", 1, {1, 2, 3}, {2, 0, 0}, {0, 0, -4}, 4.0f, 8.0f);
    for (const Vertex& v : q.vertices) {
        EXPECT_FLOAT_EQ(v.tangent[0], 1.0f);
        EXPECT_FLOAT_EQ(v.tangent[3], 1.0f);
        EXPECT_FLOAT_EQ(v.uv_density, 0.5f);  // 2 world units over 4 tiles, 4 over 8
    }
    const Mesh mirrored = make_quad("m", 1, {0, 0, 0}, {2, 0, 0}, {0, 2, 0}, 1.0f, 1.0f, true);
    for (const Vertex& v : mirrored.vertices) {
        EXPECT_FLOAT_EQ(v.tangent[0], -1.0f);  // u runs along -x
        EXPECT_FLOAT_EQ(v.tangent[3], -1.0f);  // N x T = -y, against dP/dv = +y
        EXPECT_FLOAT_EQ(v.uv_density, 2.0f);
    }
}

TEST(Tangents, BoxCylinderSphereFollowTheirUv) {
    const Mesh box = make_box("box", 1, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 1.0f);
    int mirrored = 0;
    for (const Vertex& v : box.vertices) {
        mirrored += v.tangent[3] < 0;
        EXPECT_FLOAT_EQ(v.uv_density, 1.0f);
    }
    EXPECT_EQ(mirrored, 4);  // the -x face's four vertices
    // Each face's frame from its own uv square (the frames check below, with exact chords).
    check_frames(box, 1.0 - 1e-6, [&](const Vertex& v) {
        // The face's corners: dP/du and dP/dv from the uv layout of make_quad.
        const glm::dvec3 n = g(v.normal);
        const int axis = std::abs(n.x) > 0.5 ? 0 : std::abs(n.y) > 0.5 ? 1 : 2;
        const double side = n[axis];
        glm::dvec3 eu(0.0), ev(0.0);
        eu[(axis + 1) % 3] = 1.0;
        ev[(axis + 2) % 3] = 1.0;
        if (side < 0) std::swap(eu, ev);
        if (axis == 0 && side < 0) eu = -eu;
        return std::pair{eu, ev};
    });
    const int segments = 48;
    const double chord = std::cos(2.0 * 3.14159265358979 / segments);
    const Mesh cyl = make_cylinder("cylinder", 1, {0, 0, 0}, 0.5f, 1.0f, segments, 3.0f, 1.0f);
    check_frames(cyl, chord, [&](const Vertex& v) {
        const glm::dvec3 p = g(v.position);
        if (std::abs(v.normal[1]) > 0.5)  // a cap: u along +x, v along -z on top, +z below
            return std::pair{glm::dvec3(1, 0, 0), glm::dvec3(0, 0, v.normal[1] > 0 ? -1 : 1)};
        return std::pair{glm::dvec3(p.z, 0, -p.x), glm::dvec3(0, 1, 0)};  // d/dphi, up
    });
    const Mesh sphere = make_sphere("sphere", 1, {0, 0, 0}, 1.0f, segments, 24, 4.0f, 2.0f);
    check_frames(sphere, chord, [&](const Vertex& v) {
        const glm::dvec3 p = g(v.position);
        const glm::dvec3 around(p.z, 0, -p.x);                    // u: increasing phi
        const glm::dvec3 south = glm::dvec3(0, -1, 0) + p * p.y;  // v: toward the south pole
        const bool pole = std::abs(p.y) > 1.0 - 1e-6;  // no direction of increasing phi there
        return std::pair{pole ? glm::dvec3(0.0) : around, south};
    });
    // v runs from the north pole down: mirrored frames (a pole vertex whose only triangle has
    // no area takes any frame; it never draws).
    for (const Vertex& v : sphere.vertices)
        if (std::abs(v.position[1]) < 1.0f - 1e-6f) {
            EXPECT_EQ(v.tangent[3], -1.0f);
        }
}

TEST(Tangents, RandomTrianglesKeepTheirOrientation) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> r(-1.0f, 1.0f);
    for (int k = 0; k < 200; ++k) {
        Mesh m;
        for (int i = 0; i < 3; ++i) {
            Vertex v;
            v.position = {r(rng), r(rng), r(rng)};
            v.uv = {r(rng), r(rng)};
            m.vertices.push_back(v);
        }
        m.indices = {0, 1, 2};
        const glm::dvec3 p0 = g(m.vertices[0].position), e1 = g(m.vertices[1].position) - p0,
                         e2 = g(m.vertices[2].position) - p0;
        const glm::dvec3 n = glm::normalize(glm::cross(e1, e2));
        for (Vertex& v : m.vertices) v.normal = {float(n.x), float(n.y), float(n.z)};
        const double du1 = m.vertices[1].uv[0] - m.vertices[0].uv[0],
                     dv1 = m.vertices[1].uv[1] - m.vertices[0].uv[1],
                     du2 = m.vertices[2].uv[0] - m.vertices[0].uv[0],
                     dv2 = m.vertices[2].uv[1] - m.vertices[0].uv[1];
        const double det = du1 * dv2 - du2 * dv1;
        if (std::abs(det) < 1e-3) continue;
        derive_tangents(m);
        const glm::dvec3 dpdu = (e1 * dv2 - e2 * dv1) / det, dpdv = (e2 * du1 - e1 * du2) / det;
        check_frames(m, 0.0, [&](const Vertex&) { return std::pair{dpdu, dpdv}; });
        // The density: sqrt(world area / uv area).
        const double world = 0.5 * glm::length(glm::cross(e1, e2)), uv = 0.5 * std::abs(det);
        EXPECT_NEAR(m.vertices[0].uv_density, std::sqrt(world / uv), 1e-4 * std::sqrt(world / uv));
    }
}

std::vector<LoadedMaterial> room_table() {
    return load_materials(
        read_material_table(std::string(OFFSETMAP_SOURCE_DIR) + "/data/room.json"));
}

std::vector<MethodParams> methods_for(const std::vector<LoadedMaterial>& table,
                                      const std::string& method) {
    std::vector<MethodParams> m;
    for (const LoadedMaterial& t : table)
        m.push_back(method.empty() ? resolve_params(find_method(t.spec.method), t.spec.params)
                                   : resolve_params(find_method(method), {}));
    return m;
}

TEST(Renderer, GBufferMatchesTheScene) {
    const Scene scene = builtin_room(std::string(OFFSETMAP_SOURCE_DIR) + "/data");
    const auto table = room_table();
    FrameRenderer r(runtime(), scene, table, methods_for(table, ""), 160, 90, ShadeSettings{});
    r.render(FrameMode::Deferred, false, 1);
    const EngineScene& e = r.gbuffer();
    std::set<float> ids;
    size_t floor = 0;
    double worst = 0.0;
    for (int y = 0; y < e.height; ++y)
        for (int x = 0; x < e.width; ++x) {
            const size_t k = static_cast<size_t>(y) * e.width + x;
            ids.insert(e.material[k]);
            if (e.depth[k] >= 1.0f) {
                EXPECT_TRUE(std::isnan(e.uv[2 * k]));  // sky: an empty pixel
                continue;
            }
            if (e.material[k] != 2.0f) continue;
            // The floor: y = 0, normal +y, tangent +x, uv from x and z at 1.5 world units a
            // tile (scenes.cpp), derivatives of that map along the pixel's footprint.
            const glm::dvec3 p = unproject(e, x, y, e.depth[k]);
            // P from a float depth: at distance z a depth step moves P by about z^2 / near
            // times 6e-8 (the step of d near 1), under 2e-5 within the room's 8 m; uv is P
            // over 1.5, and the rasterizer interpolates it in float.
            EXPECT_NEAR(p.y, 0.0, 1e-4);
            EXPECT_NEAR(e.uv[2 * k], (p.x + 3.0) / 1.5, 1e-4);
            EXPECT_NEAR(e.uv[2 * k + 1], (2.5 - p.z) / 1.5, 1e-4);
            worst = std::max(worst, std::abs(e.uv[2 * k] - (p.x + 3.0) / 1.5));
            // Interpolating three equal vectors: exact up to the barycentric weights' rounding.
            EXPECT_NEAR(e.normal[4 * k + 1], 1.0f, 1e-6);
            EXPECT_NEAR(e.tangent[4 * k], 1.0f, 1e-6);
            EXPECT_EQ(e.tangent[4 * k + 3], 1.0f);
            const glm::dvec3 right = unproject(e, x + 1, y, e.depth[k]) - p;
            EXPECT_NEAR(e.uv_derivatives[4 * k], right.x / 1.5,
                        0.05 * std::abs(right.x / 1.5) + 1e-4);
            ++floor;
        }
    EXPECT_GT(floor, 1000u);
    EXPECT_EQ(ids, (std::set<float>{0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f}));
    std::printf("floor: %zu pixels, worst |u - u(P)| %.2e\n", floor, worst);
    // The explicit G-buffer the passes read: unit tangent-space V facing the eye.
    const GBuffer& gb = r.explicit_gbuffer();
    for (size_t k = 0; k < gb.pixels(); ++k)
        if (e.depth[k] < 1.0f && e.material[k] == 2.0f) {
            const auto& v = gb.view[k].s;
            EXPECT_NEAR(v[0] * v[0] + v[1] * v[1] + v[2] * v[2], 1.0, 1e-5);
            EXPECT_GT(v[2], 0.0f);
        }
}

// The depth written back: each pixel's surface point moved along its eye ray by t times the uv
// density, projected again; computed here in double from the depth before, for the walls (1 world
// unit a tile) and the floor (1.5).
TEST(Renderer, DepthOffsetIsTheHitsDepth) {
    const Scene scene = builtin_room(std::string(OFFSETMAP_SOURCE_DIR) + "/data");
    const auto table = room_table();
    FrameRenderer r(runtime(), scene, table, methods_for(table, ""), 160, 90, ShadeSettings{});
    const FrameRun run = r.render(FrameMode::Deferred, false, 1);
    const EngineScene& e = r.gbuffer();
    const Camera& cam = scene.camera;
    const glm::dvec3 eye = g(cam.eye);
    const glm::dmat4 vp =
        glm::perspective(glm::radians(double(cam.fov_y_deg)), double(e.width) / e.height,
                         double(cam.near_plane), double(cam.far_plane)) *
        glm::lookAt(eye, g(cam.target), glm::dvec3(0, 1, 0));
    size_t checked = 0, deeper = 0;
    double worst = 0.0;
    for (int y = 0; y < e.height; ++y)
        for (int x = 0; x < e.width; ++x) {
            const size_t k = static_cast<size_t>(y) * e.width + x;
            const float id = e.material[k];
            if (e.depth[k] >= 1.0f) {
                EXPECT_EQ(run.depth_after[k], e.depth[k]);  // sky keeps its depth
                continue;
            }
            if (id != 1.0f && id != 2.0f) continue;
            const double density = id == 1.0f ? 1.0 : 1.5, t = run.offset.depth[k];
            const glm::dvec3 p = unproject(e, x, y, e.depth[k]);
            const glm::dvec3 q = p - t * density * glm::normalize(eye - p);
            const glm::dvec4 c = vp * glm::dvec4(q, 1.0);
            const double expected = 0.5 * c.z / c.w + 0.5;
            // The shader's float arithmetic on the same steps: relative 1e-6 of P, a depth step
            // of about 1e-6 at these distances.
            EXPECT_NEAR(run.depth_after[k], expected, 2e-6) << x << "," << y;
            worst = std::max(worst, std::abs(run.depth_after[k] - expected));
            deeper += t > 0.0 && run.depth_after[k] > e.depth[k];
            ++checked;
        }
    EXPECT_GT(checked, 5000u);
    EXPECT_GT(deeper, checked / 2);  // r = 1: the hit lies below the polygon
    std::printf("%zu pixels, worst depth difference %.2e\n", checked, worst);
}

// The forward peer against the deferred pass, method by method at equal parameters: each uv'
// from the same rasterized G-buffer, V from the interpolated position (forward) or from the depth
// (deferred). Both trace the same steps; the two V differ by float rounding, which moves uv' by
// t |dV|, far below a texel, except where it flips a step's outcome (the sample nearest the
// relief): those pixels are few, so the error against exact agrees.
TEST(Renderer, ForwardPeerHasTheDeferredError) {
    const Scene scene = builtin_room(std::string(OFFSETMAP_SOURCE_DIR) + "/data");
    const auto table = room_table();
    for (const std::string method : {"parallax", "pom", "steep", "relief"}) {
        FrameRenderer r(runtime(), scene, table, methods_for(table, method), 192, 108,
                        ShadeSettings{});
        const FrameRun deferred = r.render(FrameMode::Deferred, false, 1);
        const FrameRun forward = r.render(FrameMode::Forward, false, 1);
        const OffsetResult exact = r.exact();
        const GBuffer& gb = r.explicit_gbuffer();
        const auto ed = material_errors(gb, deferred.offset, exact, table);
        const auto ef = material_errors(gb, forward.offset, exact, table);
        size_t covered = 0, apart = 0;
        for (size_t k = 0; k < gb.pixels(); ++k) {
            if (std::isnan(gb.uv[k].s[0])) continue;
            ++covered;
            const int s = static_cast<int>(gb.material[k]) - 1;
            const double texels = std::max(table[s].map.width, table[s].map.height);
            const double du = forward.offset.uv[k].s[0] - deferred.offset.uv[k].s[0],
                         dv = forward.offset.uv[k].s[1] - deferred.offset.uv[k].s[1];
            apart += std::hypot(du, dv) * texels > 0.01;
        }
        std::printf("%-8s %zu of %zu pixels apart by more than 0.01 texel\n", method.c_str(), apart,
                    covered);
        EXPECT_LT(apart, covered / 100) << method;
        for (size_t s = 0; s < table.size(); ++s) {
            std::printf("  %-7s mean %.4f / %.4f  p95 %.4f / %.4f\n", table[s].spec.name.c_str(),
                        ed[s].error.mean, ef[s].error.mean, ed[s].error.p95, ef[s].error.p95);
            EXPECT_NEAR(ef[s].error.mean, ed[s].error.mean, 0.05 * ed[s].error.mean + 1e-3)
                << method << " " << table[s].spec.name;
            EXPECT_NEAR(ef[s].error.p95, ed[s].error.p95, 0.05 * ed[s].error.p95 + 1e-3)
                << method << " " << table[s].spec.name;
        }
    }
}

// The terrain (no uv, triplanar): the forward peer traces each projection in the fragment shader
// and the frame shades them in the projections the reconstruct pass chose, so its picture is the
// deferred frame's but for rounding. Unlike a uv-mapped frame's, the projections' uv come from the
// world point: the forward shader's interpolated one, the deferred frame's from the float depth
// buffer, whose step 2^-24 in d is 2^-23 in NDC z, so dz = 2^-23 z^2 / (2 near) along the view axis
// (far >> near), up to 1.5 times that along a ray of the frame, and world_scale times the map's
// texels in uv. At most 1 % of the triplanar pixels may have their dominant uv' apart by more
// than that bound at the scene's farthest point (twice, and 0.01 texel for the march's own
// rounding), a colour channel by more than 0.02, or the point after the depth offset by more than
// three such steps.
TEST(Renderer, TriplanarForwardPeerIsTheDeferredFrame) {
    const std::string data = std::string(OFFSETMAP_SOURCE_DIR) + "/data";
    const std::vector<MaterialSpec> specs = read_material_table(data + "/terrain.json");
    const Scene scene = load_gltf_scene(data + "/terrain.gltf", specs, data + "/terrain.json");
    const std::vector<LoadedMaterial> table = load_materials(specs);
    FrameRenderer r(runtime(), scene, table, methods_for(table, ""), 192, 108, ShadeSettings{});
    const FrameRun deferred = r.render(FrameMode::Deferred, false, 1);
    const FrameRun forward = r.render(FrameMode::Forward, false, 1);
    ASSERT_EQ(forward.projections, deferred.projections);
    const size_t projected =
        deferred.projections[0] + deferred.projections[1] + deferred.projections[2];
    ASSERT_GT(deferred.projections[1] + deferred.projections[2], projected / 20);
    double far = 0;
    const glm::dvec3 eye(scene.camera.eye[0], scene.camera.eye[1], scene.camera.eye[2]);
    for (const Mesh& m : scene.meshes)
        for (const Vertex& v : m.vertices)
            far = std::max(
                far, glm::length(glm::dvec3(v.position[0], v.position[1], v.position[2]) - eye));
    const double dz = std::ldexp(1.0, -23) * far * far / (2.0 * scene.camera.near_plane);
    size_t uv_apart = 0, colour_apart = 0, depth_apart = 0;
    const EngineScene& base = r.gbuffer();
    for (size_t k = 0; k < deferred.projection_count.size(); ++k) {
        if (deferred.projection_count[k] == 0) continue;
        // The depth offsets: each projection's t scaled to the world ray and blended, in both.
        const int x = static_cast<int>(k % base.width), y = static_cast<int>(k / base.width);
        depth_apart += glm::length(unproject(base, x, y, forward.depth_after[k]) -
                                   unproject(base, x, y, deferred.depth_after[k])) > 3.0 * 1.5 * dz;
        const int s = static_cast<int>(deferred.material[k]) - 1;
        const double texels = std::max(table[s].map.width, table[s].map.height);
        const double du = forward.offset.uv[k].s[0] - deferred.offset.uv[k].s[0],
                     dv = forward.offset.uv[k].s[1] - deferred.offset.uv[k].s[1];
        const double bound = 2.0 * 1.5 * dz * table[s].spec.triplanar.world_scale * texels;
        uv_apart += std::hypot(du, dv) * texels > bound + 0.01;
        double worst = 0;
        for (int c = 0; c < 3; ++c)
            worst =
                std::max(worst, double(std::abs(forward.color[k].s[c] - deferred.color[k].s[c])));
        colour_apart += worst > 0.02;
    }
    std::printf(
        "[ terrain ] %zu triplanar pixels, depth step at the farthest point %.2g: dominant uv' "
        "apart in %zu, colour in %zu, depth in %zu\n",
        projected, dz, uv_apart, colour_apart, depth_apart);
    EXPECT_LE(uv_apart, projected / 100);
    EXPECT_LE(depth_apart, projected / 100);
    EXPECT_LE(colour_apart, projected / 100);
}

// The tile mask on the box (one uv square a face): the deferred pass flags OUT_OF_TILE where a
// ray leaves its face; the forward shader drops those fragments, so without a pre-pass the pixel
// shows the surface behind (never the box: its far faces are culled), and after a depth pre-pass
// it is left empty, as a one-layer G-buffer must leave it. Every other pixel is unchanged. The two
// uv' differ by float rounding (V from the interpolated position or from the depth), which can put
// a uv' within rounding of the tile's edge on the other side of it: at most 2 % of the masked
// count may disagree (1 of 528 here).
TEST(Renderer, ForwardTileMaskShowsWhatIsBehind) {
    Scene scene = builtin_room(std::string(OFFSETMAP_SOURCE_DIR) + "/data");
    scene.camera = parse_camera("-0.2,1.3,0.6,-1.3,0.5,-1.9,50");  // close to the box
    auto table = room_table();
    for (LoadedMaterial& m : table) m.spec.settings.out_of_tile_mask = m.spec.id == 3;
    FrameRenderer r(runtime(), scene, table, methods_for(table, ""), 320, 180, ShadeSettings{});
    const FrameRun deferred = r.render(FrameMode::Deferred, false, 1);
    const EngineScene before = r.gbuffer();
    for (bool prepass : {false, true}) {
        r.render(FrameMode::Forward, prepass, 1);
        const EngineScene& after = r.gbuffer();
        size_t masked = 0, disagree = 0;
        for (size_t k = 0; k < deferred.offset.flags.size(); ++k) {
            const bool same = std::memcmp(&after.uv[2 * k], &before.uv[2 * k], 8) == 0;
            if (deferred.offset.flags[k] & OM_FLAG_OUT_OF_TILE) {
                ++masked;
                ASSERT_EQ(before.material[k], 3.0f);
                disagree += prepass ? !std::isnan(after.uv[2 * k])
                                    : (after.material[k] == 3.0f || std::isnan(after.uv[2 * k]));
            } else {
                disagree += !same;
            }
        }
        std::printf("%s: %zu pixels masked, %zu disagree\n", prepass ? "pre-pass" : "forward",
                    masked, disagree);
        EXPECT_GT(masked, 100u);
        EXPECT_LE(disagree, masked / 50);
    }
}

// Overdraw: forward pays its method on every fragment that passes the depth test when drawn;
// after a depth pre-pass, on exactly one per covered pixel.
TEST(Renderer, PrepassShadesEachPixelOnce) {
    const Scene scene = builtin_room(std::string(OFFSETMAP_SOURCE_DIR) + "/data");
    const auto table = room_table();
    FrameRenderer r(runtime(), scene, table, methods_for(table, ""), 160, 90, ShadeSettings{});
    const FrameRun plain = r.render(FrameMode::Forward, false, 1);
    const FrameRun pre = r.render(FrameMode::Forward, true, 1);
    EXPECT_EQ(static_cast<size_t>(pre.shaded_fragments), r.covered_pixels());
    EXPECT_GT(static_cast<size_t>(plain.shaded_fragments), r.covered_pixels());
    // The same picture either way.
    for (size_t k = 0; k < plain.offset.uv.size(); ++k) {
        if (std::isnan(plain.offset.uv[k].s[0])) continue;
        EXPECT_EQ(plain.offset.uv[k].s[0], pre.offset.uv[k].s[0]);
        EXPECT_EQ(plain.offset.uv[k].s[1], pre.offset.uv[k].s[1]);
    }
}

// The full-screen peers' relief: rocks at s 0.05.
struct PeerRelief {
    HeightMap map = load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png");
    PassSettings s = [] {
        PassSettings p;
        p.scale = 0.05f;
        return p;
    }();
    std::shared_ptr<Runtime> rt = runtime();
};

// The bench's full-screen GLSL peer traces as the kernels do on the same uv, V and map: for the
// camera plane and for random rays, uv' apart by more than 0.01 texel on under 0.5 % of pixels
// (a float rounding that flips one step's outcome at the sample nearest the relief; the two
// compilers contract and order the arithmetic differently), the same fetch count on over 99 %.
TEST(Renderer, FullScreenPeerTracesAsTheKernels) {
    const PeerRelief relief;
    const HeightMap& map = relief.map;
    const PassSettings& s = relief.s;
    auto rt = runtime();
    const DeviceHeightField f = upload(*rt, map, s);
    PlaneScene plane;
    plane.width = 160;
    plane.height = 90;
    for (const GBuffer& gb : {make_scene(plane), make_scene(RandomScene{128, 64, 3, 5.0, 90.0})}) {
        const DeviceGBuffer dg = upload(*rt, gb);
        GlslPeer peer(gb, map, s);
        const std::vector<std::pair<std::string, std::map<std::string, std::string> > > rows = {
            {"parallax", {}},
            {"pom", {}},
            {"pom", {{"spacing", "6"}}},
            {"steep", {}},
            {"relief", {}}};
        for (const auto& [method, set] : rows) {
            const MethodParams params = resolve_params(find_method(method), set);
            OffsetPass pass(rt, params);
            const OffsetResult kernel = run_offset(*rt, pass, dg, f, s, 1);
            peer.set_method(params);
            peer.run();
            const OffsetResult glsl = peer.result();
            size_t traced_px = 0, apart = 0, same_fetches = 0;
            for (size_t k = 0; k < gb.pixels(); ++k) {
                if (!traced(kernel.flags[k])) continue;
                ++traced_px;
                const double du = glsl.uv[k].s[0] - kernel.uv[k].s[0],
                             dv = glsl.uv[k].s[1] - kernel.uv[k].s[1];
                apart += !(std::hypot(du * map.width, dv * map.height) <= 0.01);
                same_fetches += glsl.fetches[k] == kernel.fetches[k];
            }
            std::string label = method;
            for (const auto& [name, value] : set) label += " " + name + "=" + value;
            std::printf("%-18s %zu of %zu pixels apart, %zu with the same fetches\n", label.c_str(),
                        apart, traced_px, same_fetches);
            ASSERT_GT(traced_px, gb.pixels() / 2);
            EXPECT_LE(apart, traced_px / 200) << label;
            EXPECT_GE(same_fetches, traced_px * 99 / 100) << label;
        }
    }
    GlslPeer peer(make_scene(plane), map, s);
    EXPECT_THROW(peer.set_method(resolve_params(find_method("cone"), {})), Error);
}

// Over a curved base (a sphere, a cylinder, a saddle, a stretched sphere; radius 0.25 to 0.33 uv
// at s 0.05) the GLSL methods trace the kernels' curved ray: uv' apart by more than 0.01 texel on
// under 0.5 % of the pixels both trace (the rounding above), the same SILHOUETTE verdict on over
// 99.5 % of all, and at least 2 % of the rays leave.
TEST(Renderer, FullScreenPeerTracesTheCurvedBaseAsTheKernels) {
    const PeerRelief p;
    const DeviceHeightField f = upload(*p.rt, p.map, p.s);
    GBuffer gb = make_scene(RandomScene{128, 64, 5, 5.0, 90.0});
    const cl_float4 bases[] = {{{4.0f, 0.0f, 4.0f, 1.0f}},
                               {{3.0f, 0.0f, 0.0f, 1.0f}},
                               {{3.0f, 1.0f, -2.0f, 1.0f}},
                               {{4.0f, 0.0f, 4.0f, 1.3f}}};
    for (size_t k = 0; k < gb.pixels(); ++k) gb.curvature.push_back(bases[k % 4]);
    const DeviceGBuffer dg = upload(*p.rt, gb);
    GlslPeer peer(gb, p.map, p.s);
    for (const char* method : {"parallax", "pom", "steep", "relief"}) {
        const MethodParams params = resolve_params(find_method(method), {});
        OffsetPass pass(p.rt, params);
        const OffsetResult kernel = run_offset(*p.rt, pass, dg, f, p.s, 1);
        peer.set_method(params);
        peer.run();
        const OffsetResult glsl = peer.result();
        size_t both = 0, apart = 0, verdicts = 0, left = 0;
        for (size_t k = 0; k < gb.pixels(); ++k) {
            const bool kernel_left = kernel.flags[k] & OM_FLAG_SILHOUETTE;
            left += kernel_left;
            verdicts += kernel_left == ((glsl.flags[k] & OM_FLAG_SILHOUETTE) != 0);
            if (!traced(kernel.flags[k]) || kernel_left || glsl.flags[k]) continue;
            ++both;
            const double du = glsl.uv[k].s[0] - kernel.uv[k].s[0],
                         dv = glsl.uv[k].s[1] - kernel.uv[k].s[1];
            apart += !(std::hypot(du * p.map.width, dv * p.map.height) <= 0.01);
        }
        std::printf("%-9s curved: %zu of %zu pixels apart, %zu left, %zu of %zu verdicts agree\n",
                    method, apart, both, left, verdicts, gb.pixels());
        ASSERT_GT(both, gb.pixels() / 2) << method;
        EXPECT_LE(apart, both / 200) << method;
        EXPECT_GE(verdicts, gb.pixels() * 995 / 1000) << method;
        EXPECT_GE(left, gb.pixels() / 50) << method;
    }
}
#endif

// The rendered room, 500 frames on one runtime and one GL context (50 renders of a warm-up and 9
// timed frames each; buffers reused): resident memory flat after the first 10 frames (within
// 1 %), no thread, file or mapping more, and the last frame's colour the first render's.
TEST(Renderer, Soak500FramesHoldMemoryFlat) {
    const Scene scene = builtin_room(std::string(OFFSETMAP_SOURCE_DIR) + "/data");
    const auto table = room_table();
    FrameRenderer r(runtime(), scene, table, methods_for(table, ""), 160, 90, ShadeSettings{});
    std::vector<cl_float4> first;
    Soak soak;
    soak.frames_per_sample = 10;
    for (int k = 0; k < 50; ++k) {
        const FrameRun run = r.render(FrameMode::Deferred, false, 9);
        if (k == 0) first = run.color;
        if (k == 49) {
            ASSERT_EQ(run.color.size(), first.size());
            EXPECT_EQ(std::memcmp(run.color.data(), first.data(), first.size() * sizeof(cl_float4)),
                      0)
                << "the 500th frame differs from the 10th";
        }
        soak.sample();
    }
    soak.check("rendered room 160x90, 500 frames", 1, "soak.room");
}

}  // namespace
}  // namespace omtest
