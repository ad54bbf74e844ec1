#include "offsetmap/renderer/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

#include "offsetmap/mesh_curvature.hpp"
#include "offsetmap/mesh_uv_metric.hpp"

namespace offsetmap::renderer {

namespace {

glm::vec3 g(const Vec3& v) { return {v[0], v[1], v[2]}; }
Vec3 a(const glm::vec3& v) { return {v.x, v.y, v.z}; }

void add_quad(Mesh& m, std::uint32_t a0, std::uint32_t a1, std::uint32_t a2, std::uint32_t a3) {
    m.indices.insert(m.indices.end(), {a0, a1, a2, a0, a2, a3});
}

const float kTwoPi = 6.28318530718f;

// A surface of revolution about the y axis: rows + 1 rings of segments + 1 vertices (the seam:
// a ring's first and last vertex coincide, at u = 0 and tiles_u; u runs counter-clockwise seen
// from above), joined by quads. place(j, phi, v) sets ring j's vertex at angle phi: its position,
// normal and v.
template <typename Place>
void add_revolution(Mesh& m, int rows, int segments, float tiles_u, Place place) {
    const std::uint32_t base = static_cast<std::uint32_t>(m.vertices.size());
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= segments; ++i) {
            Vertex v;
            place(j, kTwoPi * float(i) / float(segments), v);
            v.uv[0] = tiles_u * float(i) / float(segments);
            m.vertices.push_back(v);
        }
    const std::uint32_t row = static_cast<std::uint32_t>(segments + 1);
    for (std::uint32_t j = 0; j < std::uint32_t(rows); ++j)
        for (std::uint32_t i = 0; i < std::uint32_t(segments); ++i) {
            const std::uint32_t k = base + j * row + i;
            add_quad(m, k, k + 1, k + row + 1, k + row);
        }
}

}  // namespace

void derive_curvature(Mesh& mesh) {
    // Core's, reading the interleaved vertices in place.
    const float* base = mesh.vertices.empty() ? nullptr : mesh.vertices[0].position.data();
    CurvatureMesh view;
    view.positions = base;
    view.normals = mesh.vertices.empty() ? nullptr : mesh.vertices[0].normal.data();
    view.tangents = mesh.vertices.empty() ? nullptr : mesh.vertices[0].tangent.data();
    view.position_stride = view.normal_stride = view.tangent_stride = sizeof(Vertex);
    view.vertex_count = mesh.vertices.size();
    view.indices = mesh.indices.data();
    view.index_count = mesh.indices.size();
    const std::vector<std::array<float, 3> > k = offsetmap::derive_curvature(view);
    for (size_t v = 0; v < k.size(); ++v) mesh.vertices[v].curvature = k[v];
}

void derive_tangents(Mesh& mesh) {
    const size_t n = mesh.vertices.size();
    std::vector<glm::dvec3> su(n, glm::dvec3(0.0)), sv(n, glm::dvec3(0.0));
    std::vector<double> world(n, 0.0), uv(n, 0.0);
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const std::uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const Vertex &v0 = mesh.vertices[i[0]], &v1 = mesh.vertices[i[1]],
                     &v2 = mesh.vertices[i[2]];
        const glm::dvec3 e1 = glm::dvec3(g(v1.position) - g(v0.position));
        const glm::dvec3 e2 = glm::dvec3(g(v2.position) - g(v0.position));
        const double du1 = v1.uv[0] - v0.uv[0], dv1 = v1.uv[1] - v0.uv[1];
        const double du2 = v2.uv[0] - v0.uv[0], dv2 = v2.uv[1] - v0.uv[1];
        const double det = du1 * dv2 - du2 * dv1;  // twice the signed uv area
        const double area = 0.5 * glm::length(glm::cross(e1, e2));
        if (std::abs(det) < 1e-20 || area < 1e-20) continue;
        // dP/du and dP/dv: the linear map from uv to the triangle's plane.
        const glm::dvec3 dpdu = (e1 * dv2 - e2 * dv1) / det;
        const glm::dvec3 dpdv = (e2 * du1 - e1 * du2) / det;
        for (std::uint32_t k : i) {
            su[k] += area * dpdu;
            sv[k] += area * dpdv;
            world[k] += area;
            uv[k] += 0.5 * std::abs(det);
        }
    }
    for (size_t k = 0; k < n; ++k) {
        Vertex& v = mesh.vertices[k];
        const glm::dvec3 nn = glm::normalize(glm::dvec3(g(v.normal)));
        glm::dvec3 t = su[k] - nn * glm::dot(nn, su[k]);
        const double lt = glm::length(t);
        if (!std::isfinite(lt) || lt < 1e-12 * (1.0 + glm::length(su[k]))) {
            // No usable dP/du (or one past double's range, from extreme uv or positions): any
            // unit vector orthogonal to N.
            const glm::dvec3 other =
                std::abs(nn.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
            t = other - nn * glm::dot(nn, other);
        }
        t = glm::normalize(t);
        const double w = glm::dot(glm::cross(nn, t), sv[k]) < 0.0 ? -1.0 : 1.0;
        v.normal = a(glm::vec3(nn));
        v.tangent = {float(t.x), float(t.y), float(t.z), float(w)};
        const float density = uv[k] > 0.0 ? float(std::sqrt(world[k] / uv[k])) : 1.0f;
        v.uv_density = std::isfinite(density) && density > 0.0f ? density : 1.0f;
        // The stretch from the tangent plane's parts of dP/du and dP/dv. Float positions and uv
        // give an isotropic mesh a few 1e-6 of log stretch; below 2^-12 (a stretch within 1.7e-4
        // of 1, under 0.002 texel on a 10-texel offset) it is none, and the plane's trace runs.
        const double lu = glm::length(su[k] - nn * glm::dot(nn, su[k]));
        const double lv = glm::length(sv[k] - nn * glm::dot(nn, sv[k]));
        const double stretch = 0.5 * std::log2(lu / lv);
        v.uv_log_stretch = std::isfinite(stretch) && std::fabs(stretch) > 0x1p-12
                               ? float(std::clamp(stretch, -8.0, 8.0))
                               : 0.0f;
    }
    derive_curvature(mesh);
    derive_uv_metric(mesh);
}

void derive_uv_metric(Mesh& mesh) {
    UvMetricMesh view;
    view.positions = mesh.vertices.empty() ? nullptr : mesh.vertices[0].position.data();
    view.uvs = mesh.vertices.empty() ? nullptr : mesh.vertices[0].uv.data();
    view.position_stride = view.uv_stride = sizeof(Vertex);
    view.vertex_count = mesh.vertices.size();
    view.indices = mesh.indices.data();
    view.index_count = mesh.indices.size();
    const std::vector<UvMetricVertex> m = offsetmap::derive_uv_metric(view);
    for (size_t v = 0; v < m.size(); ++v) {
        Vertex& x = mesh.vertices[v];
        x.dpdu = m[v].dpdu;
        x.dpdv = m[v].dpdv;
        x.gamma_u = m[v].gamma_u;
        x.gamma_v = m[v].gamma_v;
    }
}

void project_from_world(Mesh& mesh, float world_scale) {
    for (Vertex& v : mesh.vertices) {
        v.uv_density = 1.0f / world_scale;
        v.curvature = {0.0f, 0.0f, 0.0f};
        v.uv_log_stretch = 0.0f;
        v.dpdu = v.dpdv = v.gamma_u = v.gamma_v = {0.0f, 0.0f, 0.0f};
    }
}

Mesh make_quad(const std::string& name, int material, Vec3 origin, Vec3 edge_u, Vec3 edge_v,
               float tiles_u, float tiles_v, bool mirror_u) {
    Mesh m{name, material, {}, {}};
    const glm::vec3 o = g(origin), eu = g(edge_u), ev = g(edge_v);
    const Vec3 normal = a(glm::normalize(glm::cross(eu, ev)));
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
            Vertex v;
            v.position = a(o + float(i) * eu + float(j) * ev);
            v.normal = normal;
            v.uv = {(mirror_u ? 1.0f - float(i) : float(i)) * tiles_u, float(j) * tiles_v};
            m.vertices.push_back(v);
        }
    add_quad(m, 0, 1, 3, 2);
    derive_tangents(m);
    return m;
}

Mesh make_box(const std::string& name, int material, Vec3 center, Vec3 half, float tiles) {
    Mesh box{name, material, {}, {}};
    const glm::vec3 c = g(center), h = g(half);
    // Per face: the outward axis and two edges whose cross product points outward.
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2) {
            glm::vec3 n(0.0f), eu(0.0f), ev(0.0f);
            n[axis] = float(side);
            const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            eu[a1] = 2.0f * h[a1];
            ev[a2] = 2.0f * h[a2];
            if (side < 0) std::swap(eu, ev);  // keep cross(eu, ev) along n
            glm::vec3 origin = c + n * h[axis] - 0.5f * (eu + ev);
            const bool mirror = axis == 0 && side < 0;
            Mesh face = make_quad(name, material, a(origin), a(eu), a(ev), tiles, tiles, mirror);
            const std::uint32_t base = static_cast<std::uint32_t>(box.vertices.size());
            box.vertices.insert(box.vertices.end(), face.vertices.begin(), face.vertices.end());
            for (std::uint32_t i : face.indices) box.indices.push_back(base + i);
        }
    return box;
}

Mesh make_cylinder(const std::string& name, int material, Vec3 base, float radius, float height,
                   int segments, float tiles_u, float tiles_v) {
    Mesh m{name, material, {}, {}};
    const glm::vec3 b = g(base);
    add_revolution(m, 1, segments, tiles_u, [&](int j, float phi, Vertex& v) {
        const glm::vec3 r(std::cos(phi), 0.0f, -std::sin(phi));
        v.position = a(b + radius * r + glm::vec3(0.0f, height * float(j), 0.0f));
        v.normal = a(r);
        v.uv[1] = tiles_v * float(j);
    });
    // Caps: planar uv, one tile per diameter.
    for (int cap = 0; cap <= 1; ++cap) {
        const float y = height * float(cap);
        const glm::vec3 n(0.0f, cap ? 1.0f : -1.0f, 0.0f);
        const std::uint32_t centre = static_cast<std::uint32_t>(m.vertices.size());
        Vertex c;
        c.position = a(b + glm::vec3(0.0f, y, 0.0f));
        c.normal = a(n);
        c.uv = {0.5f, 0.5f};
        m.vertices.push_back(c);
        for (int i = 0; i <= segments; ++i) {
            const float phi = kTwoPi * float(i) / float(segments);
            Vertex v;
            v.position = a(b + glm::vec3(radius * std::cos(phi), y, -radius * std::sin(phi)));
            v.normal = a(n);
            v.uv = {0.5f + 0.5f * std::cos(phi), 0.5f + (cap ? 0.5f : -0.5f) * std::sin(phi)};
            m.vertices.push_back(v);
        }
        for (std::uint32_t i = 0; i < std::uint32_t(segments); ++i) {
            const std::uint32_t p = centre + 1 + i, q = p + 1;
            if (cap)
                m.indices.insert(m.indices.end(), {centre, p, q});
            else
                m.indices.insert(m.indices.end(), {centre, q, p});
        }
    }
    derive_tangents(m);
    return m;
}

Mesh make_sphere(const std::string& name, int material, Vec3 center, float radius, int segments,
                 int rings, float tiles_u, float tiles_v) {
    Mesh m{name, material, {}, {}};
    const glm::vec3 c = g(center);
    add_revolution(m, rings, segments, tiles_u, [&](int j, float phi, Vertex& v) {
        const float theta = 0.5f * kTwoPi * float(j) / float(rings);  // from the south pole up
        const glm::vec3 r(std::sin(theta) * std::cos(phi), -std::cos(theta),
                          -std::sin(theta) * std::sin(phi));
        v.position = a(c + radius * r);
        v.normal = a(r);
        // v from the north pole down, as images run: a picture reads upright (w = -1).
        v.uv[1] = tiles_v * (1.0f - float(j) / float(rings));
    });
    derive_tangents(m);
    return m;
}

Mesh make_torus(const std::string& name, int material, Vec3 center, float radius, float tube,
                int segments, int rings, float tiles_u, float tiles_v) {
    Mesh m{name, material, {}, {}};
    const glm::vec3 c = g(center);
    add_revolution(m, rings, segments, tiles_u, [&](int j, float phi, Vertex& v) {
        const float theta = kTwoPi * float(j) / float(rings);  // around the tube, outside first
        const glm::vec3 out(std::cos(phi), 0.0f, -std::sin(phi));
        const glm::vec3 n = std::cos(theta) * out + glm::vec3(0.0f, std::sin(theta), 0.0f);
        v.position = a(c + radius * out + tube * n);
        v.normal = a(n);
        v.uv[1] = tiles_v * float(j) / float(rings);
    });
    derive_tangents(m);
    return m;
}

}  // namespace offsetmap::renderer
