// What the renderer draws: meshes with material ids, a camera, a light and the material table
// that gives each id its height map and method.
#pragma once
#include <string>
#include <vector>

#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/renderer/mesh.hpp"

namespace offsetmap::renderer {

struct Camera {
    Vec3 eye = {0.3f, 1.45f, 1.5f};
    Vec3 target = {-0.1f, 0.75f, -2.0f};
    float fov_y_deg = 60.0f;  // vertical field of view
    float near_plane = 0.05f;
    float far_plane = 50.0f;
    // An orthographic view (a directional light's, for a shadow map): eye - target is the
    // direction toward the viewer, ortho_half_height the view's half height in world units (its
    // half width by the aspect); fov_y_deg is unused.
    bool orthographic = false;
    float ortho_half_height = 1.0f;
};

// "ex,ey,ez,tx,ty,tz[,fov]": the eye, the point looked at (up is +y) and the vertical field of
// view in degrees. Throws Error naming --camera.
Camera parse_camera(const std::string& text);

struct Scene {
    std::string name;
    std::vector<Mesh> meshes;
    Camera camera;
    EngineLight light;
    std::string material_table;  // the JSON file the meshes' ids index
};

// A room of brick walls (id 1) on a bumpy floor (id 2) with a box (3; uv seams at its edges, one
// face mirrored), a cylinder (4; a seam down its side) and a sphere (5; a seam and two poles),
// lit by a point light; its table is data_dir/room.json.
Scene builtin_room(const std::string& data_dir);

// A directional light's orthographic view of the whole scene: toward `toward_light` (a world
// direction, any length but zero) from beyond the meshes' bounding sphere, its half height the
// sphere's radius (a map at least as wide as tall sees all of it), near and far planes just
// outside it. Throws Error for a zero or non-finite direction or a scene without
// triangles.
Camera light_camera(const Scene& scene, const Vec3& toward_light);
// A spot light's perspective view (EngineLight::Spot): from its position along its axis, its
// field of view the cone's (twice the outer half-angle, and 1 % more), the near plane a thousandth
// of the distance to the meshes' bounding sphere's far side and the far plane past it. Throws
// Error for a light that is not a spot, a cone or axis the reconstruct pass would refuse, or a
// scene without triangles.
Camera spot_camera(const Scene& scene, const EngineLight& spot);

}  // namespace offsetmap::renderer
