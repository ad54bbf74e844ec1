// glTF scenes: data/pillars.gltf (made by data/make_gltf.py) read into world space with its
// node transforms, normals and winding, materials matched by name to the table, the file's camera;
// and bad files refused with one line naming the file and the mesh or material.
#include <fstream>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "support.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/gltf.hpp"
#endif

namespace omtest {
namespace {

#ifdef OFFSETMAP_HAVE_RENDERER
using namespace offsetmap::renderer;

const std::string kData = std::string(OFFSETMAP_SOURCE_DIR) + "/data/";

Scene pillars() {
    const std::string table = kData + "pillars.json";
    return load_gltf_scene(kData + "pillars.gltf", offsetmap::read_material_table(table), table);
}

glm::dvec3 g(const Vec3& v) { return {v[0], v[1], v[2]}; }

const Mesh& mesh(const Scene& s, const std::string& name) {
    for (const Mesh& m : s.meshes)
        if (m.name == name) return m;
    throw std::runtime_error("no mesh " + name);
}

TEST(Gltf, PillarsInWorldSpace) {
    const Scene s = pillars();
    ASSERT_EQ(s.meshes.size(), 6u);  // block is instanced twice
    std::map<std::string, int> ids;
    for (const Mesh& m : s.meshes) ids[m.name] = m.material;
    EXPECT_EQ(ids["floor"], 1);
    EXPECT_EQ(ids["wall"], 2);
    EXPECT_EQ(ids["block"], 2);
    EXPECT_EQ(ids["column"], 3);
    EXPECT_EQ(ids["text box"], 4);

    // Each vertex taken back through its node chain lands on the local shape (float positions:
    // 1e-5 m at a few metres). Block a: turned 30 degrees about y at (-1.6, 0, -1.5), lifted 0.5.
    const glm::dmat4 blocks =
        glm::rotate(glm::translate(glm::dmat4(1), {-1.6, 0, -1.5}), glm::radians(30.0), {0, 1, 0});
    const glm::dmat4 a_inv = glm::inverse(glm::translate(blocks, {0, 0.5, 0}));
    for (const Vertex& v : s.meshes[2].vertices) {
        const glm::dvec3 q = glm::dvec3(a_inv * glm::dvec4(g(v.position), 1));
        EXPECT_NEAR(std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}), 0.5, 1e-5);
    }
    // The column: a unit-radius-0.35 cylinder under scale (1.3, 2.2, 0.8).
    for (const Vertex& v : mesh(s, "column").vertices) {
        const glm::dvec3 q = (g(v.position) - glm::dvec3(1.5, 0, -2.0)) / glm::dvec3(1.3, 2.2, 0.8);
        EXPECT_NEAR(std::hypot(q.x, q.z), 0.35, 1e-5);
        EXPECT_TRUE(q.y > -1e-6 && q.y < 1 + 1e-6);
    }
    // The mirrored box: scale (-1, 1, 1) at (0.6, 0.4, 0.2).
    for (const Vertex& v : mesh(s, "text box").vertices) {
        const glm::dvec3 q = g(v.position) - glm::dvec3(0.6, 0.4, 0.2);
        EXPECT_NEAR(std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)}), 0.4, 1e-5);
    }
}

// Every vertex normal of the flat meshes equals its faces' normal, counter-clockwise from the
// front (a winding left unreversed under the mirror is 180 degrees off); the elliptic column's
// equals the gradient of (x / 1.3)^2 + (z / 0.8)^2 (normals moved by the matrix instead of its
// inverse transpose miss it by up to 27 degrees).
TEST(Gltf, NormalsAndWindingFollowTheSurface) {
    for (const Mesh& m : pillars().meshes) {
        std::vector<glm::dvec3> faces(m.vertices.size(), glm::dvec3(0));
        for (size_t t = 0; t < m.indices.size(); t += 3) {
            const glm::dvec3 p0 = g(m.vertices[m.indices[t]].position);
            const glm::dvec3 c = glm::cross(g(m.vertices[m.indices[t + 1]].position) - p0,
                                            g(m.vertices[m.indices[t + 2]].position) - p0);
            for (int k = 0; k < 3; ++k) faces[m.indices[t + k]] += c;
        }
        if (m.name == "column") {
            for (size_t i = 0; i < m.vertices.size(); ++i) {
                const glm::dvec3 p = g(m.vertices[i].position) - glm::dvec3(1.5, 0, -2.0);
                const glm::dvec3 want = glm::normalize(glm::dvec3(p.x / 1.69, 0, p.z / 0.64));
                EXPECT_NEAR(glm::dot(g(m.vertices[i].normal), want), 1.0, 1e-6);
                EXPECT_GT(glm::dot(glm::normalize(faces[i]), want), 0.99);  // within 8 degrees
            }
            continue;
        }
        for (size_t i = 0; i < m.vertices.size(); ++i) {
            ASSERT_NEAR(glm::length(g(m.vertices[i].normal)), 1.0, 1e-6) << m.name;
            EXPECT_NEAR(glm::dot(g(m.vertices[i].normal), glm::normalize(faces[i])), 1.0, 1e-6)
                << m.name;
        }
    }
}

// glTF's uv run down an image's rows, so upright faces have w = -1; the tangent runs along +u.
TEST(Gltf, FramesFollowTheUv) {
    const Scene s = pillars();
    for (const Vertex& v : mesh(s, "wall").vertices) {
        EXPECT_NEAR(v.tangent[0], 1.0f, 1e-6f);
        EXPECT_EQ(v.tangent[3], -1.0f);
        EXPECT_NEAR(v.uv_density, 1.0f, 1e-5f);  // 8 m over 8 tiles, 3 m over 3
    }
    for (const Vertex& v : mesh(s, "text box").vertices) EXPECT_EQ(v.tangent[3], 1.0f);  // mirrored
}

TEST(Gltf, CameraFromTheFile) {
    const Scene s = pillars();
    EXPECT_NEAR(glm::length(g(s.camera.eye) - glm::dvec3(0.4, 1.9, 4.2)), 0.0, 1e-5);
    const glm::dvec3 want = glm::normalize(glm::dvec3(0.0, 0.6, -1.2) - glm::dvec3(0.4, 1.9, 4.2));
    EXPECT_NEAR(glm::dot(glm::normalize(g(s.camera.target) - g(s.camera.eye)), want), 1.0, 1e-6);
    EXPECT_NEAR(s.camera.fov_y_deg, 55.0f, 1e-4f);
}

// Each bad file: offsetmap::Error whose one line names the file and what is wrong.
TEST(Gltf, BadFilesOneLineEach) {
    nlohmann::json base;
    std::ifstream(kData + "pillars.gltf") >> base;
    const std::string table = kData + "pillars.json";
    const auto specs = offsetmap::read_material_table(table);
    const std::string dir = ::testing::TempDir();
    const auto expect = [&](const std::string& file, const std::string& text, const char* want) {
        const std::string path = dir + "/" + file;
        std::ofstream(path) << text;
        try {
            load_gltf_scene(path, specs, table);
            ADD_FAILURE() << file << " was read";
        } catch (const offsetmap::Error& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find(path + ": " + want), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    };
    const auto edit = [&](const std::function<void(nlohmann::json&)>& f) {
        nlohmann::json j = base;
        f(j);
        return j.dump();
    };
    expect("garbage.gltf", "not json {", "cannot read glTF");
    expect("missing.gltf", "", "cannot read glTF");
    EXPECT_THROW(load_gltf_scene(dir + "/no-such.glb", specs, table), offsetmap::Error);
    auto& floor = base["meshes"][0]["primitives"][0];
    ASSERT_EQ(base["meshes"][0]["name"], "floor");
    expect("no-normals.gltf",
           edit([](auto& j) { j["meshes"][0]["primitives"][0]["attributes"].erase("NORMAL"); }),
           "mesh 'floor' has no normals (NORMAL)");
    expect("no-uv.gltf",
           edit([](auto& j) { j["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_0"); }),
           "mesh 'floor' has no uv (TEXCOORD_0)");
    expect("no-material.gltf",
           edit([](auto& j) { j["meshes"][0]["primitives"][0].erase("material"); }),
           "mesh 'floor' has a primitive without a material");
    expect("no-height-map.gltf", edit([](auto& j) { j["materials"][3]["name"] = "marble"; }),
           "material 'marble' (mesh 'text box') has no height map");
    expect("lines.gltf", edit([](auto& j) { j["meshes"][0]["primitives"][0]["mode"] = 1; }),
           "mesh 'floor' is points or lines");
    const int pos = floor["attributes"]["POSITION"];
    expect("short-buffer.gltf", edit([&](auto& j) { j["accessors"][pos]["count"] = 1000; }),
           "mesh 'floor' runs past the end of its buffer");
    expect("empty.gltf", edit([](auto& j) { j["scenes"][0]["nodes"] = nlohmann::json::array(); }),
           "its scene has no triangles");
}
#endif

}  // namespace
}  // namespace omtest
