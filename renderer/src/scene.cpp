#include "offsetmap/renderer/scene.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

Camera parse_camera(const std::string& text) {
    std::vector<float> v;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ',')) {
        size_t used = 0;
        float x = 0.0f;
        try {
            x = std::stof(item, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos ||
            !std::isfinite(x))
            throw Error("--camera: '" + item +
                        "' is not a number (expected ex,ey,ez,tx,ty,tz[,fov])");
        v.push_back(x);
    }
    if (v.size() != 6 && v.size() != 7)
        throw Error("--camera needs 6 or 7 numbers (ex,ey,ez,tx,ty,tz[,fov]), got " +
                    std::to_string(v.size()));
    Camera c;
    c.eye = {v[0], v[1], v[2]};
    c.target = {v[3], v[4], v[5]};
    if (v.size() == 7) c.fov_y_deg = v[6];
    const float dx = v[3] - v[0], dy = v[4] - v[1], dz = v[5] - v[2];
    const float len = std::sqrt(dx * dx + dy * dy + dz * dz);
    if (!(len > 1e-6f)) throw Error("--camera: the eye and the target are the same point");
    if (std::abs(dy) > 0.9999f * len)
        throw Error("--camera: the view is straight up or down (up is +y); tilt it a little");
    if (!(c.fov_y_deg >= 1.0f && c.fov_y_deg <= 170.0f))
        throw Error("--camera: the field of view must be in [1, 170] degrees, got " +
                    std::to_string(c.fov_y_deg));
    return c;
}

Scene builtin_room(const std::string& data_dir) {
    Scene s;
    s.name = "room";
    s.material_table = data_dir + "/room.json";
    // The room: x in [-3, 3], z in [-4, 2.5], walls 3 high, no ceiling; one brick tile a metre.
    const float x0 = -3.0f, x1 = 3.0f, z0 = -4.0f, z1 = 2.5f, h = 3.0f;
    s.meshes.push_back(make_quad("floor", 2, {x0, 0, z1}, {x1 - x0, 0, 0}, {0, 0, z0 - z1},
                                 (x1 - x0) / 1.5f, (z1 - z0) / 1.5f));
    s.meshes.push_back(
        make_quad("back wall", 1, {x0, 0, z0}, {x1 - x0, 0, 0}, {0, h, 0}, x1 - x0, h));
    s.meshes.push_back(
        make_quad("left wall", 1, {x0, 0, z1}, {0, 0, z0 - z1}, {0, h, 0}, z1 - z0, h));
    s.meshes.push_back(
        make_quad("right wall", 1, {x1, 0, z0}, {0, 0, z1 - z0}, {0, h, 0}, z1 - z0, h));
    s.meshes.push_back(
        make_quad("front wall", 1, {x1, 0, z1}, {x0 - x1, 0, 0}, {0, h, 0}, x1 - x0, h));
    s.meshes.push_back(make_box("box", 3, {-1.3f, 0.5f, -1.9f}, {0.5f, 0.5f, 0.5f}, 1.0f));
    s.meshes.push_back(
        make_cylinder("cylinder", 4, {1.45f, 0.0f, -2.3f}, 0.45f, 1.4f, 64, 3.0f, 1.5f));
    s.meshes.push_back(make_sphere("sphere", 5, {0.25f, 0.55f, -1.0f}, 0.55f, 64, 32, 4.0f, 2.0f));
    s.light.kind = LightKind::Point;
    s.light.vector = {1.2f, 2.7f, 0.8f};
    return s;
}

namespace {

// The meshes' bounding sphere: the box's centre and its farthest vertex, a margin of 1 % (at least
// a millimetre) around.
void bounding_sphere(const Scene& scene, double c[3], double& r) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (const Mesh& m : scene.meshes)
        for (std::uint32_t i : m.indices)
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], double(m.vertices[i].position[a]));
                hi[a] = std::max(hi[a], double(m.vertices[i].position[a]));
            }
    if (!(lo[0] <= hi[0])) throw Error("scene '" + scene.name + "' has no triangles to light");
    for (int a = 0; a < 3; ++a) c[a] = 0.5 * (lo[a] + hi[a]);
    double r2 = 0.0;
    for (const Mesh& m : scene.meshes)
        for (std::uint32_t i : m.indices) {
            double d2 = 0.0;
            for (int a = 0; a < 3; ++a) d2 += std::pow(m.vertices[i].position[a] - c[a], 2);
            r2 = std::max(r2, d2);
        }
    r = std::sqrt(r2) * 1.01 + 1e-3;
}

}  // namespace

Camera light_camera(const Scene& scene, const Vec3& toward_light) {
    const double lx = toward_light[0], ly = toward_light[1], lz = toward_light[2];
    const double len = std::sqrt(lx * lx + ly * ly + lz * lz);
    if (!(len > 0.0) || !std::isfinite(len))
        throw Error("the light's direction must be finite and not the zero vector");
    double c[3], r;
    bounding_sphere(scene, c, r);
    Camera cam;
    cam.orthographic = true;
    cam.ortho_half_height = static_cast<float>(r);
    cam.target = {float(c[0]), float(c[1]), float(c[2])};
    cam.eye = {float(c[0] + 2.0 * r * lx / len), float(c[1] + 2.0 * r * ly / len),
               float(c[2] + 2.0 * r * lz / len)};
    cam.near_plane = static_cast<float>(r);
    cam.far_plane = static_cast<float>(3.0 * r);
    return cam;
}

Camera spot_camera(const Scene& scene, const EngineLight& spot) {
    if (spot.kind != LightKind::Spot) throw Error("a spot light's view needs a spot light");
    const std::array<float, 3>& p = spot.vector;
    const std::array<float, 3>& a = spot.axis;
    const double len = std::sqrt(double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]);
    if (!(len > 0.0) || !std::isfinite(len) || !std::isfinite(p[0] + p[1] + p[2]))
        throw Error("the spot light's position and axis must be finite, the axis not zero");
    if (!(spot.cone_inner >= 0.0f && spot.cone_inner <= spot.cone_outer &&
          spot.cone_outer < 0.5f * float(M_PI) && spot.cone_outer > 0.0f))
        throw Error("the spot light's cone must have 0 <= inner <= outer < 90 degrees, outer > 0");
    double c[3], r;
    bounding_sphere(scene, c, r);
    const double far =
        std::sqrt(std::pow(p[0] - c[0], 2) + std::pow(p[1] - c[1], 2) + std::pow(p[2] - c[2], 2)) +
        r;
    Camera cam;
    cam.eye = p;
    cam.target = {float(p[0] + a[0] / len), float(p[1] + a[1] / len), float(p[2] + a[2] / len)};
    cam.fov_y_deg = static_cast<float>(std::min(2.02 * spot.cone_outer * 180.0 / M_PI, 179.0));
    cam.near_plane = static_cast<float>(1e-3 * far);
    cam.far_plane = static_cast<float>(far);
    return cam;
}

}  // namespace offsetmap::renderer
