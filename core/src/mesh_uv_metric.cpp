// Double precision throughout; core links nothing but OpenCL.
#include "offsetmap/mesh_uv_metric.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

#include "mesh_arrays.hpp"
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

void check(const UvMetricMesh& m) {
    if (m.vertex_count && (!m.positions || !m.uvs))
        throw Error("derive_uv_metric: the mesh has " + std::to_string(m.vertex_count) +
                    " vertices but no positions or uvs");
    check_triangles("derive_uv_metric", m.indices, m.index_count, m.vertex_count);
}

// A triangle's uv edges from its first corner and the linear map's determinant: the rates of any
// per-corner value x over the triangle, d x / du and d x / dv.
struct UvEdges {
    double du1, dv1, du2, dv2, det;
    D3 rate_u(D3 x0, D3 x1, D3 x2) const { return ((x1 - x0) * dv2 - (x2 - x0) * dv1) * (1 / det); }
    D3 rate_v(D3 x0, D3 x1, D3 x2) const { return ((x2 - x0) * du1 - (x1 - x0) * du2) * (1 / det); }
};

// Groups of vertices at one place (a uv seam's sides, a pole's copies): within a millionth of the
// mesh's size, through a grid of cells of that size (each vertex against the 27 around its own).
std::vector<std::vector<std::size_t> > weld(const std::vector<D3>& p) {
    D3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (const D3& x : p) {
        lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
        hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
    }
    const D3 size = hi - lo;
    const double eps = std::max(1e-6 * std::sqrt(dot(size, size)), 1e-30);
    std::map<std::array<long long, 3>, std::vector<std::size_t> > cells;
    std::vector<std::size_t> group(p.size());
    std::vector<std::vector<std::size_t> > groups;
    for (std::size_t k = 0; k < p.size(); ++k) {
        const D3 q = (p[k] - lo) * (1 / eps);
        const long long c[3] = {static_cast<long long>(std::floor(q.x)),
                                static_cast<long long>(std::floor(q.y)),
                                static_cast<long long>(std::floor(q.z))};
        std::size_t found = SIZE_MAX;
        for (int d = 0; d < 27 && found == SIZE_MAX; ++d) {
            const auto it = cells.find({c[0] + d % 3 - 1, c[1] + d / 3 % 3 - 1, c[2] + d / 9 - 1});
            if (it == cells.end()) continue;
            for (std::size_t r : it->second) {
                const D3 e = p[r] - p[k];
                if (dot(e, e) <= eps * eps) {
                    found = group[r];
                    break;
                }
            }
        }
        if (found == SIZE_MAX) {
            found = groups.size();
            groups.emplace_back();
            cells[{c[0], c[1], c[2]}].push_back(k);
        }
        group[k] = found;
        groups[found].push_back(k);
    }
    std::vector<std::vector<std::size_t> > of(p.size());
    for (std::size_t k = 0; k < p.size(); ++k) of[k] = groups[group[k]];
    return of;
}

// One triangle's contribution: its area, its uv orientation and its dP/du and dP/dv.
struct Face {
    std::uint32_t i[3];
    UvEdges e;
    double area;
    D3 dpdu, dpdv;
};

// The mesh's usable triangles (uv and world area above 1e-20) and each vertex's.
struct Faces {
    std::vector<Face> list;
    std::vector<std::vector<std::size_t> > of;  // per vertex, indices into list
};

Faces collect_faces(const UvMetricMesh& mesh, const std::vector<D3>& pos) {
    Faces faces;
    faces.of.resize(pos.size());
    auto uv = [&](std::size_t k) {
        return strided_row(mesh.uvs, mesh.uv_stride, k, 2 * sizeof(float));
    };
    for (std::size_t t = 0; t < mesh.index_count; t += 3) {
        Face f{{mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]}, {}, 0.0, {}, {}};
        const float *a = uv(f.i[0]), *b = uv(f.i[1]), *c = uv(f.i[2]);
        UvEdges& e = f.e;
        e.du1 = double(b[0]) - a[0], e.dv1 = double(b[1]) - a[1];
        e.du2 = double(c[0]) - a[0], e.dv2 = double(c[1]) - a[1];
        e.det = e.du1 * e.dv2 - e.du2 * e.dv1;
        const D3 p0 = pos[f.i[0]], p1 = pos[f.i[1]], p2 = pos[f.i[2]];
        const D3 cr = cross(p1 - p0, p2 - p0);
        f.area = 0.5 * std::sqrt(dot(cr, cr));
        if (std::fabs(e.det) < 1e-20 || !(f.area > 1e-20) || !std::isfinite(e.det)) continue;
        f.dpdu = e.rate_u(p0, p1, p2);
        f.dpdv = e.rate_v(p0, p1, p2);
        for (std::uint32_t k : f.i) faces.of[k].push_back(faces.list.size());
        faces.list.push_back(f);
    }
    return faces;
}

// Each vertex's seam's triangles, once each: those of every vertex at its place whose uv runs
// the way its own triangles' does (the same orientation, dP/du and dP/dv within 90 degrees of
// its own: a translated seam, not a mirrored or turned one), so a seam's vertex has both sides'
// triangles, as one inside has.
std::vector<std::vector<std::size_t> > seam_faces(const Faces& faces, const std::vector<D3>& pos) {
    const std::size_t n = pos.size();
    const std::vector<std::vector<std::size_t> > welded = weld(pos);
    std::vector<std::vector<std::size_t> > seam(n);
    for (std::size_t k = 0; k < n; ++k) {
        if (faces.of[k].empty()) continue;
        D3 own_u, own_v;
        for (std::size_t q : faces.of[k]) {
            own_u = own_u + faces.list[q].dpdu * faces.list[q].area;
            own_v = own_v + faces.list[q].dpdv * faces.list[q].area;
        }
        const bool positive = faces.list[faces.of[k][0]].e.det > 0.0;
        for (std::size_t j : welded[k])
            for (std::size_t q : faces.of[j]) {
                const Face& f = faces.list[q];
                if ((f.e.det > 0.0) == positive && dot(f.dpdu, own_u) > 0.0 &&
                    dot(f.dpdv, own_v) > 0.0)
                    seam[k].push_back(q);
            }
        std::sort(seam[k].begin(), seam[k].end());
        seam[k].erase(std::unique(seam[k].begin(), seam[k].end()), seam[k].end());
    }
    return seam;
}

// A triangle's Christoffel symbols (Gamma^u uu, uv, vv, then Gamma^v) from the rates of the
// vertices' dP/du (su) and dP/dv (sv) interpolated over it, at its centroid's; false where its
// first fundamental form is singular or a symbol is not finite.
bool face_symbols(const Face& t, const std::vector<D3>& su, const std::vector<D3>& sv,
                  std::array<double, 6>& g) {
    const std::uint32_t a = t.i[0], b = t.i[1], c = t.i[2];
    const D3 suu = t.e.rate_u(su[a], su[b], su[c]), suv_a = t.e.rate_v(su[a], su[b], su[c]);
    const D3 suv_b = t.e.rate_u(sv[a], sv[b], sv[c]), svv = t.e.rate_v(sv[a], sv[b], sv[c]);
    const D3 suv = (suv_a + suv_b) * 0.5;
    const D3 tu = (su[a] + su[b] + su[c]) * (1.0 / 3), tv = (sv[a] + sv[b] + sv[c]) * (1.0 / 3);
    const double E = dot(tu, tu), F = dot(tu, tv), G = dot(tv, tv), det = E * G - F * F;
    if (!(det > 1e-30 * (E * G))) return false;
    const D3 second[3] = {suu, suv, svv};
    bool finite = true;
    for (int ij = 0; ij < 3; ++ij) {
        const double xu = dot(second[ij], tu), xv = dot(second[ij], tv);
        g[ij] = (G * xu - F * xv) / det;      // Gamma^u_ij
        g[3 + ij] = (E * xv - F * xu) / det;  // Gamma^v_ij
        finite = finite && std::isfinite(g[ij]) && std::isfinite(g[3 + ij]);
    }
    return finite;
}

}  // namespace

std::vector<UvMetricVertex> derive_uv_metric(const UvMetricMesh& mesh) {
    check(mesh);
    const std::size_t n = mesh.vertex_count;
    std::vector<D3> pos(n);
    for (std::size_t k = 0; k < n; ++k) {
        const float* p = strided_row(mesh.positions, mesh.position_stride, k, 3 * sizeof(float));
        pos[k] = D3{p[0], p[1], p[2]};
    }
    const Faces faces = collect_faces(mesh, pos);
    const std::vector<std::vector<std::size_t> > seam = seam_faces(faces, pos);
    // dP/du and dP/dv a vertex: its seam's triangles', area-weighted (the renderer's tangents').
    std::vector<D3> su(n), sv(n);
    for (std::size_t k = 0; k < n; ++k) {
        double w = 0.0;
        for (std::size_t q : seam[k]) {
            su[k] = su[k] + faces.list[q].dpdu * faces.list[q].area;
            sv[k] = sv[k] + faces.list[q].dpdv * faces.list[q].area;
            w += faces.list[q].area;
        }
        if (w > 0.0) su[k] = su[k] * (1 / w), sv[k] = sv[k] * (1 / w);
    }
    std::vector<std::array<double, 6> > face_gamma(faces.list.size());
    std::vector<bool> has_gamma(faces.list.size());
    for (std::size_t q = 0; q < faces.list.size(); ++q)
        has_gamma[q] = face_symbols(faces.list[q], su, sv, face_gamma[q]);
    // The symbols a vertex: its seam's triangles', area-weighted.
    std::vector<UvMetricVertex> out(n);
    for (std::size_t k = 0; k < n; ++k) {
        if (seam[k].empty()) continue;
        out[k].dpdu = f3(su[k]);
        out[k].dpdv = f3(sv[k]);
        std::array<double, 6> sum{};
        double w = 0.0;
        for (std::size_t q : seam[k]) {
            if (!has_gamma[q]) continue;
            for (int i = 0; i < 6; ++i) sum[i] += faces.list[q].area * face_gamma[q][i];
            w += faces.list[q].area;
        }
        if (!(w > 0.0)) continue;
        for (int i = 0; i < 3; ++i) {
            out[k].gamma_u[i] = float(sum[i] / w);
            out[k].gamma_v[i] = float(sum[3 + i] / w);
        }
    }
    return out;
}

}  // namespace offsetmap
