// What the displaced-mesh builders share (truth_mesh.cpp cuts along uv's lattice,
// truth_triplanar.cpp along the world's).
#pragma once
#include <cstdint>
#include <glm/glm.hpp>
#include <tuple>
#include <vector>

#include "offsetmap/material_table.hpp"
#include "offsetmap/renderer/mesh.hpp"

namespace offsetmap::renderer {

// The order a shared edge's endpoints are taken in, so both triangles make its points alike.
inline bool vertex_less(const Vertex& a, const Vertex& b) {
    return std::tie(a.position[0], a.position[1], a.position[2], a.uv[0], a.uv[1]) <
           std::tie(b.position[0], b.position[1], b.position[2], b.uv[0], b.uv[1]);
}

// Whether a view cannot see the triangle of these clip-space corners: all outside one side of the
// frustum, or (in front of the eye) facing away, unless back faces are kept (front: CCW).
inline bool outside_view(const glm::dvec4* const clip[3], bool keep_back_faces) {
    for (int axis = 0; axis < 3; ++axis)
        for (double side : {-1.0, 1.0}) {
            bool out = true;
            for (int i = 0; i < 3; ++i) out = out && side * (*clip[i])[axis] > clip[i]->w;
            if (out) return true;
        }
    if (keep_back_faces || !(clip[0]->w > 0 && clip[1]->w > 0 && clip[2]->w > 0)) return false;
    const glm::dvec2 s0 = glm::dvec2(*clip[0]) / clip[0]->w, s1 = glm::dvec2(*clip[1]) / clip[1]->w,
                     s2 = glm::dvec2(*clip[2]) / clip[2]->w;
    return (s1.x - s0.x) * (s2.y - s0.y) - (s2.x - s0.x) * (s1.y - s0.y) <= 0.0;
}

// Appends the triangle of three computed points to `out`, in their order, each point's vertex
// once (`vertex`: its index in `out`, -1 until then), unless `view` (a view-projection, or null for
// none) cannot see it. P: a builder's point, with `clip`, `vertex` and `data`.
template <typename P>
void emit_triangle(P* const p[3], const glm::dmat4* view, bool keep_back_faces, Mesh& out) {
    const glm::dvec4* clip[3] = {&p[0]->clip, &p[1]->clip, &p[2]->clip};
    if (view && outside_view(clip, keep_back_faces)) return;
    for (int i = 0; i < 3; ++i) {
        if (p[i]->vertex < 0) {
            p[i]->vertex = static_cast<int>(out.vertices.size());
            out.vertices.push_back(p[i]->data);
        }
        out.indices.push_back(static_cast<std::uint32_t>(p[i]->vertex));
    }
}

// A triplanar material's mesh cut by the world's lattice planes and displaced by the blended
// height (docs/design.md, "Triplanar relief"), one base triangle at a time.
class TriplanarBuilder {
  public:
    TriplanarBuilder(const Mesh& base, const LoadedMaterial& material, double texels_per_quad,
                     const glm::dmat4* view_projection, bool keep_back_faces);
    void triangle(std::uint32_t ia, std::uint32_t ib, std::uint32_t ic);
    Mesh& mesh() { return out_; }

  private:
    struct Point {
        double w[3] = {0, 0, 0};  // barycentric in the base triangle
        glm::dvec3 pos{0.0};      // the base point
        double lattice[4] = {0, 0, 0, 0};
        unsigned edges = 0;  // the base triangle's edges it lies on (bit e: vertices e, e + 1)
        int vertex = -1;
        glm::dvec4 clip{0.0};
        bool computed = false;
        Vertex data;
    };
    struct Cut {
        int axis;
        double texels_per_unit;  // the map's texels along it per world unit (world_scale x size)
    };
    const Mesh& base_;
    const LoadedMaterial& m_;
    double tpq_;
    const glm::dmat4* vp_;
    bool keep_back_faces_;
    std::vector<Cut> cuts_;
    Mesh out_;
    const Vertex* v_[3] = {nullptr, nullptr, nullptr};
    std::vector<Point> pts_;

    int add(Point p);
    int crossing(int a, int b, int cut, double line);
    void compute(Point& p);
    void emit(const std::vector<int>& polygon);
};

// About how many triangles TriplanarBuilder makes of `base` before culling.
double triplanar_triangles_estimate(const Mesh& base, const LoadedMaterial& material,
                                    double texels_per_quad);

}  // namespace offsetmap::renderer
