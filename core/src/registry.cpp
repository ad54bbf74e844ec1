#include "offsetmap/registry.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "methods/maxmip_pyramid.h"
#include "offsetmap/error.hpp"
#include "offsetmap/shared.h"
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

ParamSpec integer_param(const char* name, float value, float lo, float hi, const char* doc,
                        const char* at_most = "") {
    return {name, value, lo, hi, true, doc, at_most};
}
ParamSpec real_param(const char* name, float value, float lo, float hi, const char* doc) {
    return {name, value, lo, hi, false, doc};
}

// A registry row, each field named where it is set (the rest keep MethodInfo's defaults).
class Row {
  public:
    Row(const char* name, const char* kernel_file) {
        m_.name = name;
        m_.kernel_file = kernel_file;
    }
    Row& summary(const char* text) { return set(m_.summary, text); }
    Row& reference(const char* text) { return set(m_.reference, text); }
    Row& params(std::vector<ParamSpec> p) { return set(m_.params, std::move(p)); }
    Row& precompute(const PrecomputeSpec* spec) { return set(m_.precompute, spec); }
    Row& sweep(std::vector<std::map<std::string, std::string>> s) {
        return set(m_.sweep, std::move(s));
    }
    Row& fetch_cap(double (*cap)(const MethodParams&)) { return set(m_.fetch_cap, cap); }
    Row& lane_pairs() { return set(m_.lane_pairs, true); }
    Row& beam() { return set(m_.beam, true); }
    Row& glsl(const char* branch, std::map<std::string, float> only_with = {}) {
        m_.glsl_only_with = std::move(only_with);
        return set(m_.glsl, branch);
    }
    operator MethodInfo() const { return m_; }

  private:
    template <typename T, typename V>
    Row& set(T& field, V&& value) {
        field = std::forward<V>(value);
        return *this;
    }
    MethodInfo m_;
};

}  // namespace

const std::vector<MethodInfo>& methods() {
    static const std::vector<MethodInfo> table = {
        Row("none", "none.cl")
            .summary("normal mapping only: uv' = uv")
            .reference("Blinn 1978, bump mapping")
            .fetch_cap(cap_zero)
            .glsl("NONE"),
        Row("parallax", "parallax.cl")
            .summary(
                "one height fetch, flat-surface assumption: uv' = uv - (r - H(uv)) s V.xy / V.z")
            .reference("Kaneko et al. 2001, detailed shape representation with parallax mapping")
            .fetch_cap(cap_one)
            .glsl("PARALLAX"),
        Row("parallax-limited", "parallax_limited.cl")
            .summary("parallax with offset limiting: uv' = uv - (r - H(uv)) s V.xy (no 1/V.z)")
            .reference("Welsh 2004, parallax mapping with offset limiting")
            .fetch_cap(cap_one),
        Row("parallax-slope", "parallax_slope.cl")
            .summary("one slope step: the ray meets the relief's tangent plane at uv (1 fetch; the "
                     "bilinear patch's own gradient gives the normal)")
            .reference(
                "Premecz 2006, iterative parallax mapping with slope information, section 3; slope "
                "notes")
            .params({integer_param("safe", 0, 0, 1,
                                   "0: t = s(r-H) / (n.V), n = (-s grad H, 1), n.V >= 1e-4, t "
                                   "clamped to the slab; 1: Premecz safe form t = s(r-H) N.z")})
            .sweep({{{"safe", "0"}}, {{"safe", "1"}}})
            .fetch_cap(cap_one),
        Row("parallax-iterative", "parallax_iterative.cl")
            .summary("the slope step repeated from the previous estimate (1 fetch per iteration)")
            .reference("Premecz 2006, section 3")
            .params(
                {integer_param("iterations", 4, 1, 64, "slope steps k (k = 1 is parallax-slope)"),
                 integer_param("safe", 0, 0, 1, "as parallax-slope")})
            .sweep({{{"iterations", "2"}},
                    {{"iterations", "4"}},
                    {{"iterations", "8"}},
                    {{"iterations", "16"}}})
            .fetch_cap(cap_iterative),
        Row("steep", "steep.cl")
            .summary(
                "n equal depth layers, first sample at or below the relief (reads one level of the "
                "height pyramid)")
            .reference("McGuire & McGuire 2005, steep parallax mapping")
            .params({integer_param("layers", 16, 1, 256, "depth layers n (at most n + 1 fetches)"),
                     integer_param("lod", 0, 0, 15, "mip level held fixed during the march")})
            .sweep({{{"layers", "4"}},
                    {{"layers", "8"}},
                    {{"layers", "16"}},
                    {{"layers", "32"}},
                    {{"layers", "64"}},
                    {{"layers", "128"}}})
            .fetch_cap(cap_steep)
            .glsl("STEEP", {{"lod", 0}}),
        Row("relief", "relief.cl")
            .summary("linear search, then binary search")
            .reference("Policarpo, Oliveira & Comba 2005, relief mapping; Premecz 2006 section 2.3")
            .params({integer_param("linear", 16, 1, 256, "linear search steps n"),
                     integer_param("binary", 6, 0, 32, "binary search steps m")})
            .sweep({{{"linear", "4"}, {"binary", "2"}},
                    {{"linear", "8"}, {"binary", "4"}},
                    {{"linear", "16"}, {"binary", "6"}},
                    {{"linear", "32"}, {"binary", "8"}},
                    {{"linear", "64"}, {"binary", "10"}}})
            .fetch_cap(cap_relief)
            .glsl("RELIEF"),
        Row("pom", "pom.cl")
            .summary("linear search with lerp(n_max, n_min, V.z) steps (or one per `spacing` "
                     "texels crossed), then the ray cut with the segment between the last two "
                     "samples")
            .reference("Tatarchuk 2006, practical parallax occlusion mapping")
            .params({integer_param("min_samples", 8, 1, 256, "steps when looking straight down",
                                   "max_samples"),
                     integer_param("max_samples", 32, 1, 256, "steps at grazing views"),
                     real_param("spacing", 0, 0, 1024,
                                "> 0: one step per this many texels the ray crosses, within "
                                "[min_samples, max_samples]; 0: Tatarchuk's lerp by V.z")})
            .sweep({{{"min_samples", "1"}, {"max_samples", "8"}},
                    {{"min_samples", "1"}, {"max_samples", "10"}},
                    {{"min_samples", "2"}, {"max_samples", "10"}},
                    {{"min_samples", "4"}, {"max_samples", "16"}},
                    {{"min_samples", "8"}, {"max_samples", "32"}},
                    {{"min_samples", "16"}, {"max_samples", "64"}},
                    {{"min_samples", "32"}, {"max_samples", "128"}},
                    {{"min_samples", "1"}, {"max_samples", "16"}, {"spacing", "6"}}})
            .fetch_cap(cap_pom)
            .glsl("POM"),
        Row("sphere", "sphere.cl")
            .summary("sphere tracing through a conservative 3D distance map from the top plane")
            .reference(
                "Donnelly 2005, per-pixel displacement mapping with distance functions (GPU Gems "
                "2 ch. 8); Premecz 2006 section 2.4")
            .params(
                {integer_param("res", 256, 8, 1024, "distance map voxels per side of the tile"),
                 integer_param("layers", 32, 2, 128, "distance map voxels through the relief slab"),
                 integer_param("steps", 64, 1, 256,
                               "sphere-tracing steps (one distance fetch each)"),
                 integer_param("cells", 1, 0, 1,
                               "1: near the proxy, and once out of steps, solve the bilinear "
                               "cells (one fetch each; the exact hit); 0: stop at the proxy "
                               "(Donnelly)")})
            .precompute(&kDistanceMap)
            .sweep({{{"res", "64"}, {"layers", "16"}, {"steps", "16"}, {"cells", "0"}},
                    {{"res", "128"}, {"layers", "16"}, {"steps", "32"}, {"cells", "0"}},
                    {{"res", "256"}, {"layers", "32"}, {"steps", "64"}, {"cells", "0"}},
                    {{"res", "512"}, {"layers", "64"}, {"steps", "128"}, {"cells", "0"}},
                    {{"res", "256"}, {"layers", "32"}, {"steps", "64"}}})
            .fetch_cap(cap_sphere)
            .lane_pairs(),
        Row("secant", "secant.cl")
            .summary("pom's linear search, then secant refinement (regula falsi, Illinois) to a "
                     "tolerance")
            .reference(
                "Risser, Shah & Pattanaik 2007, faster relief mapping using the secant method")
            .params({integer_param("min_samples", 8, 1, 256,
                                   "linear steps when looking straight down", "max_samples"),
                     integer_param("max_samples", 32, 1, 256, "linear steps at grazing views"),
                     integer_param("refine", 4, 0, 32, "secant iterations at most (0: pom)"),
                     real_param("tol", 1e-4f, 0.0f, 0.1f,
                                "stop when the height gap is below this (H units)")})
            .sweep({{{"min_samples", "1"}, {"max_samples", "4"}, {"refine", "1"}},
                    {{"min_samples", "1"}, {"max_samples", "5"}, {"refine", "1"}},
                    {{"min_samples", "2"}, {"max_samples", "4"}, {"refine", "1"}},
                    {{"min_samples", "2"}, {"max_samples", "8"}, {"refine", "2"}},
                    {{"min_samples", "4"}, {"max_samples", "16"}, {"refine", "2"}},
                    {{"min_samples", "8"}, {"max_samples", "32"}, {"refine", "3"}},
                    {{"min_samples", "16"}, {"max_samples", "64"}, {"refine", "4"}},
                    {{"min_samples", "32"}, {"max_samples", "128"}, {"refine", "6"}}})
            .fetch_cap(cap_secant),
        Row("maxmip", "maxmip.cl")
            .summary("exact first hit by a hierarchical walk of a maximum-height pyramid (O(log n) "
                     "block tests)")
            .reference("Tevs, Ihrke & Seidel 2008, maximum mipmaps for height field rendering")
            .params({integer_param("max_level", OM_MAXMIP_MAX_LEVEL, 0, OM_MAXMIP_MAX_LEVEL,
                                   "highest pyramid level used (0: plain DDA, as exact)"),
                     integer_param("beam", 0, 0, 1,
                                   "1: a work-item's rays first skip together the empty space "
                                   "the pyramid proves")})
            .precompute(&kMaxPyramid)
            .beam()
            .sweep({{{"max_level", "0"}}, {{"max_level", "3"}}, {{"max_level", "15"}}})
            .fetch_cap(cap_cells),
        Row("cone", "cone.cl")
            .summary(
                "exact first hit by cone steps over a cell-conservative cone map, min step one "
                "cell, exact patch solve where the ray dips below a cell's maximum")
            .reference(
                "Dummer 2006 and Policarpo & Oliveira 2007 (GPU Gems 3 ch. 18), cone step mapping; "
                "Bán, Valasek et al. 2024, robust cone step mapping")
            .params({integer_param(
                         "max_ratio", 64, 1, 1024,
                         "widest cone stored, texels per unit height: bounds the build's search "
                         "radius"),
                     integer_param("beam", 0, 0, 1,
                                   "1: a work-item's rays first skip together the empty space "
                                   "the max pyramid proves (stored after the cone map)")})
            .precompute(&kConeMap)
            .beam()
            .sweep({{{"max_ratio", "4"}},
                    {{"max_ratio", "16"}},
                    {{"max_ratio", "64"}},
                    {{"max_ratio", "256"}}})
            .fetch_cap(cap_cells)
            .lane_pairs(),
        Row("exact", "exact.cl")
            .summary("first hit with the bilinear height field: DDA over texel cells, quadratic "
                     "per patch")
            .reference("ground truth of this project (ray / bilinear patch)")
            .fetch_cap(cap_cells)
            .lane_pairs(),
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

std::vector<std::string> prelude_files() { return {"common/lanes_pocl.h", "common/lanes.h"}; }

std::vector<std::string> sampling_program_files(const std::string& file) {
    return {"common/sampling.cl", file};
}

std::vector<std::string> prep_program_files(const PrecomputeSpec& spec) {
    std::vector<std::string> files = {"common/sampling.cl"};
    if (spec.layout_file) files.push_back(spec.layout_file);
    files.push_back(spec.prep_file);
    return files;
}

std::vector<std::string> shade_program_files() {
    return {"common/sampling.cl", "common/blocks.cl", "frame/slots.h", "common/triplanar.cl",
            "shade.cl"};
}

std::string shade_program_defines(int lanes, bool materials) {
    return lanes_define(lanes) + (materials ? "#define OM_SHADE_MATERIALS\n" : "");
}

std::vector<std::string> classify_program_files() { return {"frame/slots.h", "frame/classify.cl"}; }

std::vector<std::string> behind_program_files() { return {"frame/behind.cl"}; }

int lane_groups(const MethodInfo& m, int lanes) { return lanes > 1 && m.lane_pairs ? 2 : 1; }

std::vector<std::string> offset_program_files(const MethodInfo& m) {
    std::vector<std::string> files = {"common/sampling.cl", "common/ray.cl", "common/patch.cl",
                                      "common/curved.cl"};
    if (m.precompute && m.precompute->layout_file) files.push_back(m.precompute->layout_file);
    if (m.beam) files.insert(files.end(), {"methods/maxmip_pyramid.h", "common/beam.cl"});
    files.insert(files.end(), {"methods/" + m.kernel_file, "common/blocks.cl", "offset.cl"});
    return files;
}

std::string lanes_define(int lanes) {
    return lanes > 1 ? "#define OM_LANES " + std::to_string(lanes) + "\n" : "";
}

std::string offset_program_defines(const MethodInfo& method, const OffsetVariant& v, bool tiles) {
    std::string defines = lanes_define(v.lanes);
    if (lane_groups(method, v.lanes) == 2) defines += "#define OM_LANE_PAIRS\n";
    if (v.images && !tiles) defines += "#define OM_IMAGES\n";
    if (v.lod && !tiles) defines += "#define OM_LOD\n";
    if (v.curved) defines += "#define OM_CURVED\n";
    if (v.curved && v.uv_metric) defines += "#define OM_UV_METRIC\n";
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
