#include "offsetmap/renderer/gltf.hpp"

// The same configuration as tinygltf_impl.cpp, which compiles the implementation.
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>

#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

namespace {

// The loader reads geometry only: images are left undecoded (and unread when missing).
bool skip_image(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                const unsigned char*, int, void*) {
    return true;
}

// ".glb" for "scene.GLB": the file's extension in lower case.
std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    return ext;
}

std::string one_line(std::string s) {
    std::replace(s.begin(), s.end(), '\n', ' ');
    while (!s.empty() && (s.back() == ' ' || s.back() == '\r')) s.pop_back();
    return s;
}

class Loader {
  public:
    Loader(const std::string& path, const std::vector<MaterialSpec>& table,
           const std::string& table_path)
        : path_(path), table_(table), table_path_(table_path) {}

    Scene load() {
        read();
        Scene s;
        s.name = std::filesystem::path(path_).stem().string();
        s.material_table = table_path_;
        if (model_.scenes.empty() && model_.nodes.empty()) fail("has no scene");
        std::vector<int> roots;
        if (!model_.scenes.empty()) {
            const int k = model_.defaultScene >= 0 ? model_.defaultScene : 0;
            if (k >= int(model_.scenes.size())) fail("its default scene does not exist");
            roots = model_.scenes[k].nodes;
        } else {
            for (int n = 0; n < int(model_.nodes.size()); ++n) roots.push_back(n);
        }
        for (int r : roots) visit(r, glm::dmat4(1.0), s, 0);
        if (s.meshes.empty()) fail("its scene has no triangles");
        for (Mesh& m : s.meshes) {
            derive_tangents(m);
            if (const Triplanar* t = triplanar_of(m.material))
                project_from_world(m, t->world_scale);
        }
        place_view(s);
        return s;
    }

  private:
    [[noreturn]] void fail(const std::string& why) const { throw Error(path_ + ": " + why); }

    void read() {
        tinygltf::TinyGLTF loader;
        loader.SetImageLoader(skip_image, nullptr);
        std::string err, warn;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path_, ec))
            throw Error(path_ + ": cannot read glTF: no such file");
        const bool ok = lower_extension(path_) == ".glb"
                            ? loader.LoadBinaryFromFile(&model_, &err, &warn, path_)
                            : loader.LoadASCIIFromFile(&model_, &err, &warn, path_);
        if (!ok)
            throw Error(path_ + ": cannot read glTF: " +
                        one_line(err.empty() ? "tinygltf gave no reason" : err));
    }

    void visit(int node_index, const glm::dmat4& parent, Scene& s, int depth) {
        if (node_index < 0 || node_index >= int(model_.nodes.size()))
            fail("a scene names node " + std::to_string(node_index) + ", which does not exist");
        if (depth > 64) fail("its node hierarchy is deeper than 64 (a cycle?)");
        const tinygltf::Node& node = model_.nodes[node_index];
        const glm::dmat4 world = parent * local(node);
        if (node.mesh >= 0) add_mesh(node, world, s);
        if (node.camera >= 0 && !camera_found_) take_camera(node, world, s);
        for (int c : node.children) visit(c, world, s, depth + 1);
    }

    static glm::dmat4 local(const tinygltf::Node& node) {
        if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major
        glm::dmat4 m(1.0);
        if (node.translation.size() == 3)
            m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
        if (node.rotation.size() == 4) {
            const glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1],
                               node.rotation[2]);  // glTF stores x, y, z, w
            m = m * glm::dmat4(glm::mat3_cast(glm::normalize(q)));
        }
        if (node.scale.size() == 3)
            m = m * glm::dmat4(glm::dmat3(glm::dvec3(node.scale[0], 0, 0),
                                          glm::dvec3(0, node.scale[1], 0),
                                          glm::dvec3(0, 0, node.scale[2])));
        return m;
    }

    // An accessor as rows of `width` floats (float, or normalized integer components).
    std::vector<float> floats(int index, int width, const std::string& what) const {
        const tinygltf::Accessor& a = accessor(index, what);
        if (tinygltf::GetNumComponentsInType(a.type) != width)
            fail(what + " has " + std::to_string(tinygltf::GetNumComponentsInType(a.type)) +
                 " components, expected " + std::to_string(width));
        std::vector<float> out(a.count * width);
        const int type = a.componentType;
        if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !a.normalized)
            fail(what + " is neither float nor normalized integers");
        for_each_element(a, what, [&](size_t i, const unsigned char* p) {
            for (int c = 0; c < width; ++c) out[i * width + c] = component(p, type, c);
        });
        return out;
    }

    std::vector<std::uint32_t> indices(int index, const std::string& what) const {
        const tinygltf::Accessor& a = accessor(index, what);
        const int type = a.componentType;
        if (a.type != TINYGLTF_TYPE_SCALAR || (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                               type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                               type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
            fail(what + " are not unsigned integer scalars");
        std::vector<std::uint32_t> out(a.count);
        for_each_element(a, what, [&](size_t i, const unsigned char* p) {
            if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) out[i] = p[0];
            if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
                std::uint16_t v;
                std::memcpy(&v, p, 2);
                out[i] = v;
            }
            if (type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) std::memcpy(&out[i], p, 4);
        });
        return out;
    }

    const tinygltf::Accessor& accessor(int index, const std::string& what) const {
        if (index < 0 || index >= int(model_.accessors.size()))
            fail(what + " names accessor " + std::to_string(index) + ", which does not exist");
        const tinygltf::Accessor& a = model_.accessors[index];
        if (a.sparse.isSparse) fail(what + " is a sparse accessor, which frame does not read");
        return a;
    }

    // Visits each element's bytes after checking that every one lies inside its buffer.
    template <typename F>
    void for_each_element(const tinygltf::Accessor& a, const std::string& what, F f) const {
        if (a.bufferView < 0 || a.bufferView >= int(model_.bufferViews.size()))
            fail(what + " has no buffer view");
        const tinygltf::BufferView& v = model_.bufferViews[a.bufferView];
        if (v.buffer < 0 || v.buffer >= int(model_.buffers.size()))
            fail(what + "'s buffer view names no buffer");
        const std::vector<unsigned char>& data = model_.buffers[v.buffer].data;
        const int elem = tinygltf::GetComponentSizeInBytes(a.componentType) *
                         tinygltf::GetNumComponentsInType(a.type);
        if (elem <= 0) fail(what + " has an unknown component type");
        const size_t stride = v.byteStride ? v.byteStride : size_t(elem);
        const size_t begin = v.byteOffset + a.byteOffset;
        if (a.count > 0 && (begin + (a.count - 1) * stride + elem > v.byteOffset + v.byteLength ||
                            v.byteOffset + v.byteLength > data.size()))
            fail(what + " runs past the end of its buffer");
        for (size_t i = 0; i < a.count; ++i) f(i, data.data() + begin + i * stride);
    }

    static float component(const unsigned char* p, int type, int c) {
        switch (type) {
            case TINYGLTF_COMPONENT_TYPE_FLOAT: {
                float v;
                std::memcpy(&v, p + 4 * c, 4);
                return v;
            }
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
                return p[c] / 255.0f;
            case TINYGLTF_COMPONENT_TYPE_BYTE:
                return std::max(float(static_cast<signed char>(p[c])) / 127.0f, -1.0f);
            case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
                std::uint16_t v;
                std::memcpy(&v, p + 2 * c, 2);
                return v / 65535.0f;
            }
            case TINYGLTF_COMPONENT_TYPE_SHORT: {
                std::int16_t v;
                std::memcpy(&v, p + 2 * c, 2);
                return std::max(float(v) / 32767.0f, -1.0f);
            }
            default:
                return std::numeric_limits<float>::quiet_NaN();
        }
    }

    const Triplanar* triplanar_of(int id) const {
        for (const MaterialSpec& spec : table_)
            if (spec.id == id && spec.triplanar.enabled) return &spec.triplanar;
        return nullptr;
    }

    int material_id(const std::string& mesh_name, int material) const {
        if (material < 0)
            fail("mesh '" + mesh_name +
                 "' has a primitive without a material, so no height map names it");
        if (material >= int(model_.materials.size()))
            fail("mesh '" + mesh_name + "' names material " + std::to_string(material) +
                 ", which does not exist");
        const std::string& name = model_.materials[material].name;
        for (const MaterialSpec& spec : table_)
            if (!name.empty() && spec.name == name) return spec.id;
        fail("material '" + (name.empty() ? "#" + std::to_string(material) : name) + "' (mesh '" +
             mesh_name + "') has no height map: " + table_path_ + " has no entry named '" + name +
             "'");
    }

    void add_mesh(const tinygltf::Node& node, const glm::dmat4& world, Scene& s) {
        if (node.mesh >= int(model_.meshes.size()))
            fail("node '" + node.name + "' names mesh " + std::to_string(node.mesh) +
                 ", which does not exist");
        const tinygltf::Mesh& gm = model_.meshes[node.mesh];
        const std::string name = gm.name.empty() ? "#" + std::to_string(node.mesh) : gm.name;
        const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(glm::dmat3(world)));
        const bool mirrored = glm::determinant(glm::dmat3(world)) < 0.0;
        for (size_t p = 0; p < gm.primitives.size(); ++p) {
            const tinygltf::Primitive& prim = gm.primitives[p];
            const std::string what =
                "mesh '" + name + "'" +
                (gm.primitives.size() > 1 ? " (primitive " + std::to_string(p) + ")" : "");
            if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
                prim.mode != TINYGLTF_MODE_TRIANGLE_FAN)
                fail(what + " is points or lines; frame draws triangles");
            const auto attr = [&](const char* key, const char* plain) {
                const auto it = prim.attributes.find(key);
                if (it == prim.attributes.end()) fail(what + " has no " + plain + " (" + key + ")");
                return it->second;
            };
            const std::vector<float> pos = floats(attr("POSITION", "positions"), 3, what);
            const std::vector<float> nrm = floats(attr("NORMAL", "normals"), 3, what);
            Mesh m;
            m.name = name + (gm.primitives.size() > 1 ? "#" + std::to_string(p) : "");
            m.material = material_id(name, prim.material);
            // A triplanar material projects the world: its meshes need no uv, and any they have
            // is not read.
            const bool projected = triplanar_of(m.material) != nullptr;
            if (!projected && !prim.attributes.count("TEXCOORD_0"))
                fail(what +
                     " has no uv (TEXCOORD_0); a mesh without uv needs a material with "
                     "\"projection\": \"triplanar\" in " +
                     table_path_);
            const size_t count = pos.size() / 3;
            const std::vector<float> uv = projected ? std::vector<float>(2 * count, 0.0f)
                                                    : floats(attr("TEXCOORD_0", "uv"), 2, what);
            if (nrm.size() / 3 != count || uv.size() / 2 != count)
                fail(what + ": its attributes have different vertex counts");
            for (size_t i = 0; i < count; ++i) {
                Vertex v;
                const glm::dvec4 wp =
                    world * glm::dvec4(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2], 1.0);
                glm::dvec3 wn =
                    normal_matrix * glm::dvec3(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
                const double len = glm::length(wn);
                wn /= len;
                v.position = {float(wp.x), float(wp.y), float(wp.z)};
                v.normal = {float(wn.x), float(wn.y), float(wn.z)};
                v.uv = {uv[2 * i], uv[2 * i + 1]};
                // In float, as the renderer keeps them: a world position past float's range is
                // as unusable as a NaN.
                if (!(len > 1e-12) || !std::isfinite(v.position[0] + v.position[1] + v.position[2]))
                    fail(what + " has a zero or non-finite normal or position at vertex " +
                         std::to_string(i));
                if (!std::isfinite(v.uv[0] + v.uv[1]))
                    fail(what + " has a non-finite uv at vertex " + std::to_string(i));
                m.vertices.push_back(v);
                extend(wp);
            }
            std::vector<std::uint32_t> idx;
            if (prim.indices >= 0) {
                idx = indices(prim.indices, what + "'s indices");
            } else {
                idx.resize(count);
                for (size_t i = 0; i < count; ++i) idx[i] = std::uint32_t(i);
            }
            for (std::uint32_t k : idx)
                if (k >= count)
                    fail(what + " has index " + std::to_string(k) + " past its " +
                         std::to_string(count) + " vertices");
            m.indices = triangles(idx, prim.mode, mirrored);
            if (!m.indices.empty()) s.meshes.push_back(std::move(m));
        }
    }

    // Triangle lists, counter-clockwise from the front (a mirroring transform reverses winding).
    static std::vector<std::uint32_t> triangles(const std::vector<std::uint32_t>& idx, int mode,
                                                bool mirrored) {
        std::vector<std::uint32_t> out;
        const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            if (mirrored) std::swap(b, c);
            out.insert(out.end(), {a, b, c});
        };
        if (mode == TINYGLTF_MODE_TRIANGLES)
            for (size_t t = 0; t + 2 < idx.size(); t += 3) add(idx[t], idx[t + 1], idx[t + 2]);
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
            for (size_t t = 0; t + 2 < idx.size(); ++t)
                t % 2 ? add(idx[t + 1], idx[t], idx[t + 2]) : add(idx[t], idx[t + 1], idx[t + 2]);
        if (mode == TINYGLTF_MODE_TRIANGLE_FAN)
            for (size_t t = 1; t + 1 < idx.size(); ++t) add(idx[0], idx[t], idx[t + 1]);
        return out;
    }

    void extend(const glm::dvec4& p) {
        lo_ = glm::min(lo_, glm::dvec3(p));
        hi_ = glm::max(hi_, glm::dvec3(p));
    }

    void take_camera(const tinygltf::Node& node, const glm::dmat4& world, Scene& s) {
        if (node.camera >= int(model_.cameras.size())) return;
        const tinygltf::Camera& c = model_.cameras[node.camera];
        if (c.type != "perspective") return;
        const glm::dvec3 eye(world[3]);
        const glm::dvec3 forward = glm::normalize(-glm::dvec3(world[2]));
        glm::dvec3 target = eye + forward;
        // The renderer's view keeps +y up; a camera looking straight down is tipped a hair
        // toward its own up so the view stays defined.
        if (std::abs(forward.y) > 0.9999) target += 1e-3 * glm::normalize(glm::dvec3(world[1]));
        s.camera.eye = {float(eye.x), float(eye.y), float(eye.z)};
        s.camera.target = {float(target.x), float(target.y), float(target.z)};
        s.camera.fov_y_deg = float(glm::degrees(c.perspective.yfov));
        if (c.perspective.znear > 0) s.camera.near_plane = float(c.perspective.znear);
        if (c.perspective.zfar > c.perspective.znear)
            s.camera.far_plane = float(c.perspective.zfar);
        camera_found_ = true;
    }

    // Without a camera in the file: the bounds' centre seen from the front, above and to the right,
    // far enough that the bounding sphere fills the view; the light above the bounds.
    void place_view(Scene& s) const {
        const glm::dvec3 centre = 0.5 * (lo_ + hi_);
        const double radius = std::max(0.5 * glm::length(hi_ - lo_), 1e-3);
        if (!camera_found_) {
            const double fov = 50.0;
            const double dist = radius / std::sin(glm::radians(fov / 2)) * 1.05;
            const glm::dvec3 eye = centre + dist * glm::normalize(glm::dvec3(0.35, 0.45, 1.0));
            s.camera.eye = {float(eye.x), float(eye.y), float(eye.z)};
            s.camera.target = {float(centre.x), float(centre.y), float(centre.z)};
            s.camera.fov_y_deg = float(fov);
            s.camera.near_plane = float(std::max(dist - radius, dist * 1e-3) * 0.5);
            s.camera.far_plane = float(dist + 2.0 * radius);
        }
        s.light.kind = LightKind::Point;
        const glm::dvec3 light = centre + glm::dvec3(0.3, 1.2, 0.4) * radius;
        s.light.vector = {float(light.x), float(light.y), float(light.z)};
    }

    std::string path_;
    const std::vector<MaterialSpec>& table_;
    std::string table_path_;
    tinygltf::Model model_;
    bool camera_found_ = false;
    glm::dvec3 lo_{std::numeric_limits<double>::max()};
    glm::dvec3 hi_{std::numeric_limits<double>::lowest()};
};

}  // namespace

bool is_gltf_path(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".gltf" || ext == ".glb";
}

Scene load_gltf_scene(const std::string& path, const std::vector<MaterialSpec>& table,
                      const std::string& table_path) {
    return Loader(path, table, table_path).load();
}

}  // namespace offsetmap::renderer
