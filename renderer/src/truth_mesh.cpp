// The displaced mesh: each relief triangle cut along the lattice of lines through texel centres
// (every texels_per_quad texels), so that every piece lies inside one bilinear cell of the height
// field and the tessellated surface departs from the bilinear one by the cell's twist alone;
// pieces are displaced along the interpolated normal and culled to the view.
//
// Lattice coordinates: X = (u W - 0.5) / texels_per_quad, Y likewise; whole X and Y are lattice
// lines. A point of a triangle's edge is computed from the edge's endpoints in one order (the
// smaller vertex first), so the two triangles sharing the edge make the same point, bit for bit,
// and the displaced mesh has no cracks where its base mesh had none.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <tuple>
#include <unordered_map>

#include "offsetmap/error.hpp"
#include "offsetmap/oracle.hpp"
#include "offsetmap/renderer/truth.hpp"
#include "offsetmap/timing.hpp"
#include "raster.hpp"
#include "truth_internal.hpp"

namespace offsetmap::renderer {

namespace {

struct Point {
    double X = 0, Y = 0;
    double w[3] = {0, 0, 0};                    // barycentric in the base triangle
    bool lattice_u = false, lattice_v = false;  // X (Y) is a lattice line: u (v) from it exactly
    int vertex = -1;                            // index in the output mesh once emitted
    glm::dvec4 clip{0.0};
    bool computed = false;
    Vertex data;
};

// The lattice cells the mesh's uv covers, two triangles each (k: lattice lines a texel).
double uv_triangles_estimate(const Mesh& base, const HeightMap& map, double k) {
    double cells = 0.0;
    for (size_t t = 0; t + 2 < base.indices.size(); t += 3) {
        const auto& a = base.vertices[base.indices[t]].uv;
        const auto& b = base.vertices[base.indices[t + 1]].uv;
        const auto& c = base.vertices[base.indices[t + 2]].uv;
        cells += 0.5 * std::fabs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) *
                 map.width * map.height * k * k;
    }
    return 2.0 * cells;
}

// The largest bilinear twist |H00 - H10 - H01 + H11| over the map's cells (wrapping ones too).
double max_twist(const HeightMap& m, AddressMode address) {
    const int w = m.width, h = m.height;
    auto at = [&](int i, int j) {
        if (address == AddressMode::Wrap) {
            i = (i % w + w) % w;
            j = (j % h + h) % h;
        } else {
            i = std::clamp(i, 0, w - 1);
            j = std::clamp(j, 0, h - 1);
        }
        return static_cast<double>(m.h[static_cast<size_t>(j) * w + i]);
    };
    double worst = 0.0;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            worst = std::max(worst,
                             std::fabs(at(i, j) - at(i + 1, j) - at(i, j + 1) + at(i + 1, j + 1)));
    return worst;
}

class Builder {
  public:
    Builder(const Mesh& base, const HeightMap& map, const PassSettings& s, double k,
            const glm::dmat4* view_projection, bool keep_back_faces)
        : base_(base),
          map_(map),
          s_(s),
          k_(k),
          vp_(view_projection),
          keep_back_faces_(keep_back_faces) {
        out_.name = base.name;
        out_.material = base.material;
    }

    void triangle(std::uint32_t ia, std::uint32_t ib, std::uint32_t ic);
    Mesh& mesh() { return out_; }

  private:
    const Mesh& base_;
    const HeightMap& map_;
    PassSettings s_;
    double k_;
    const glm::dmat4* vp_;
    bool keep_back_faces_;
    Mesh out_;
    const Vertex* v_[3] = {nullptr, nullptr, nullptr};
    std::vector<Point> pts_;
    double sign_ = 1.0;

    double lx(double u) const { return (u * map_.width - 0.5) * k_; }
    double ly(double v) const { return (v * map_.height - 0.5) * k_; }
    void compute(Point& p);
    void emit(int a, int b, int c);
    void polygon(std::vector<int>& ids);
};

void Builder::compute(Point& p) {
    if (p.computed) return;
    p.computed = true;
    glm::dvec3 pos(0.0), nrm(0.0), tan(0.0);
    double density = 0.0, u = 0.0, v = 0.0;
    for (int i = 0; i < 3; ++i) {
        const Vertex& b = *v_[i];
        pos += p.w[i] * glm::dvec3(b.position[0], b.position[1], b.position[2]);
        nrm += p.w[i] * glm::dvec3(b.normal[0], b.normal[1], b.normal[2]);
        tan += p.w[i] * glm::dvec3(b.tangent[0], b.tangent[1], b.tangent[2]);
        density += p.w[i] * b.uv_density;
        u += p.w[i] * b.uv[0];
        v += p.w[i] * b.uv[1];
    }
    if (p.lattice_u) u = (p.X / k_ + 0.5) / map_.width;
    if (p.lattice_v) v = (p.Y / k_ + 0.5) / map_.height;
    const double len = glm::length(nrm);
    const glm::dvec3 n = len > 0.0 ? nrm / len : glm::dvec3(0.0);
    const double lift =
        density * s_.scale * (bilinear_height(map_, u, v, s_.address) - s_.reference_plane);
    pos += n * lift;
    Vertex& d = p.data;
    d.position = {float(pos.x), float(pos.y), float(pos.z)};
    d.normal = {float(n.x), float(n.y), float(n.z)};
    d.tangent = {float(tan.x), float(tan.y), float(tan.z), v_[0]->tangent[3]};
    d.uv = {float(u), float(v)};
    d.uv_density = float(density);
    if (vp_) p.clip = *vp_ * glm::dvec4(pos, 1.0);
}

// The triangle (a, b, c) of pts_, oriented as the base triangle, unless the view cannot see it.
void Builder::emit(int a, int b, int c) {
    Point* p[3] = {&pts_[a], &pts_[b], &pts_[c]};
    for (Point* q : p) compute(*q);
    emit_triangle(p, vp_, keep_back_faces_, out_);
}

// A convex piece: its points in angle order around their mean, as a fan.
void Builder::polygon(std::vector<int>& ids) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    if (ids.size() < 3) return;
    double cx = 0, cy = 0;
    for (int i : ids) cx += pts_[i].X, cy += pts_[i].Y;
    cx /= ids.size();
    cy /= ids.size();
    std::sort(ids.begin(), ids.end(), [&](int a, int b) {
        return std::atan2(pts_[a].Y - cy, pts_[a].X - cx) <
               std::atan2(pts_[b].Y - cy, pts_[b].X - cx);
    });
    for (size_t i = 1; i + 1 < ids.size(); ++i) {
        if (sign_ > 0)
            emit(ids[0], ids[i], ids[i + 1]);
        else
            emit(ids[0], ids[i + 1], ids[i]);
    }
}

void Builder::triangle(std::uint32_t ia, std::uint32_t ib, std::uint32_t ic) {
    const std::uint32_t idx[3] = {ia, ib, ic};
    for (int i = 0; i < 3; ++i) v_[i] = &base_.vertices[idx[i]];
    pts_.clear();
    for (int i = 0; i < 3; ++i) {
        Point p;
        p.X = lx(v_[i]->uv[0]);
        p.Y = ly(v_[i]->uv[1]);
        p.w[i] = 1.0;
        pts_.push_back(p);
    }
    const double area = (pts_[1].X - pts_[0].X) * (pts_[2].Y - pts_[0].Y) -
                        (pts_[2].X - pts_[0].X) * (pts_[1].Y - pts_[0].Y);
    if (!(std::fabs(area) > 1e-18)) {  // no uv extent: the base triangle, displaced
        sign_ = 1.0;
        emit(0, 1, 2);
        return;
    }
    sign_ = area > 0 ? 1.0 : -1.0;
    // The cells each point lies in (two or four where it sits on lattice lines).
    std::unordered_map<std::uint64_t, std::vector<int>> cells;
    auto key = [](long long cx, long long cy) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(cy)) << 32) |
               static_cast<std::uint32_t>(cx);
    };
    auto bucket = [&](int id) {
        const Point& p = pts_[id];
        const long long fx = static_cast<long long>(std::floor(p.X)),
                        fy = static_cast<long long>(std::floor(p.Y));
        for (long long cx = fx - (p.X == fx ? 1 : 0); cx <= fx; ++cx)
            for (long long cy = fy - (p.Y == fy ? 1 : 0); cy <= fy; ++cy)
                cells[key(cx, cy)].push_back(id);
    };
    for (int i = 0; i < 3; ++i) bucket(i);
    // Where each edge crosses the lattice lines, from its endpoints in one order.
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        if (vertex_less(*v_[b], *v_[a])) std::swap(a, b);
        const Point pa = pts_[a], pb = pts_[b];
        for (int axis = 0; axis < 2; ++axis) {
            const double ca = axis ? pa.Y : pa.X, cb = axis ? pb.Y : pb.X;
            if (ca == cb) continue;
            const double lo = std::min(ca, cb), hi = std::max(ca, cb);
            for (double line = std::floor(lo) + 1.0; line < hi; line += 1.0) {
                if (line <= lo) continue;
                const double t = (line - ca) / (cb - ca);
                Point p;
                p.w[a] = 1.0 - t;
                p.w[b] = t;
                if (axis) {
                    p.Y = line;
                    p.X = pa.X + t * (pb.X - pa.X);
                    p.lattice_v = true;
                } else {
                    p.X = line;
                    p.Y = pa.Y + t * (pb.Y - pa.Y);
                    p.lattice_u = true;
                }
                pts_.push_back(p);
                bucket(static_cast<int>(pts_.size()) - 1);
            }
        }
    }
    // The lattice points strictly inside, row by row (a convex shape: one run a row).
    const double min_x = std::min({pts_[0].X, pts_[1].X, pts_[2].X}),
                 max_x = std::max({pts_[0].X, pts_[1].X, pts_[2].X}),
                 min_y = std::min({pts_[0].Y, pts_[1].Y, pts_[2].Y}),
                 max_y = std::max({pts_[0].Y, pts_[1].Y, pts_[2].Y});
    const long long row0 = static_cast<long long>(std::floor(min_y)),
                    row1 = static_cast<long long>(std::ceil(max_y));
    const long long col0 = static_cast<long long>(std::floor(min_x)),
                    col1 = static_cast<long long>(std::ceil(max_x));
    const double x0 = pts_[0].X, y0 = pts_[0].Y;
    const double e1x = pts_[1].X - x0, e1y = pts_[1].Y - y0, e2x = pts_[2].X - x0,
                 e2y = pts_[2].Y - y0;
    struct Run {
        long long first = 0, count = 0;
        int id = 0;
    };
    std::vector<Run> runs(static_cast<size_t>(row1 - row0 + 1));
    for (long long r = row0; r <= row1; ++r) {
        Run& run = runs[static_cast<size_t>(r - row0)];
        run.id = static_cast<int>(pts_.size());
        run.first = col1 + 1;
        for (long long c = col0; c <= col1; ++c) {
            const double px = c - x0, py = r - y0;
            const double b1 = (px * e2y - py * e2x) / area, b2 = (e1x * py - e1y * px) / area;
            const double b0 = 1.0 - b1 - b2;
            if (!(b0 > 1e-12 && b1 > 1e-12 && b2 > 1e-12)) {
                if (run.count) break;
                continue;
            }
            if (!run.count) run.first = c;
            ++run.count;
            Point p;
            p.X = static_cast<double>(c);
            p.Y = static_cast<double>(r);
            p.w[0] = b0;
            p.w[1] = b1;
            p.w[2] = b2;
            p.lattice_u = p.lattice_v = true;
            pts_.push_back(p);
        }
    }
    auto inside = [&](long long c, long long r) -> int {
        if (r < row0 || r > row1) return -1;
        const Run& run = runs[static_cast<size_t>(r - row0)];
        if (c < run.first || c >= run.first + run.count) return -1;
        return run.id + static_cast<int>(c - run.first);
    };
    std::vector<int> piece;
    for (long long cy = row0; cy < row1; ++cy)
        for (long long cx = col0; cx < col1; ++cx) {
            const int c00 = inside(cx, cy), c10 = inside(cx + 1, cy), c11 = inside(cx + 1, cy + 1),
                      c01 = inside(cx, cy + 1);
            const auto found = cells.find(key(cx, cy));
            if (found == cells.end()) {
                if (c00 < 0 || c10 < 0 || c11 < 0 || c01 < 0) continue;
                piece = {c00, c10, c11, c01};  // a whole cell: its two triangles
                if (sign_ > 0) {
                    emit(c00, c10, c11);
                    emit(c00, c11, c01);
                } else {
                    emit(c00, c11, c10);
                    emit(c00, c01, c11);
                }
                continue;
            }
            piece = found->second;
            for (int c : {c00, c10, c11, c01})
                if (c >= 0) piece.push_back(c);
            polygon(piece);
        }
}

}  // namespace

Tessellation displace_scene(const Scene& scene, const std::vector<LoadedMaterial>& table,
                            const TessellationOptions& o) {
    const Stopwatch clock;
    const double tpq = o.texels_per_quad;
    if (!(tpq > 0.0 && tpq <= 64.0))
        throw Error("tessellation: texels per quad must be in (0, 64], got " + std::to_string(tpq));
    const double k = 1.0 / tpq;
    if (tpq < 1.0 && std::fabs(k - std::round(k)) > 1e-6)
        throw Error(
            "tessellation: below one texel per quad, 1 / texels per quad must be whole "
            "(0.5, 0.25, ...), got " +
            std::to_string(tpq));
    glm::dmat4 vp(1.0);
    const bool cull = o.width > 0 && o.height > 0;
    if (cull) {
        const View view = make_view(scene.camera, o.width, o.height);
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) vp[c][r] = view.view_projection[4 * c + r];
    }
    Tessellation out;
    out.scene = scene;
    out.scene.meshes.clear();
    std::unordered_map<int, double> twists;
    for (const Mesh& base : scene.meshes) {
        const LoadedMaterial* material = nullptr;
        for (const LoadedMaterial& m : table)
            if (m.spec.id == base.material && base.material != 0) material = &m;
        TessellatedMesh info;
        info.name = base.name;
        info.material = base.material;
        info.base_triangles = base.indices.size() / 3;
        if (!material || material->spec.settings.scale == 0.0f) {  // nothing to displace
            out.scene.meshes.push_back(base);
            info.triangles = info.base_triangles;
            info.height_bound = std::nan("");
        } else {
            const PassSettings& s = material->spec.settings;
            // Its height is a blend of three projections' (docs/design.md): the world's lattice.
            const bool triplanar = material->spec.triplanar.enabled;
            // Before any work: about how many triangles the lattice makes of the mesh.
            const double needed = triplanar ? triplanar_triangles_estimate(base, *material, tpq)
                                            : uv_triangles_estimate(base, material->map, k);
            if (needed > 20.0 * static_cast<double>(o.max_triangles))
                throw Error("tessellation: mesh '" + base.name + "' would need about " +
                            std::to_string(static_cast<long long>(needed)) + " triangles at " +
                            std::to_string(tpq) + " texels per quad before culling; the limit is " +
                            std::to_string(o.max_triangles) + " kept");
            auto build = [&](auto& builder) {
                for (size_t t = 0; t + 2 < base.indices.size(); t += 3) {
                    builder.triangle(base.indices[t], base.indices[t + 1], base.indices[t + 2]);
                    if (out.triangles + builder.mesh().indices.size() / 3 > o.max_triangles)
                        throw Error("tessellation: mesh '" + base.name + "' needs more than " +
                                    std::to_string(o.max_triangles - out.triangles) +
                                    " triangles at " + std::to_string(tpq) +
                                    " texels per quad (about " +
                                    std::to_string(static_cast<long long>(needed)) +
                                    " before culling); the limit over the scene is " +
                                    std::to_string(o.max_triangles));
                }
                out.scene.meshes.push_back(std::move(builder.mesh()));
            };
            if (triplanar) {
                TriplanarBuilder builder(base, *material, tpq, cull ? &vp : nullptr,
                                         o.keep_back_faces);
                build(builder);
            } else {
                Builder builder(base, material->map, s, k, cull ? &vp : nullptr, o.keep_back_faces);
                build(builder);
            }
            info.triangles = out.scene.meshes.back().indices.size() / 3;
            info.texels_per_quad = static_cast<float>(tpq);
            info.triplanar = triplanar;
            // A blend's weights vary over a piece with the interpolated normal: no bound derived.
            if (tpq <= 1.0 && !triplanar) {
                auto it = twists.find(base.material);
                if (it == twists.end())
                    it = twists.emplace(base.material, max_twist(material->map, s.address)).first;
                info.height_bound = it->second * tpq * tpq / 4.0;  // see truth_bound_texels
            } else {
                info.height_bound = std::nan("");
            }
        }
        const Mesh& m = out.scene.meshes.back();
        out.triangles += m.indices.size() / 3;
        out.bytes += m.vertices.size() * sizeof(Vertex) + m.indices.size() * sizeof(std::uint32_t);
        out.meshes.push_back(info);
    }
    out.build_ms = clock.total();
    return out;
}

}  // namespace offsetmap::renderer
