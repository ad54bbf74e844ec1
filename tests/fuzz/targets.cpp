#include "targets.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>

#include "offsetmap/error.hpp"
#include "offsetmap/evaluation.hpp"
#include "offsetmap/material_table.hpp"
#ifdef OFFSETMAP_HAVE_RENDERER
#include "offsetmap/renderer/gltf.hpp"
#endif

namespace omfuzz {
namespace {

using namespace offsetmap;

// A folder of this process's own, made once, for the input files.
const std::string& scratch() {
    static const std::string dir = [] {
        const char* tmp = std::getenv("TMPDIR");
        std::string t = std::string(tmp && *tmp ? tmp : "/tmp") + "/offsetmap-fuzz-XXXXXX";
        if (!mkdtemp(t.data())) std::abort();
        return t;
    }();
    return dir;
}

std::string write_input(const std::uint8_t* data, std::size_t size, const std::string& name) {
    const std::string path = scratch() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) std::abort();
    return path;
}

bool starts_with(const std::uint8_t* data, std::size_t size, const char* magic) {
    const std::size_t n = std::strlen(magic);
    return size >= n && std::memcmp(data, magic, n) == 0;
}

// The extension a user's file with these first bytes would have (OpenImageIO picks its reader by
// extension first).
const char* image_extension(const std::uint8_t* data, std::size_t size) {
    if (starts_with(data, size, "\x89PNG")) return ".png";
    if (starts_with(data, size, "\x76\x2f\x31\x01")) return ".exr";
    if (starts_with(data, size, "II*") || starts_with(data, size, "MM\0*")) return ".tif";
    if (starts_with(data, size, "\xff\xd8")) return ".jpg";
    if (starts_with(data, size, "PF") || starts_with(data, size, "Pf")) return ".pfm";
    if (starts_with(data, size, "P")) return ".pnm";
    if (starts_with(data, size, "#?")) return ".hdr";
    return ".png";
}

// Runs a reader: its Error is a clean outcome, any other exception a finding.
template <typename F>
std::string guarded(F&& read) {
    try {
        return read();
    } catch (const Error&) {
        return "";
    } catch (const std::exception& e) {
        return std::string("an exception other than offsetmap::Error: ") + e.what();
    } catch (...) {
        return "an exception that is not a std::exception";
    }
}

bool finite(float x) { return std::isfinite(x); }

std::string height_map(const std::uint8_t* data, std::size_t size) {
    // The last byte picks the options (a trailing byte is ignored by the image decoders).
    const std::uint8_t opt = size ? data[size - 1] : 0;
    HeightLoadOptions o;
    o.channel = opt & 3;
    o.depth_map = opt & 4;
    o.max_bytes = kReadLimitBytes;
    const std::string path =
        write_input(data, size, std::string("height") + image_extension(data, size));
    return guarded([&]() -> std::string {
        const HeightMap m = load_height_map(path, o);
        if (m.width < 1 || m.height < 1 ||
            m.h.size() != static_cast<std::size_t>(m.width) * m.height)
            return "a height map whose sizes disagree";
        for (float h : m.h)
            if (!(h >= 0.0f && h <= 1.0f)) return "a height outside [0, 1]";
        return "";
    });
}

std::string gbuffer_checks(const GBuffer& g) {
    if (g.width < 1 || g.height < 1) return "an empty G-buffer";
    const std::size_t n = g.pixels();
    if (g.uv.size() != n || g.view.size() != n || (g.has_light() && g.light.size() != n) ||
        (g.has_lod() && g.lod.size() != n) || (g.has_material() && g.material.size() != n))
        return "G-buffer planes whose sizes disagree";
    for (float m : g.material)
        if (!(m >= 0.0f && m <= 65535.0f && m == std::floor(m))) return "a material id not kept";
    return "";
}

std::string gbuffer(const std::uint8_t* data, std::size_t size) {
    const std::string path = write_input(data, size, "gbuffer.exr");
    static const std::shared_ptr<Runtime> runtime = Runtime::create();
    return guarded([&] { return gbuffer_checks(load_gbuffer(path, kReadLimitBytes, runtime)); });
}

std::string engine_gbuffer(const std::uint8_t* data, std::size_t size) {
    const std::string path = write_input(data, size, "engine.exr");
    return guarded([&]() -> std::string {
        const EngineScene e = load_engine_gbuffer(path, kReadLimitBytes);
        const std::size_t n = e.pixels();
        const bool q = e.frame == FrameForm::Quaternion;
        if (e.width < 1 || e.height < 1 || e.depth.size() != n || e.uv.size() != 2 * n ||
            e.normal.size() != 4 * n || e.tangent.size() != (q ? 0 : 4 * n) ||
            !(e.uv_derivatives.empty() || e.uv_derivatives.size() == 4 * n))
            return "engine planes whose sizes disagree";
        for (float x : e.camera.inverse_view_projection)
            if (!finite(x)) return "a non-finite camera matrix kept";
        for (float x : e.camera.eye)
            if (!finite(x)) return "a non-finite eye kept";
        return "";
    });
}

std::string material_table(const std::uint8_t* data, std::size_t size) {
    const std::string path = write_input(data, size, "materials.json");
    return guarded([&]() -> std::string {
        const auto specs = read_material_table(path);
        for (const auto& m : specs) {
            if (m.id < 1 || m.id > kMaxMaterialId) return "an id out of range kept";
            // What the reader says it checked must hold: a later Error here is a finding.
            try {
                validate(m.settings);
                if (m.method != "auto") (void)resolve_params(find_method(m.method), m.params);
            } catch (const Error& e) {
                return std::string("a table entry the reader let through: ") + e.what();
            }
        }
        return "";
    });
}

#ifdef OFFSETMAP_HAVE_RENDERER
std::string gltf(const std::uint8_t* data, std::size_t size) {
    // The table data/pillars.json gives (the names of its materials; no image is read).
    static const std::vector<MaterialSpec> table = [] {
        std::vector<MaterialSpec> t;
        int id = 1;
        for (const char* name : {"floor", "bricks", "sines", "text"}) {
            MaterialSpec m;
            m.id = id++;
            m.name = name;
            t.push_back(m);
        }
        return t;
    }();
    const std::string path =
        write_input(data, size, starts_with(data, size, "glTF") ? "scene.glb" : "scene.gltf");
    return guarded([&]() -> std::string {
        const renderer::Scene s = renderer::load_gltf_scene(path, table, "pillars.json");
        if (s.meshes.empty()) return "a scene without meshes";
        for (const auto& mesh : s.meshes) {
            if (mesh.indices.size() % 3) return "a mesh whose index count is not whole triangles";
            for (auto i : mesh.indices)
                if (i >= mesh.vertices.size()) return "an index past the mesh's vertices";
            for (const auto& v : mesh.vertices) {
                const auto all_finite = [](std::initializer_list<float> xs) {
                    for (float x : xs)
                        if (!finite(x)) return false;
                    return true;
                };
                if (!all_finite({v.position[0], v.position[1], v.position[2]}))
                    return "a non-finite position kept";
                if (!all_finite({v.normal[0], v.normal[1], v.normal[2]}))
                    return "a non-finite normal kept";
                if (!all_finite({v.uv[0], v.uv[1]})) return "a non-finite uv kept";
                if (!all_finite({v.tangent[0], v.tangent[1], v.tangent[2], v.tangent[3]}))
                    return "a non-finite tangent derived";
                if (!(v.uv_density > 0.0f) || !finite(v.uv_density))
                    return "a uv density that is not positive and finite";
            }
        }
        for (float x : {s.camera.eye[0], s.camera.eye[1], s.camera.eye[2], s.camera.fov_y_deg,
                        s.camera.near_plane, s.camera.far_plane})
            if (!finite(x)) return "a non-finite camera kept";
        return "";
    });
}
#endif

}  // namespace

const std::vector<Target>& targets() {
    static const std::vector<Target> all = {
        {"height_map", height_map},
        {"gbuffer", gbuffer},
        {"engine_gbuffer", engine_gbuffer},
        {"material_table", material_table},
#ifdef OFFSETMAP_HAVE_RENDERER
        {"gltf", gltf},
#endif
    };
    return all;
}

}  // namespace omfuzz
