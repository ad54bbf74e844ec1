// Double precision throughout, in the operation order of the GLM expressions the renderer first
// wrote this with (its frames are unchanged bit for bit): core links nothing but OpenCL.
#include "offsetmap/mesh_curvature.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "mesh_arrays.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap {

namespace {

struct D3 {
    double x = 0, y = 0, z = 0;
    double operator[](int i) const { return i == 0 ? x : i == 1 ? y : z; }
    double& operator[](int i) { return i == 0 ? x : i == 1 ? y : z; }
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
D3 operator*(double s, D3 a) { return {s * a.x, s * a.y, s * a.z}; }
D3 operator/(D3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) {
    return {a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y};
}
double length(D3 a) { return std::sqrt(dot(a, a)); }
D3 normalize(D3 a) { return a * (1.0 / std::sqrt(dot(a, a))); }

// Column-major as GLM's: m[column][row].
struct M3 {
    D3 c[3];
    const D3& operator[](int i) const { return c[i]; }
    D3& operator[](int i) { return c[i]; }
};
M3 operator+(const M3& a, const M3& b) { return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}}; }
M3 operator*(double s, const M3& m) { return {{m[0] * s, m[1] * s, m[2] * s}}; }
M3 operator/(const M3& m, double s) { return {{m[0] / s, m[1] / s, m[2] / s}}; }
M3& operator+=(M3& a, const M3& b) { return a = a + b; }
D3 operator*(const M3& m, D3 v) {
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
            m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}
// column c times row r: m[i][j] = c[j] r[i].
M3 outer(D3 c, D3 r) { return {{c * r.x, c * r.y, c * r.z}}; }
double determinant(const M3& m) {
    return +m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) -
           m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2]) +
           m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2]);
}
M3 inverse(const M3& m) {
    const double d = 1.0 / determinant(m);
    M3 r;
    r[0][0] = +(m[1][1] * m[2][2] - m[2][1] * m[1][2]) * d;
    r[1][0] = -(m[1][0] * m[2][2] - m[2][0] * m[1][2]) * d;
    r[2][0] = +(m[1][0] * m[2][1] - m[2][0] * m[1][1]) * d;
    r[0][1] = -(m[0][1] * m[2][2] - m[2][1] * m[0][2]) * d;
    r[1][1] = +(m[0][0] * m[2][2] - m[2][0] * m[0][2]) * d;
    r[2][1] = -(m[0][0] * m[2][1] - m[2][0] * m[0][1]) * d;
    r[0][2] = +(m[0][1] * m[1][2] - m[1][1] * m[0][2]) * d;
    r[1][2] = -(m[0][0] * m[1][2] - m[1][0] * m[0][2]) * d;
    r[2][2] = +(m[0][0] * m[1][1] - m[1][0] * m[0][1]) * d;
    return r;
}

// The mesh's arrays read at their strides.
struct Arrays {
    const CurvatureMesh& m;
    static D3 at(const float* base, std::size_t stride, std::size_t k, std::size_t packed) {
        const float* p = strided_row(base, stride, k, packed);
        return {p[0], p[1], p[2]};
    }
    D3 position(std::size_t k) const {
        return at(m.positions, m.position_stride, k, 3 * sizeof(float));
    }
    D3 normal(std::size_t k) const { return at(m.normals, m.normal_stride, k, 3 * sizeof(float)); }
    D3 tangent(std::size_t k) const {
        return at(m.tangents, m.tangent_stride, k, 4 * sizeof(float));
    }
    float handedness(std::size_t k) const {
        return strided_row(m.tangents, m.tangent_stride, k, 4 * sizeof(float))[3];
    }
};

void check(const CurvatureMesh& m) {
    if (m.vertex_count && (!m.positions || !m.normals || !m.tangents))
        throw Error("derive_curvature: the mesh has " + std::to_string(m.vertex_count) +
                    " vertices but no positions, normals or tangents");
    check_triangles("derive_curvature", m.indices, m.index_count, m.vertex_count);
}

// x turned by the rotation that takes the unit vector `from` onto `to` about their common
// perpendicular (Rodrigues); from and to must not be opposite.
D3 rotate_onto(D3 x, D3 from, D3 to) {
    const D3 axis = cross(from, to);
    const double s = length(axis), c = dot(from, to);
    if (s < 1e-15) return x;
    const D3 k = axis / s;
    return x * c + cross(k, x) * s + k * dot(k, x) * (1.0 - c);
}

// Groups of vertices at one place with one normal (a uv seam's two sides, a revolved mesh's
// first and last ring): within a millionth of the mesh's size and 1e-4 radian, found through a
// grid of cells of that size (each vertex against the 27 cells around its own).
std::vector<std::size_t> weld(const Arrays& a, std::size_t& count) {
    const std::size_t n = a.m.vertex_count;
    D3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (std::size_t k = 0; k < n; ++k) {
        const D3 p = a.position(k);
        for (int i = 0; i < 3; ++i) {
            lo[i] = p[i] < lo[i] ? p[i] : lo[i];
            hi[i] = hi[i] < p[i] ? p[i] : hi[i];
        }
    }
    const double eps = std::max(1e-6 * length(hi - lo), 1e-30);
    std::map<std::array<long long, 3>, std::vector<std::size_t> > cells;  // representatives
    std::vector<std::size_t> group(n);
    count = 0;
    for (std::size_t k = 0; k < n; ++k) {
        const D3 p = a.position(k), nk = normalize(a.normal(k));
        const D3 q = (p - lo) / eps;
        const long long c[3] = {static_cast<long long>(std::floor(q.x)),
                                static_cast<long long>(std::floor(q.y)),
                                static_cast<long long>(std::floor(q.z))};
        std::size_t found = SIZE_MAX;
        for (int dz = -1; dz <= 1 && found == SIZE_MAX; ++dz)
            for (int dy = -1; dy <= 1 && found == SIZE_MAX; ++dy)
                for (int dx = -1; dx <= 1 && found == SIZE_MAX; ++dx) {
                    const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == cells.end()) continue;
                    for (std::size_t r : it->second)
                        if (length(a.position(r) - p) <= eps &&
                            dot(normalize(a.normal(r)), nk) > 1.0 - 5e-9) {
                            found = group[r];
                            break;
                        }
                }
        if (found == SIZE_MAX) {
            found = count++;
            cells[{c[0], c[1], c[2]}].push_back(k);
        }
        group[k] = found;
    }
    return group;
}

// One face's tensor in its own frame (uf, vf, nf): the symmetric [[a, b], [b, c]] with
// K (e.u, e.v) = (dn.u, dn.v) over the three edges, least squares (the normal equations of the
// rows (eu, ev, 0) and (0, eu, ev)). False where the edges do not determine it.
bool face_tensor(const D3 p[3], const D3 nv[3], D3 uf, D3 vf, D3& abc) {
    M3 ata{};
    D3 atb{};
    for (int i = 0; i < 3; ++i) {
        const D3 e = p[(i + 2) % 3] - p[(i + 1) % 3];
        const D3 dn = nv[(i + 2) % 3] - nv[(i + 1) % 3];
        const double eu = dot(e, uf), ev = dot(e, vf);
        const double du = dot(dn, uf), dv = dot(dn, vf);
        const D3 r1{eu, ev, 0.0}, r2{0.0, eu, ev};
        ata += outer(r1, r1) + outer(r2, r2);
        atb = atb + (r1 * du + r2 * dv);
    }
    if (!(std::fabs(determinant(ata)) > 1e-30)) return false;
    abc = inverse(ata) * atb;
    return true;
}

}  // namespace

std::vector<std::array<float, 3> > derive_curvature(const CurvatureMesh& mesh) {
    check(mesh);
    const Arrays a{mesh};
    const std::size_t n = mesh.vertex_count;
    std::size_t groups = 0;
    const std::vector<std::size_t> group = weld(a, groups);
    // Per group: the area-weighted sum of the faces' tensors as 3 x 3 world tensors, each face's
    // first turned so its normal is the vertex's.
    std::vector<M3> sum(groups, M3{});
    std::vector<double> weight(groups, 0.0);
    for (std::size_t t = 0; t < mesh.index_count; t += 3) {
        D3 p[3], nv[3];
        for (int c = 0; c < 3; ++c) {
            p[c] = a.position(mesh.indices[t + c]);
            nv[c] = normalize(a.normal(mesh.indices[t + c]));
        }
        const D3 cr = cross(p[1] - p[0], p[2] - p[0]);
        const double area = 0.5 * length(cr);
        if (!(area > 1e-20)) continue;
        const D3 nf = cr / (2.0 * area);
        const D3 uf = normalize(p[1] - p[0]), vf = cross(nf, uf);
        D3 abc;
        if (!face_tensor(p, nv, uf, vf, abc)) continue;
        for (int c = 0; c < 3; ++c) {
            if (dot(nv[c], nf) <= 0.0) continue;  // a normal against its face's winding
            const D3 u = rotate_onto(uf, nf, nv[c]), v = rotate_onto(vf, nf, nv[c]);
            const M3 face =
                abc.x * outer(u, u) + abc.y * (outer(u, v) + outer(v, u)) + abc.z * outer(v, v);
            const std::size_t k = group[mesh.indices[t + c]];
            sum[k] += area * face;
            weight[k] += area;
        }
    }
    std::vector<std::array<float, 3> > out(n, {0.0f, 0.0f, 0.0f});
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t q = group[k];
        if (!(weight[q] > 0.0)) continue;
        const M3 K = sum[q] / weight[q];
        const D3 nn = normalize(a.normal(k));
        const D3 tt = normalize(a.tangent(k));
        const D3 bb = double(a.handedness(k) < 0.0f ? -1.0f : 1.0f) * cross(nn, tt);
        out[k] = {float(dot(tt, K * tt)), float(dot(tt, K * bb)), float(dot(bb, K * bb))};
    }
    return out;
}

}  // namespace offsetmap
