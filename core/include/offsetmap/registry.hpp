#pragma once
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "offsetmap/cl.hpp"

namespace offsetmap {

class Runtime;
struct DeviceHeightField;
struct PassSettings;
struct MethodInfo;

struct ParamSpec {
    std::string name;  // the kernel reads it as OM_PARAM(P, name)
    float default_value;
    float min_value;
    float max_value;
    bool integer;
    std::string doc;
    std::string at_most = {};  // another parameter this one may not exceed ("" for none)
};

// A method's parameter values, resolved once (resolve_params): read by name. `values` follow the
// row's parameter order, which is the slot order the host's defines give the kernel.
struct MethodParams {
    const MethodInfo* method = nullptr;
    std::vector<float> values;
    // The value of that parameter; throws Error when the method has no such parameter.
    float operator[](const std::string& name) const;
};

// A method's precomputed data: built on the device from the height field before its first pass,
// by a builder that lives beside its prep kernel (core/src/precompute/, kernels/prep/).
struct PrecomputeSpec {
    const char* doc;        // what it holds and its memory, for `offsetmap methods`
    const char* prep_file;  // its kernels, under kernels/ (after the sampling layer)
    // The data's layout, a header under kernels/ shared by the builder, the prep kernel and the
    // method (both programs list it before their own file), or nullptr.
    const char* layout_file;
    // The bytes the pass keeps for these parameters on a map_w x map_h field.
    size_t (*bytes)(const MethodParams& params, const PassSettings& settings, int map_w, int map_h);
    // Enqueued after the field's `ready` event, not waited for: the data is complete when every
    // one of `events` is (its kernels, for the pass to wait on and the build time to sum).
    struct Built {
        cl::Buffer data;
        std::vector<cl::Event> events;
    };
    Built (*build)(Runtime& runtime, const DeviceHeightField& field, const PassSettings& settings,
                   const MethodParams& params);
};

// A method's whole contract: everything the host, the tools, the renderer and the tests know of it,
// its one table. Adding a method is one kernel file (kernels/methods/), one row here
// (core/src/registry.cpp, built field by field by name) and one test row (tests/support.hpp); with
// precomputed data, also its prep kernel and builder (docs/design.md, "Adding a method").
struct MethodInfo {
    std::string name;         // CLI and API name, e.g. "parallax-limited"
    std::string kernel_file;  // under kernels/methods/
    std::string summary;
    std::string reference;                       // the source it follows
    std::vector<ParamSpec> params;               // by name; resolved by resolve_params
    const PrecomputeSpec* precompute = nullptr;  // none for most methods
    // Settings the accuracy-vs-cost sweep tries, cheapest first (empty: the defaults only).
    std::vector<std::map<std::string, std::string>> sweep = {};
    // The most height fetches one pixel may cost: a bound from the method's loop counts for these
    // parameters, or < 0 for the cell walks, bounded by the cells the ray crosses instead
    // (tests/support.hpp derives that from the ray).
    double (*fetch_cap)(const MethodParams& params) = nullptr;
    // The kernel file also defines om_trace_pair, two groups of lanes walked in one loop: on a
    // device with lanes a work-item then takes two groups, so that one group's dependent reads
    // overlap the other's work (worth it for walks whose every step waits on its last read).
    bool lane_pairs = false;
    // The kernel file reads the beam (kernels/common/beam.cl: its lanes skip the empty space above
    // the relief together, over the max pyramid its precomputed data holds).
    bool beam = false;
    // Its forward version for a GLSL fragment shader (renderer/shaders/relief.glsl): the branch
    // the shader selects as OM_GLSL_<glsl>, "" for none; and the parameter values that version
    // alone follows (name -> value; e.g. level 0 only).
    std::string glsl = {};
    std::map<std::string, float> glsl_only_with = {};
};

// The named methods in registry order (every method when `names` is empty); throws Error for an
// unknown name.
std::vector<const MethodInfo*> select_methods(const std::vector<std::string>& names);

// "key=value key=value" for a setting (or "defaults" for an empty one).
std::string describe_setting(const std::map<std::string, std::string>& setting);

// All methods, in the order the CLI and the demo list them.
const std::vector<MethodInfo>& methods();

// The method of that name; throws Error listing the known names otherwise.
const MethodInfo& find_method(const std::string& name);

// The method's parameters: defaults overridden by `overrides` (name -> text). Throws Error for an
// unknown name, a non-numeric value, a non-integer for an integer parameter, or a value outside
// the declared range or above the parameter it may not exceed (at_most).
MethodParams resolve_params(const MethodInfo& method,
                            const std::map<std::string, std::string>& overrides);

// Parses "key=value" into the map; throws Error on a malformed item.
void parse_assignment(const std::string& item, std::map<std::string, std::string>& out);

// Kernel programs, as lists of files under kernels/ (one definition each, for the passes, the
// bench and the C++ peer). Every program starts with the prelude (Runtime::program_source puts it
// there, after offsetmap/shared.h): the lane layer, its PoCL paths first. Then a program that
// reads heights: the sampling layer then `file` (a prep kernel, the roofline); a method's prep
// program (sampling, its data's layout, its prep kernel); the shade pass (sampling, image blocks,
// shading, with the material frame's id rule); the material frame's classification; and a method's
// offset program (sampling, ray, patch solve, its data's layout, the method, image blocks, the
// entry).
std::vector<std::string> prelude_files();
std::vector<std::string> sampling_program_files(const std::string& file);
std::vector<std::string> prep_program_files(const PrecomputeSpec& spec);
std::vector<std::string> shade_program_files();
// The shade program's defines: its lanes, and the material frame's kernel (om_shade_materials,
// with the triplanar blend) or the single-material one (om_shade).
std::string shade_program_defines(int lanes, bool materials);
std::vector<std::string> classify_program_files();
std::vector<std::string> behind_program_files();  // the material frame's layer behind
std::vector<std::string> offset_program_files(const MethodInfo& method);

// Groups of lanes a work-item of `method` walks on a device with `lanes` lanes: 2 for a lane-pair
// method on lanes (the entry's OM_LANE_PAIRS), else 1.
int lane_groups(const MethodInfo& method, int lanes);

// "#define OM_LANES n" for n pixels a work-item (lanes.h), nothing for 1 (the kernels' default).
std::string lanes_define(int lanes);

// Which build of a method's offset program a pass asks for (kernels/offset.cl's OM_* switches).
struct OffsetVariant {
    int lanes = 1;        // OM_LANES (with OM_LANE_PAIRS where lane_groups says 2)
    bool images = false;  // OM_IMAGES: heights through an image1d_buffer view
    bool lod = false;     // OM_LOD
    bool curved = false;  // OM_CURVED: a curvature plane bound
    bool uv_metric = false;  // OM_UV_METRIC: a uv metric plane bound beside it
    bool depth = false, fetches = false, flags = false;  // OM_OUT_*: the optional outputs bound
};
// The defines of that build: the offset entry's (om_offset), or with `tiles` the material frame's
// tile entry's (om_offset_tiles, which takes neither images nor LOD); the parameter slots included.
std::string offset_program_defines(const MethodInfo& method, const OffsetVariant& v,
                                   bool tiles = false);

// The defines that hand a method's parameters to its kernel by name: OM_SLOT_<name> is the slot of
// OmOffsetParams::p holding it, which OM_PARAM(P, name) reads (offsetmap/shared.h).
std::string param_slot_defines(const MethodInfo& method);

}  // namespace offsetmap
