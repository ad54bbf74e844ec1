// Triangle meshes as the renderer draws them: world-space vertices with a normal, a tangent frame
// (tangent along +u, w the handedness: B = w N x T, as the engine G-buffer stores it), uv and the
// uv density (world units per uv unit, which turns the offset pass's depth into a depth offset).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace offsetmap::renderer {

using Vec3 = std::array<float, 3>;

struct Vertex {
    Vec3 position{};
    Vec3 normal{};
    std::array<float, 4> tangent{};
    std::array<float, 2> uv{};
    float uv_density = 1.0f;
    // The base surface's second fundamental form in the vertex's tangent frame (T, B = w N x T),
    // world units (1 / m): k_TT, k_TB, k_BB of dN = K dP, positive where the surface bends away
    // from its normal (a sphere seen from outside: 1 / R, 0, 1 / R). Zero on a flat mesh.
    std::array<float, 3> curvature{};
    // log2 of the uv's stretch sqrt(|dP/du| / |dP/dv|) (derive_tangents): 0 where u and v have
    // one density. The log, so that a triangle whose corners have none interpolates to exactly
    // none.
    float uv_log_stretch = 0.0f;
    // The uv's metric (core's derive_uv_metric, offsetmap/mesh_uv_metric.hpp): dP/du and dP/dv
    // in world units per uv unit, and the Christoffel symbols Gamma^u and Gamma^v (uu, uv, vv).
    // Zeros: none (a triplanar mesh's, a mesh built without uv).
    std::array<float, 3> dpdu{}, dpdv{}, gamma_u{}, gamma_v{};
};

struct Mesh {
    std::string name;
    int material = 0;  // the material table's id; 0 for no relief
    std::vector<Vertex> vertices;
    std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from the front
};

// Tangents and uv densities from the triangles' uv gradients (Lengyel's per-triangle tangent and
// bitangent, area-weighted per vertex): the tangent is dP/du made orthogonal to the vertex normal,
// w = -1 where (N x T) points against dP/dv (mirrored uv), the density sqrt(world area / uv area).
// Vertices on a uv seam are separate vertices, so each side keeps its own frame. A vertex whose
// triangles give no usable dP/du (degenerate uv) gets any unit tangent orthogonal to its normal.
// Ends with derive_curvature and the uv metric (Vertex::dpdu ... gamma_v).
void derive_tangents(Mesh& mesh);
// Each vertex's curvature (Vertex::curvature): core's derive_curvature
// (offsetmap/mesh_curvature.hpp, which says how) over the mesh's vertices in place.
void derive_curvature(Mesh& mesh);
// Each vertex's uv metric: core's derive_uv_metric over the mesh's vertices in place.
void derive_uv_metric(Mesh& mesh);
// A mesh whose material projects the world (triplanar, `world_scale` tiles a world unit): its
// uv density the projection's (1 / world_scale, for the depth offset), no curvature and no
// stretch (the projections' frames are the axes', not the surface's).
void project_from_world(Mesh& mesh, float world_scale);

// A parallelogram from `origin` spanning `edge_u` (uv u from 0 to tiles_u) and `edge_v` (v from 0
// to tiles_v), facing cross(edge_u, edge_v); mirror_u runs u the other way (a mirrored frame).
Mesh make_quad(const std::string& name, int material, Vec3 origin, Vec3 edge_u, Vec3 edge_v,
               float tiles_u, float tiles_v, bool mirror_u = false);
// An axis-aligned box, faces outward, each face its own uv square of `tiles` tiles a side (uv
// seams at every edge); the -x face mirrored.
Mesh make_box(const std::string& name, int material, Vec3 center, Vec3 half, float tiles);
// An upright cylinder with caps: the side's u runs tiles_u times around (a seam at angle 0), its
// v tiles_v times up.
Mesh make_cylinder(const std::string& name, int material, Vec3 base, float radius, float height,
                   int segments, float tiles_u, float tiles_v);
// A uv sphere: u tiles_u times around (a seam at angle 0), v tiles_v times from the north pole to
// the south, as image rows run (so its frames are mirrored, w = -1).
Mesh make_sphere(const std::string& name, int material, Vec3 center, float radius, int segments,
                 int rings, float tiles_u, float tiles_v);
// A torus about the y axis: `radius` from the axis to the tube's centre, `tube` the tube's radius;
// u tiles_u times around the axis (a seam at angle 0), v tiles_v times around the tube from its
// outer equator, upward first.
Mesh make_torus(const std::string& name, int material, Vec3 center, float radius, float tube,
                int segments, int rings, float tiles_u, float tiles_v);

}  // namespace offsetmap::renderer
