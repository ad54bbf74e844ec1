#pragma once
#include <map>
#include <string>
#include <vector>

namespace offsetmap {

struct ParamSpec {
    std::string name;
    float default_value;
    float min_value;
    float max_value;
    bool integer;
    std::string doc;
};

// Data a method needs beyond the height pyramid, built on the device before its first pass.
enum class Precompute { None, DistanceMap, MaxMip, ConeMap };

struct MethodInfo {
    std::string name;         // CLI and API name, e.g. "parallax-limited"
    std::string kernel_file;  // under kernels/methods/
    std::string summary;
    std::string reference;          // the source it follows
    std::string precomputed;        // precomputed data and its memory, or "none"
    std::vector<ParamSpec> params;  // order = OmOffsetParams::p
    Precompute precompute = Precompute::None;
    // Settings the accuracy-vs-cost sweep tries, cheapest first (empty: the defaults only).
    std::vector<std::map<std::string, std::string>> sweep = {};
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

// Method parameter values in registry order: defaults overridden by `overrides` (name -> text).
// Throws Error for an unknown name, a non-numeric value, a non-integer for an integer parameter, or
// a value outside the declared range.
std::vector<float> resolve_params(const MethodInfo& method,
                                  const std::map<std::string, std::string>& overrides);

// Parses "key=value" into the map; throws Error on a malformed item.
void parse_assignment(const std::string& item, std::map<std::string, std::string>& out);

}  // namespace offsetmap
