// The material table file: JSON read and checked, images loaded, materials uploaded.
#include "offsetmap/material_table.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "offsetmap/error.hpp"
#include "offsetmap/height_field.hpp"

namespace offsetmap {

namespace {

using nlohmann::json;

const std::set<std::string> kKeys = {"id",
                                     "name",
                                     "height_map",
                                     "depth_map",
                                     "channel",
                                     "scale",
                                     "reference_plane",
                                     "address",
                                     "grazing",
                                     "grazing_min_deg",
                                     "max_offset",
                                     "tile_mask",
                                     "tile_bounds",
                                     "method",
                                     "params",
                                     "error_budget",
                                     "normal_map",
                                     "flip_green",
                                     "albedo",
                                     "projection",
                                     "world_scale",
                                     "sharpness",
                                     "blend_cutoff"};

// One entry's reader: every complaint names the file and the entry.
struct Entry {
    const json& j;
    std::string where;  // "FILE: material 3" or "FILE: entry 2"

    [[noreturn]] void fail(const std::string& what) const { throw Error(where + ": " + what); }
    bool has(const char* key) const { return j.contains(key); }
    double number(const char* key) const {
        const json& v = j.at(key);
        if (!v.is_number()) fail("'" + std::string(key) + "' must be a number, got " + v.dump());
        return v.get<double>();
    }
    bool boolean(const char* key) const {
        const json& v = j.at(key);
        if (!v.is_boolean())
            fail("'" + std::string(key) + "' must be true or false, got " + v.dump());
        return v.get<bool>();
    }
    std::string text(const char* key) const {
        const json& v = j.at(key);
        if (!v.is_string()) fail("'" + std::string(key) + "' must be a string, got " + v.dump());
        return v.get<std::string>();
    }
    std::string choice(const char* key, const std::set<std::string>& allowed) const {
        std::string v = text(key);
        if (!allowed.count(v)) {
            std::string list;
            for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail("'" + std::string(key) + "' must be one of " + list + ", got '" + v + "'");
        }
        return v;
    }
};

std::string resolve(const std::filesystem::path& folder, const std::string& file) {
    std::filesystem::path p(file);
    return (p.is_absolute() ? p : folder / p).lexically_normal().string();
}

MaterialSpec read_entry(const Entry& e, const std::filesystem::path& folder,
                        const PassSettings& defaults) {
    for (const auto& [key, value] : e.j.items())
        if (!kKeys.count(key)) e.fail("unknown key '" + key + "'");
    MaterialSpec m;
    m.settings = defaults;
    if (!e.has("id")) e.fail("has no 'id'");
    const double id = e.number("id");
    if (!(id >= 1 && id <= kMaxMaterialId && id == std::floor(id)))
        e.fail("'id' must be an integer in [1, " + std::to_string(kMaxMaterialId) +
               "] (0 is the pixels without relief), got " + e.j.at("id").dump());
    m.id = static_cast<int>(id);
    if (!e.has("height_map")) e.fail("has no 'height_map'");
    m.height_map = resolve(folder, e.text("height_map"));
    m.name =
        e.has("name") ? e.text("name") : std::filesystem::path(m.height_map).filename().string();
    if (e.has("depth_map")) m.load.depth_map = e.boolean("depth_map");
    if (e.has("channel")) {
        const double c = e.number("channel");
        if (!(c >= 0 && c <= 1023 && c == std::floor(c))) e.fail("'channel' must be in [0, 1023]");
        m.load.channel = static_cast<int>(c);
    }
    PassSettings& s = m.settings;
    if (e.has("scale")) s.scale = static_cast<float>(e.number("scale"));
    if (e.has("reference_plane"))
        s.reference_plane = static_cast<float>(e.number("reference_plane"));
    if (e.has("grazing_min_deg"))
        s.min_elevation_deg = static_cast<float>(e.number("grazing_min_deg"));
    if (e.has("max_offset")) s.max_offset_texels = static_cast<float>(e.number("max_offset"));
    if (e.has("tile_mask")) s.out_of_tile_mask = e.boolean("tile_mask");
    if (e.has("tile_bounds")) {
        // [u_min, v_min, u_max, v_max], null for an open side; it turns the mask on unless the
        // entry says "tile_mask": false.
        const json& b = e.j.at("tile_bounds");
        if (!b.is_array() || b.size() != 4)
            e.fail("'tile_bounds' must be [u_min, v_min, u_max, v_max] (null: open), got " +
                   b.dump());
        for (size_t k = 0; k < 4; ++k) {
            if (b[k].is_null()) {
                s.tile_bounds[k] = (k < 2 ? -1.0f : 1.0f) * INFINITY;
            } else if (b[k].is_number()) {
                s.tile_bounds[k] = static_cast<float>(b[k].get<double>());
            } else {
                e.fail("'tile_bounds' holds numbers or null, got " + b[k].dump());
            }
        }
        if (!e.has("tile_mask")) s.out_of_tile_mask = true;
    }
    if (e.has("address"))
        s.address = e.choice("address", {"wrap", "clamp"}) == "clamp" ? AddressMode::Clamp
                                                                      : AddressMode::Wrap;
    if (e.has("grazing")) {
        const std::string g = e.choice("grazing", {"clamp", "limit", "cap"});
        s.grazing = g == "limit" ? GrazingPolicy::Limit
                    : g == "cap" ? GrazingPolicy::Cap
                                 : GrazingPolicy::Clamp;
    }
    s.lod.enabled = false;  // the frame has no LOD system
    try {
        validate(s);
    } catch (const Error& x) {
        e.fail(x.what());
    }
    if (e.has("method")) m.method = e.text("method");
    if (e.has("params")) {
        const json& p = e.j.at("params");
        if (!p.is_object()) e.fail("'params' must be an object of name: value, got " + p.dump());
        for (const auto& [key, value] : p.items())
            m.params[key] = value.is_string() ? value.get<std::string>() : value.dump();
    }
    if (m.method == "auto") {
        if (!m.params.empty()) e.fail("'params' do not apply to method auto (it picks them)");
        if (!e.has("error_budget"))
            e.fail("method auto needs an 'error_budget', e.g. {\"p95_texels\": 0.5}");
        const json& b = e.j.at("error_budget");
        if (!b.is_object() || b.size() != 1 ||
            !(b.contains("p95_texels") || b.contains("mean_texels")))
            e.fail("'error_budget' must be {\"p95_texels\": x} or {\"mean_texels\": x}, got " +
                   b.dump());
        const bool p95 = b.contains("p95_texels");
        const json& v = b.begin().value();
        if (!v.is_number() || !(v.get<double>() > 0.0 && v.get<double>() <= 64.0))
            e.fail(std::string("error budget ") + (p95 ? "p95_texels" : "mean_texels") +
                   " must be in (0, 64] texels, got " + v.dump());
        m.budget.statistic = p95 ? ErrorBudget::Statistic::P95 : ErrorBudget::Statistic::Mean;
        m.budget.texels = v.get<double>();
    } else {
        if (e.has("error_budget")) e.fail("'error_budget' applies to method auto only");
        try {
            resolve_params(find_method(m.method), m.params);
        } catch (const Error& x) {
            e.fail(x.what());
        }
    }
    if (e.has("normal_map")) m.normal_map = resolve(folder, e.text("normal_map"));
    if (e.has("flip_green")) m.flip_green = e.boolean("flip_green");
    if (e.has("albedo")) m.albedo = resolve(folder, e.text("albedo"));
    Triplanar& t = m.triplanar;
    if (e.has("projection")) t.enabled = e.choice("projection", {"uv", "triplanar"}) == "triplanar";
    for (const char* key : {"world_scale", "sharpness", "blend_cutoff"})
        if (e.has(key) && !t.enabled)
            e.fail("'" + std::string(key) + "' applies to \"projection\": \"triplanar\" only");
    if (e.has("world_scale")) t.world_scale = static_cast<float>(e.number("world_scale"));
    if (e.has("sharpness")) t.sharpness = static_cast<float>(e.number("sharpness"));
    if (e.has("blend_cutoff")) t.cutoff = static_cast<float>(e.number("blend_cutoff"));
    try {
        validate(t, "the triplanar projection");
        if (t.enabled && s.address != AddressMode::Wrap)
            throw Error(
                "a triplanar projection tiles the world, so it needs \"address\": \"wrap\"");
    } catch (const Error& x) {
        e.fail(x.what());
    }
    return m;
}

}  // namespace

std::vector<MaterialSpec> read_material_table(const std::string& path,
                                              const PassSettings& defaults) {
    std::ifstream in(path);
    if (!in) throw Error("cannot read the material table '" + path + "'");
    json j;
    try {
        j = json::parse(in);
    } catch (const json::exception& e) {  // syntax, and numbers past double's range
        throw Error(path + ": not valid JSON (" + e.what() + ")");
    }
    if (!j.is_array() || j.empty())
        throw Error(path + ": a material table is a non-empty list of objects, one per material");
    if (j.size() > OM_MAX_MATERIALS)
        throw Error(path + ": " + std::to_string(j.size()) + " materials; a frame takes at most " +
                    std::to_string(OM_MAX_MATERIALS));
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    std::vector<MaterialSpec> out;
    for (size_t k = 0; k < j.size(); ++k) {
        std::string where = path + ": entry " + std::to_string(k + 1);
        if (!j[k].is_object()) throw Error(where + " is not an object");
        if (j[k].contains("id") && j[k]["id"].is_number_integer())
            where = path + ": material " + j[k]["id"].dump();
        out.push_back(read_entry(Entry{j[k], where}, folder, defaults));
        for (size_t r = 0; r < k; ++r)
            if (out[r].id == out[k].id)
                throw Error(path + ": material id " + std::to_string(out[k].id) +
                            " appears twice (entries " + std::to_string(r + 1) + " and " +
                            std::to_string(k + 1) + ")");
    }
    return out;
}

std::vector<LoadedMaterial> load_materials(const std::vector<MaterialSpec>& specs) {
    std::vector<LoadedMaterial> out;
    for (const MaterialSpec& s : specs) {
        LoadedMaterial m;
        m.spec = s;
        try {
            m.map = load_height_map(s.height_map, s.load);
            if (!s.normal_map.empty()) m.normals = load_normal_map(s.normal_map, s.flip_green);
            if (!s.albedo.empty()) m.albedo = load_image4(s.albedo);
        } catch (const Error& e) {
            throw Error("material " + std::to_string(s.id) + ": " + e.what());
        }
        out.push_back(std::move(m));
    }
    return out;
}

std::vector<FrameMaterial> upload_materials(Runtime& rt, const std::vector<LoadedMaterial>& in,
                                            const std::vector<MethodParams>& methods) {
    if (methods.size() != in.size())
        throw Error("upload_materials: one method per material is needed");
    std::vector<FrameMaterial> out;
    for (size_t k = 0; k < in.size(); ++k) {
        const LoadedMaterial& m = in[k];
        FrameMaterial f;
        f.id = m.spec.id;
        f.name = m.spec.name;
        f.settings = m.spec.settings;
        f.field = upload(rt, m.map, f.settings, m.normals.width ? &m.normals : nullptr);
        f.params = methods[k];
        if (m.albedo.width) f.albedo = upload(rt, m.albedo);
        f.triplanar = m.spec.triplanar;
        out.push_back(std::move(f));
    }
    return out;
}

void lay_out_materials(GBuffer& gb, const std::vector<int>& ids) {
    if (ids.empty()) throw Error("no material ids to lay out");
    gb.material.assign(gb.pixels(), 0.0f);
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const float u = gb.uv[k].s[0], v = gb.uv[k].s[1];
        if (!std::isfinite(u) || !std::isfinite(v)) continue;
        const auto tu = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(u)));
        const auto tv = static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v)));
        const std::uint64_t h = (tu * 0x9E3779B97F4A7C15ull) ^ (tv * 0xC2B2AE3D27D4EB4Full);
        gb.material[k] = static_cast<float>(ids[(h >> 32) % ids.size()]);
    }
}

}  // namespace offsetmap
