#include "offsetmap/registry.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "offsetmap/error.hpp"
#include "om_shared.h"
#include "precompute/precompute.hpp"

namespace offsetmap {

namespace {

// Fetch caps from the loop counts (kernels/methods/*.cl): what each pixel costs at most.
double cap_one(const MethodParams&) { return 1; }
double cap_zero(const MethodParams&) { return 0; }
double cap_cells(const MethodParams&) { return -1; }  // bounded by the cells the ray crosses
double cap_iterative(const MethodParams& p) { return p["iterations"]; }
double cap_steep(const MethodParams& p) { return p["layers"] + 1; }
double cap_relief(const MethodParams& p) { return p["linear"] + 1 + p["binary"]; }
double cap_pom(const MethodParams& p) { return std::max(p["min_samples"], p["max_samples"]) + 1; }
double cap_secant(const MethodParams& p) { return cap_pom(p) + p["refine"]; }
// With cells, a walk bounded by the cells the ray crosses follows the steps.
double cap_sphere(const MethodParams& p) { return p["cells"] > 0 ? -1 : p["steps"]; }

}  // namespace

const std::vector<MethodInfo>& methods() {
    static const std::vector<MethodInfo> table = {
        {"none",
         "none.cl",
         "normal mapping only: uv' = uv",
         "Blinn 1978, bump mapping",
         {},
         nullptr,
         {},
         cap_zero},
        {"parallax",
         "parallax.cl",
         "one height fetch, flat-surface assumption: uv' = uv - (r - H(uv)) s V.xy / V.z",
         "Kaneko et al. 2001, detailed shape representation with parallax mapping",
         {},
         nullptr,
         {},
         cap_one},
        {"parallax-limited",
         "parallax_limited.cl",
         "parallax with offset limiting: uv' = uv - (r - H(uv)) s V.xy (no 1/V.z)",
         "Welsh 2004, parallax mapping with offset limiting",
         {},
         nullptr,
         {},
         cap_one},
        {"parallax-slope",
         "parallax_slope.cl",
         "one slope step: the ray meets the relief's tangent plane at uv (1 fetch; the bilinear "
         "patch's own gradient gives the normal)",
         "Premecz 2006, iterative parallax mapping with slope information, section 3; slope notes",
         {{"safe", 0, 0, 1, true,
           "0: t = s(r-H) / (n.V), n = (-s grad H, 1), n.V >= 1e-4, t clamped to the slab; 1: "
           "Premecz safe form t = s(r-H) N.z"}},
         nullptr,
         {{{"safe", "0"}}, {{"safe", "1"}}},
         cap_one},
        {"parallax-iterative",
         "parallax_iterative.cl",
         "the slope step repeated from the previous estimate (1 fetch per iteration)",
         "Premecz 2006, section 3",
         {{"iterations", 4, 1, 64, true, "slope steps k (k = 1 is parallax-slope)"},
          {"safe", 0, 0, 1, true, "as parallax-slope"}},
         nullptr,
         {{{"iterations", "2"}},
          {{"iterations", "4"}},
          {{"iterations", "8"}},
          {{"iterations", "16"}}},
         cap_iterative},
        {"steep",
         "steep.cl",
         "n equal depth layers, first sample at or below the relief (reads one level of the "
         "height pyramid)",
         "McGuire & McGuire 2005, steep parallax mapping",
         {{"layers", 16, 1, 256, true, "depth layers n (at most n + 1 fetches)"},
          {"lod", 0, 0, 15, true, "mip level held fixed during the march"}},
         nullptr,
         {{{"layers", "4"}},
          {{"layers", "8"}},
          {{"layers", "16"}},
          {{"layers", "32"}},
          {{"layers", "64"}},
          {{"layers", "128"}}},
         cap_steep},
        {"relief",
         "relief.cl",
         "linear search, then binary search",
         "Policarpo, Oliveira & Comba 2005, relief mapping; Premecz 2006 section 2.3",
         {{"linear", 16, 1, 256, true, "linear search steps n"},
          {"binary", 6, 0, 32, true, "binary search steps m"}},
         nullptr,
         {{{"linear", "4"}, {"binary", "2"}},
          {{"linear", "8"}, {"binary", "4"}},
          {{"linear", "16"}, {"binary", "6"}},
          {{"linear", "32"}, {"binary", "8"}},
          {{"linear", "64"}, {"binary", "10"}}},
         cap_relief},
        {"pom",
         "pom.cl",
         "linear search with lerp(n_max, n_min, V.z) steps, then the ray cut with the segment "
         "between the last two samples",
         "Tatarchuk 2006, practical parallax occlusion mapping",
         {{"min_samples", 8, 1, 256, true, "steps when looking straight down", "max_samples"},
          {"max_samples", 32, 1, 256, true, "steps at grazing views"}},
         nullptr,
         {{{"min_samples", "4"}, {"max_samples", "16"}},
          {{"min_samples", "8"}, {"max_samples", "32"}},
          {{"min_samples", "16"}, {"max_samples", "64"}},
          {{"min_samples", "32"}, {"max_samples", "128"}}},
         cap_pom},
        {"sphere",
         "sphere.cl",
         "sphere tracing through a conservative 3D distance map from the top plane",
         "Donnelly 2005, per-pixel displacement mapping with distance functions (GPU Gems 2 "
         "ch. 8); Premecz 2006 section 2.4",
         {{"res", 256, 8, 1024, true, "distance map voxels per side of the tile"},
          {"layers", 32, 2, 128, true, "distance map voxels through the relief slab"},
          {"steps", 64, 1, 256, true, "sphere-tracing steps (one distance fetch each)"},
          {"cells", 1, 0, 1, true,
           "1: near the proxy, and once out of steps, solve the bilinear cells (one fetch each; "
           "the exact hit); 0: stop at the proxy (Donnelly)"}},
         &kDistanceMap,
         {{{"res", "64"}, {"layers", "16"}, {"steps", "16"}, {"cells", "0"}},
          {{"res", "128"}, {"layers", "16"}, {"steps", "32"}, {"cells", "0"}},
          {{"res", "256"}, {"layers", "32"}, {"steps", "64"}, {"cells", "0"}},
          {{"res", "512"}, {"layers", "64"}, {"steps", "128"}, {"cells", "0"}},
          {{"res", "256"}, {"layers", "32"}, {"steps", "64"}}},
         cap_sphere,
         true},
        {"secant",
         "secant.cl",
         "pom's linear search, then secant refinement (regula falsi, Illinois) to a tolerance",
         "Risser, Shah & Pattanaik 2007, faster relief mapping using the secant method",
         {{"min_samples", 8, 1, 256, true, "linear steps when looking straight down",
           "max_samples"},
          {"max_samples", 32, 1, 256, true, "linear steps at grazing views"},
          {"refine", 4, 0, 32, true, "secant iterations at most (0: pom)"},
          {"tol", 1e-4f, 0.0f, 0.1f, false, "stop when the height gap is below this (H units)"}},
         nullptr,
         {{{"min_samples", "1"}, {"max_samples", "4"}, {"refine", "1"}},
          {{"min_samples", "1"}, {"max_samples", "5"}, {"refine", "1"}},
          {{"min_samples", "2"}, {"max_samples", "4"}, {"refine", "1"}},
          {{"min_samples", "2"}, {"max_samples", "8"}, {"refine", "2"}},
          {{"min_samples", "4"}, {"max_samples", "16"}, {"refine", "2"}},
          {{"min_samples", "8"}, {"max_samples", "32"}, {"refine", "3"}},
          {{"min_samples", "16"}, {"max_samples", "64"}, {"refine", "4"}},
          {{"min_samples", "32"}, {"max_samples", "128"}, {"refine", "6"}}},
         cap_secant},
        {"maxmip",
         "maxmip.cl",
         "exact first hit by a hierarchical walk of a maximum-height pyramid (O(log n) block "
         "tests)",
         "Tevs, Ihrke & Seidel 2008, maximum mipmaps for height field rendering",
         {{"max_level", OM_MAXMIP_MAX_LEVEL, 0, OM_MAXMIP_MAX_LEVEL, true,
           "highest pyramid level used (0: plain DDA, as exact)"}},
         &kMaxPyramid,
         {{{"max_level", "0"}}, {{"max_level", "3"}}, {{"max_level", "15"}}},
         cap_cells},
        {"cone",
         "cone.cl",
         "exact first hit by cone steps over a cell-conservative cone map, min step one cell, "
         "exact patch solve where the ray dips below a cell's maximum",
         "Dummer 2006 and Policarpo & Oliveira 2007 (GPU Gems 3 ch. 18), cone step mapping; "
         "Bán, Valasek et al. 2024, robust cone step mapping",
         {{"max_ratio", 64, 1, 1024, true,
           "widest cone stored, texels per unit height: bounds the build's search radius"}},
         &kConeMap,
         {{{"max_ratio", "4"}},
          {{"max_ratio", "16"}},
          {{"max_ratio", "64"}},
          {{"max_ratio", "256"}}},
         cap_cells,
         true},
        {"exact",
         "exact.cl",
         "first hit with the bilinear height field: DDA over texel cells, quadratic per patch",
         "ground truth of this project (ray / bilinear patch)",
         {},
         nullptr,
         {},
         cap_cells,
         true},
    };
    return table;
}

const MethodInfo& find_method(const std::string& name) {
    std::string known;
    for (const auto& m : methods()) {
        if (m.name == name) return m;
        known += (known.empty() ? "" : ", ") + m.name;
    }
    throw Error("unknown method '" + name + "' (known methods: " + known + ")");
}

MethodParams resolve_params(const MethodInfo& method,
                            const std::map<std::string, std::string>& overrides) {
    if (method.params.size() > OM_MAX_METHOD_PARAMS)
        throw Error("method '" + method.name + "' declares too many parameters");
    MethodParams out;
    out.method = &method;
    std::vector<float>& values = out.values;
    for (const auto& p : method.params) values.push_back(p.default_value);
    for (const auto& [key, text] : overrides) {
        size_t idx = 0;
        while (idx < method.params.size() && method.params[idx].name != key) ++idx;
        if (idx == method.params.size()) {
            std::string known;
            for (const auto& p : method.params) known += (known.empty() ? "" : ", ") + p.name;
            throw Error("unknown parameter '" + key + "' for method '" + method.name + "' (" +
                        (known.empty() ? "it takes no parameters" : "its parameters: " + known) +
                        ")");
        }
        const ParamSpec& p = method.params[idx];
        double v = 0.0;
        std::istringstream in(text);
        in >> v;
        if (text.empty() || in.fail() || !in.eof() || !std::isfinite(v))
            throw Error("parameter '" + key + "' of method '" + method.name +
                        "' must be a number, got '" + text + "'");
        if (p.integer && v != std::floor(v))
            throw Error("parameter '" + key + "' of method '" + method.name +
                        "' must be an integer, got '" + text + "'");
        if (v < p.min_value || v > p.max_value) {
            std::ostringstream msg;
            msg << "parameter '" << key << "' of method '" << method.name << "' must be in ["
                << p.min_value << ", " << p.max_value << "], got " << text;
            throw Error(msg.str());
        }
        values[idx] = static_cast<float>(v);
    }
    for (size_t i = 0; i < method.params.size(); ++i) {
        const ParamSpec& p = method.params[i];
        if (p.at_most.empty()) continue;
        const float bound = out[p.at_most];
        if (values[i] > bound) {
            std::ostringstream msg;
            msg << "parameter '" << p.name << "' of method '" << method.name << "' (" << values[i]
                << ") must not exceed '" << p.at_most << "' (" << bound << ")";
            throw Error(msg.str());
        }
    }
    return out;
}

float MethodParams::operator[](const std::string& name) const {
    if (method)
        for (size_t k = 0; k < method->params.size() && k < values.size(); ++k)
            if (method->params[k].name == name) return values[k];
    throw Error("method '" + (method ? method->name : std::string("?")) + "' has no parameter '" +
                name + "'");
}

std::vector<const MethodInfo*> select_methods(const std::vector<std::string>& names) {
    for (const auto& n : names) find_method(n);  // unknown names are errors
    std::vector<const MethodInfo*> out;
    for (const auto& m : methods())
        if (names.empty() || std::find(names.begin(), names.end(), m.name) != names.end())
            out.push_back(&m);
    return out;
}

std::string describe_setting(const std::map<std::string, std::string>& setting) {
    std::string out;
    for (const auto& [k, v] : setting) out += (out.empty() ? "" : " ") + k + "=" + v;
    return out.empty() ? "defaults" : out;
}

void parse_assignment(const std::string& item, std::map<std::string, std::string>& out) {
    auto eq = item.find('=');
    if (eq == std::string::npos || eq == 0) throw Error("expected key=value, got '" + item + "'");
    out[item.substr(0, eq)] = item.substr(eq + 1);
}

std::vector<std::string> sampling_program_files(const std::string& file) {
    return {"common/lanes.h", "common/sampling.cl", file};
}

std::vector<std::string> shade_program_files() {
    return {"common/lanes.h", "common/sampling.cl", "common/blocks.cl", "shade.cl"};
}

int lane_groups(const MethodInfo& m, int lanes) { return lanes > 1 && m.lane_pairs ? 2 : 1; }

std::vector<std::string> offset_program_files(const MethodInfo& m) {
    return {"common/lanes.h",  "common/sampling.cl",       "common/ray.cl",
            "common/patch.cl", "methods/" + m.kernel_file, "common/blocks.cl",
            "offset.cl"};
}

std::string lanes_define(int lanes) {
    return lanes > 1 ? "#define OM_LANES " + std::to_string(lanes) + "\n" : "";
}

std::string offset_program_defines(const MethodInfo& method, const OffsetVariant& v, bool tiles) {
    std::string defines = lanes_define(v.lanes);
    if (lane_groups(method, v.lanes) == 2) defines += "#define OM_LANE_PAIRS\n";
    if (v.images && !tiles) defines += "#define OM_IMAGES\n";
    if (v.lod && !tiles) defines += "#define OM_LOD\n";
    if (v.depth) defines += "#define OM_OUT_DEPTH\n";
    if (v.fetches) defines += "#define OM_OUT_FETCHES\n";
    if (v.flags) defines += "#define OM_OUT_FLAGS\n";
    return defines + param_slot_defines(method);
}

std::string param_slot_defines(const MethodInfo& m) {
    std::string out;
    for (size_t k = 0; k < m.params.size(); ++k)
        out += "#define OM_SLOT_" + m.params[k].name + " " + std::to_string(k) + "\n";
    return out;
}

}  // namespace offsetmap
