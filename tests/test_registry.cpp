// The method registry: every row has its kernel, and parameters are checked with clear errors.
#include "support.hpp"

namespace omtest {
namespace {

TEST(Registry, SeedAndGroundTruthMethodsAreListedWithKernels) {
    for (const char* name : {"none", "parallax", "parallax-limited", "exact"}) {
        const MethodInfo& m = find_method(name);
        EXPECT_FALSE(m.reference.empty()) << name;
        EXPECT_FALSE(kernel_source("methods/" + m.kernel_file).empty()) << name;
        EXPECT_LE(m.params.size(), static_cast<size_t>(OM_MAX_METHOD_PARAMS));
    }
    try {
        find_method("pomm");
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("known methods: none, parallax"), std::string::npos);
    }
}

TEST(Registry, ParametersResolveWithDefaultsRangesAndClearErrors) {
    MethodInfo m{"demo", "none.cl", "", "",
                 {{"steps", 16, 1, 256, true, "linear steps"}, {"bias", 0.5f, 0, 1, false, ""}}};
    EXPECT_EQ(resolve_params(m, {}).values, (std::vector<float>{16, 0.5f}));
    MethodParams p = resolve_params(m, {{"steps", "32"}, {"bias", "0.25"}});
    EXPECT_EQ(p.values, (std::vector<float>{32, 0.25f}));
    EXPECT_EQ(p["bias"], 0.25f);  // by name
    EXPECT_THROW(p["step"], Error);
    auto expect_error = [&](std::map<std::string, std::string> o, const std::string& needle) {
        try {
            resolve_params(m, o);
            ADD_FAILURE() << needle;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    expect_error({{"step", "3"}}, "unknown parameter 'step' for method 'demo' (its parameters: steps, bias)");
    expect_error({{"steps", "many"}}, "must be a number, got 'many'");
    expect_error({{"steps", "2.5"}}, "must be an integer");
    expect_error({{"steps", "0"}}, "must be in [1, 256], got 0");
    expect_error({{"bias", "nan"}}, "must be a number");
    expect_error({{"steps", ""}}, "must be a number");
    std::map<std::string, std::string> kv;
    parse_assignment("steps=8", kv);
    EXPECT_EQ(kv["steps"], "8");
    EXPECT_THROW(parse_assignment("steps", kv), Error);
    EXPECT_THROW(parse_assignment("=3", kv), Error);
}

}  // namespace
}  // namespace omtest
