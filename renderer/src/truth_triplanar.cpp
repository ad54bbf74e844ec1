// The displaced mesh of a triplanar material: each base triangle cut by the planes x, y, z =
// const through the texel centres of every projection that reads that axis (every
// texels_per_quad texels), so that each piece lies inside one bilinear cell of each projection at
// once, then displaced along the interpolated normal by the blended height. The planes come in one
// family a pass (x, then y, then z), each convex piece cut at every line it spans; a point on a
// base edge is computed from the edge's endpoints in one order, so the triangles sharing the edge
// make it bit for bit and the displaced mesh has no cracks where its base mesh had none.
//
// Each vertex's tangent carries its base point (xyz, and 1): the pixel's uv in whichever
// projection a frame gives it is the base point's projection (triplanar_truth_uv).
#include <algorithm>
#include <cmath>
#include <map>

#include "offsetmap/oracle.hpp"
#include "offsetmap/triplanar.hpp"
#include "truth_internal.hpp"

namespace offsetmap::renderer {

namespace {

// Lattice units within which a point lies on a plane: far below a plane's spacing from another
// family's (whole fractions of a texel), far above double rounding.
constexpr double kOnPlane = 1e-9;

glm::dvec3 position_of(const Vertex& v) { return {v.position[0], v.position[1], v.position[2]}; }

double dot(const glm::dvec3& a, const std::array<double, 3>& b) {
    return a.x * b[0] + a.y * b[1] + a.z * b[2];
}

// The axes each projection reads and the map size along them (docs/design.md's frames): x is u
// of +-Y and +-Z; y is v of +-X and +-Z; z is u of +-X and v of +-Y (two families when the map is
// not square).
std::vector<std::pair<int, int>> cut_sizes(const HeightMap& map) {
    std::vector<std::pair<int, int>> cuts = {{0, map.width}, {1, map.height}, {2, map.width}};
    if (map.height != map.width) cuts.push_back({2, map.height});
    return cuts;
}

}  // namespace

TriplanarBuilder::TriplanarBuilder(const Mesh& base, const LoadedMaterial& material,
                                   double texels_per_quad, const glm::dmat4* view_projection,
                                   bool keep_back_faces)
    : base_(base),
      m_(material),
      tpq_(texels_per_quad),
      vp_(view_projection),
      keep_back_faces_(keep_back_faces) {
    out_.name = base.name;
    out_.material = base.material;
    for (const auto& [axis, size] : cut_sizes(material.map))
        cuts_.push_back({axis, material.spec.triplanar.world_scale * static_cast<double>(size)});
}

// A point's lattice coordinates: whole values lie on a cut's planes (u D - 1/2 = whole multiples
// of texels_per_quad for the projection with u along +axis; the one along -axis has the same
// planes when 1 / texels_per_quad is whole).
int TriplanarBuilder::add(Point p) {
    for (size_t c = 0; c < cuts_.size(); ++c)
        p.lattice[c] = (p.pos[cuts_[c].axis] * cuts_[c].texels_per_unit - 0.5) / tpq_;
    pts_.push_back(p);
    return static_cast<int>(pts_.size()) - 1;
}

int TriplanarBuilder::crossing(int a, int b, int cut, double line) {
    const unsigned common = pts_[a].edges & pts_[b].edges;
    Point p;
    if (common) {
        // On base edge e: from its endpoints, smaller first, as the neighbour computes it.
        const int e = common & 1u ? 0 : common & 2u ? 1 : 2;
        int i = e, j = (e + 1) % 3;
        if (vertex_less(*v_[j], *v_[i])) std::swap(i, j);
        const Cut& c = cuts_[static_cast<size_t>(cut)];
        const double li = (v_[i]->position[c.axis] * c.texels_per_unit - 0.5) / tpq_,
                     lj = (v_[j]->position[c.axis] * c.texels_per_unit - 0.5) / tpq_;
        const double t = (line - li) / (lj - li);
        p.w[i] = 1.0 - t;
        p.w[j] = t;
        p.edges = 1u << e;
    } else {
        const double la = pts_[a].lattice[cut], lb = pts_[b].lattice[cut];
        const double t = (line - la) / (lb - la);
        for (int i = 0; i < 3; ++i) p.w[i] = (1.0 - t) * pts_[a].w[i] + t * pts_[b].w[i];
    }
    for (int i = 0; i < 3; ++i) p.pos += p.w[i] * position_of(*v_[i]);
    const int id = add(p);
    pts_[static_cast<size_t>(id)].lattice[cut] = line;
    return id;
}

void TriplanarBuilder::compute(Point& p) {
    if (p.computed) return;
    p.computed = true;
    glm::dvec3 nrm(0.0);
    for (int i = 0; i < 3; ++i)
        nrm += p.w[i] * glm::dvec3(v_[i]->normal[0], v_[i]->normal[1], v_[i]->normal[2]);
    const double len = glm::length(nrm);
    const glm::dvec3 n = len > 0.0 ? nrm / len : glm::dvec3(0.0);
    const Triplanar& tri = m_.spec.triplanar;
    const PassSettings& s = m_.spec.settings;
    const std::array<double, 3> na = {n.x, n.y, n.z};
    const std::array<double, 3> w = triplanar_weights(na, tri.sharpness, tri.cutoff);
    double height = 0.0, largest = -1.0;
    std::array<float, 2> uv{};
    for (int a = 0; a < 3; ++a) {
        const TriplanarFrame f = triplanar_frame(triplanar_projection(na, a));
        const double u = tri.world_scale * dot(p.pos, f.t), v = tri.world_scale * dot(p.pos, f.b);
        if (w[a] > 0.0) height += w[a] * bilinear_height(m_.map, u, v, s.address);
        if (w[a] > largest) {
            largest = w[a];
            uv = {static_cast<float>(u), static_cast<float>(v)};
        }
    }
    const double density = 1.0 / tri.world_scale;
    const glm::dvec3 pos = p.pos + n * (density * s.scale * (height - s.reference_plane));
    Vertex& d = p.data;
    d.position = {float(pos.x), float(pos.y), float(pos.z)};
    d.normal = {float(n.x), float(n.y), float(n.z)};
    d.tangent = {float(p.pos.x), float(p.pos.y), float(p.pos.z), 1.0f};
    d.uv = uv;  // the largest projection's, at this point
    d.uv_density = static_cast<float>(density);
    if (vp_) p.clip = *vp_ * glm::dvec4(pos, 1.0);
}

// A convex piece in the base triangle's order, as a fan, less what the view cannot see.
void TriplanarBuilder::emit(const std::vector<int>& polygon) {
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        Point* p[3] = {&pts_[polygon[0]], &pts_[polygon[k]], &pts_[polygon[k + 1]]};
        for (Point* q : p) compute(*q);
        emit_triangle(p, vp_, keep_back_faces_, out_);
    }
}

void TriplanarBuilder::triangle(std::uint32_t ia, std::uint32_t ib, std::uint32_t ic) {
    const std::uint32_t idx[3] = {ia, ib, ic};
    for (int i = 0; i < 3; ++i) v_[i] = &base_.vertices[idx[i]];
    pts_.clear();
    for (int i = 0; i < 3; ++i) {
        Point p;
        p.w[i] = 1.0;
        p.pos = position_of(*v_[i]);
        p.edges = (1u << i) | (1u << ((i + 2) % 3));
        add(p);
    }
    std::vector<std::vector<int>> pieces = {{0, 1, 2}}, next;
    std::map<std::tuple<int, int, double>, int> crossings;  // this pass's, by edge and line
    std::vector<int> below, above;
    for (size_t cut = 0; cut < cuts_.size(); ++cut) {
        next.clear();
        crossings.clear();
        for (std::vector<int>& piece : pieces) {
            double lo = HUGE_VAL, hi = -HUGE_VAL;
            for (int i : piece) {
                lo = std::min(lo, pts_[i].lattice[cut]);
                hi = std::max(hi, pts_[i].lattice[cut]);
            }
            for (double line = std::floor(lo) + 1.0; line < hi; line += 1.0) {
                // Two families' planes can coincide (z's for a map's width and height): a point
                // the first put on the plane is on the second's, not a hair off it.
                auto side = [&](int i) {
                    const double d = pts_[i].lattice[cut] - line;
                    return std::fabs(d) < kOnPlane ? 0.0 : d;
                };
                bool under = false, over = false;
                for (int i : piece) {
                    under = under || side(i) < 0.0;
                    over = over || side(i) > 0.0;
                }
                if (!under || !over) continue;
                below.clear();
                above.clear();
                for (size_t k = 0; k < piece.size(); ++k) {
                    const int a = piece[k], b = piece[(k + 1) % piece.size()];
                    const double da = side(a), db = side(b);
                    if (da <= 0.0) below.push_back(a);
                    if (da >= 0.0) above.push_back(a);
                    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) {
                        const auto key = std::make_tuple(std::min(a, b), std::max(a, b), line);
                        auto found = crossings.find(key);
                        if (found == crossings.end())
                            found = crossings.emplace(key, crossing(a, b, int(cut), line)).first;
                        below.push_back(found->second);
                        above.push_back(found->second);
                    }
                }
                next.push_back(below);
                piece = above;
            }
            next.push_back(std::move(piece));
        }
        std::swap(pieces, next);
    }
    for (const std::vector<int>& piece : pieces) emit(piece);
}

double triplanar_triangles_estimate(const Mesh& base, const LoadedMaterial& m, double tpq) {
    // A plane of area A meets about A |n|_1 / step^2 cubes of a grid of that step; a piece is
    // a polygon of about 2.5 triangles.
    double sum = 0.0;
    const double step = tpq / (m.spec.triplanar.world_scale * std::max(m.map.width, m.map.height));
    for (size_t t = 0; t + 2 < base.indices.size(); t += 3) {
        const glm::dvec3 a = position_of(base.vertices[base.indices[t]]),
                         b = position_of(base.vertices[base.indices[t + 1]]),
                         c = position_of(base.vertices[base.indices[t + 2]]);
        const glm::dvec3 cross = glm::cross(b - a, c - a);
        sum += 0.5 * (std::fabs(cross.x) + std::fabs(cross.y) + std::fabs(cross.z));
    }
    return 2.5 * sum / (step * step);
}

}  // namespace offsetmap::renderer
