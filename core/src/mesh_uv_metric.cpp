// Double precision throughout; core links nothing but OpenCL.
#include "offsetmap/mesh_uv_metric.hpp"

#include <cmath>
#include <string>

#include "offsetmap/error.hpp"

namespace offsetmap {

namespace {

struct D3 {
    double x = 0, y = 0, z = 0;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) {
    return {a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y};
}
std::array<float, 3> f3(D3 a) { return {float(a.x), float(a.y), float(a.z)}; }

const float* row(const float* base, std::size_t stride, std::size_t k, std::size_t packed) {
    return reinterpret_cast<const float*>(reinterpret_cast<const char*>(base) +
                                          k * (stride ? stride : packed));
}

void check(const UvMetricMesh& m) {
    if (m.vertex_count && (!m.positions || !m.uvs))
        throw Error("derive_uv_metric: the mesh has " + std::to_string(m.vertex_count) +
                    " vertices but no positions or uvs");
    if (m.index_count % 3)
        throw Error("derive_uv_metric: " + std::to_string(m.index_count) +
                    " indices are not whole triangles");
    if (m.index_count && !m.indices) throw Error("derive_uv_metric: the indices are missing");
    for (std::size_t i = 0; i < m.index_count; ++i)
        if (m.indices[i] >= m.vertex_count)
            throw Error("derive_uv_metric: index " + std::to_string(i) + " is " +
                        std::to_string(m.indices[i]) + ", past the mesh's " +
                        std::to_string(m.vertex_count) + " vertices");
}

// A triangle's uv edges from its first corner and the linear map's determinant: the rates of any
// per-corner value x over the triangle, d x / du and d x / dv.
struct UvEdges {
    double du1, dv1, du2, dv2, det;
    D3 rate_u(D3 x0, D3 x1, D3 x2) const { return ((x1 - x0) * dv2 - (x2 - x0) * dv1) * (1 / det); }
    D3 rate_v(D3 x0, D3 x1, D3 x2) const { return ((x2 - x0) * du1 - (x1 - x0) * du2) * (1 / det); }
};

}  // namespace

std::vector<UvMetricVertex> derive_uv_metric(const UvMetricMesh& mesh) {
    check(mesh);
    const std::size_t n = mesh.vertex_count;
    auto position = [&](std::size_t k) {
        const float* p = row(mesh.positions, mesh.position_stride, k, 3 * sizeof(float));
        return D3{p[0], p[1], p[2]};
    };
    auto uv = [&](std::size_t k) { return row(mesh.uvs, mesh.uv_stride, k, 2 * sizeof(float)); };
    // Each usable triangle's corners, uv edges and area.
    struct Tri {
        std::uint32_t i[3];
        UvEdges e;
        double area;
    };
    std::vector<Tri> tris;
    for (std::size_t t = 0; t < mesh.index_count; t += 3) {
        Tri tri{{mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]}, {}, 0.0};
        const float *a = uv(tri.i[0]), *b = uv(tri.i[1]), *c = uv(tri.i[2]);
        UvEdges& e = tri.e;
        e.du1 = double(b[0]) - a[0], e.dv1 = double(b[1]) - a[1];
        e.du2 = double(c[0]) - a[0], e.dv2 = double(c[1]) - a[1];
        e.det = e.du1 * e.dv2 - e.du2 * e.dv1;
        const D3 p0 = position(tri.i[0]);
        const D3 cr = cross(position(tri.i[1]) - p0, position(tri.i[2]) - p0);
        tri.area = 0.5 * std::sqrt(dot(cr, cr));
        if (std::fabs(e.det) < 1e-20 || !(tri.area > 1e-20) || !std::isfinite(e.det)) continue;
        tris.push_back(tri);
    }
    // dP/du and dP/dv a vertex, as the renderer's derive_tangents weighs them.
    std::vector<D3> su(n), sv(n);
    std::vector<double> weight(n, 0.0);
    for (const Tri& t : tris) {
        const D3 p0 = position(t.i[0]), p1 = position(t.i[1]), p2 = position(t.i[2]);
        const D3 dpdu = t.e.rate_u(p0, p1, p2), dpdv = t.e.rate_v(p0, p1, p2);
        for (std::uint32_t k : t.i) {
            su[k] = su[k] + dpdu * t.area;
            sv[k] = sv[k] + dpdv * t.area;
            weight[k] += t.area;
        }
    }
    for (std::size_t k = 0; k < n; ++k)
        if (weight[k] > 0.0) su[k] = su[k] * (1 / weight[k]), sv[k] = sv[k] * (1 / weight[k]);
    // Each triangle's Christoffel symbols from the rates of the interpolated dP/du and dP/dv, at
    // its centroid's dP/du and dP/dv.
    std::vector<std::array<double, 6> > gamma(n, std::array<double, 6>{});
    std::vector<double> gw(n, 0.0);
    for (const Tri& t : tris) {
        const std::uint32_t a = t.i[0], b = t.i[1], c = t.i[2];
        const D3 suu = t.e.rate_u(su[a], su[b], su[c]), suv_a = t.e.rate_v(su[a], su[b], su[c]);
        const D3 suv_b = t.e.rate_u(sv[a], sv[b], sv[c]), svv = t.e.rate_v(sv[a], sv[b], sv[c]);
        const D3 suv = (suv_a + suv_b) * 0.5;
        const D3 tu = (su[a] + su[b] + su[c]) * (1.0 / 3), tv = (sv[a] + sv[b] + sv[c]) * (1.0 / 3);
        const double E = dot(tu, tu), F = dot(tu, tv), G = dot(tv, tv), det = E * G - F * F;
        if (!(det > 1e-30 * (E * G))) continue;
        const D3 second[3] = {suu, suv, svv};
        std::array<double, 6> g{};
        for (int ij = 0; ij < 3; ++ij) {
            const double xu = dot(second[ij], tu), xv = dot(second[ij], tv);
            g[ij] = (G * xu - F * xv) / det;      // Gamma^u_ij
            g[3 + ij] = (E * xv - F * xu) / det;  // Gamma^v_ij
        }
        bool finite = true;
        for (double x : g) finite = finite && std::isfinite(x);
        if (!finite) continue;
        for (std::uint32_t k : t.i) {
            for (int q = 0; q < 6; ++q) gamma[k][q] += t.area * g[q];
            gw[k] += t.area;
        }
    }
    std::vector<UvMetricVertex> out(n);
    for (std::size_t k = 0; k < n; ++k) {
        if (!(weight[k] > 0.0)) continue;
        out[k].dpdu = f3(su[k]);
        out[k].dpdv = f3(sv[k]);
        if (!(gw[k] > 0.0)) continue;
        for (int q = 0; q < 3; ++q) {
            out[k].gamma_u[q] = float(gamma[k][q] / gw[k]);
            out[k].gamma_v[q] = float(gamma[k][3 + q] / gw[k]);
        }
    }
    return out;
}

}  // namespace offsetmap
