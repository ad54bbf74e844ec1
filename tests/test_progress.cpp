// Long precomputes report progress through the runtime, and building in slices (to report it)
// gives the same data, bit for bit, as building in one launch.
#include <cstring>

#include "support.hpp"

namespace omtest {
namespace {

std::vector<float> read_all(Runtime& rt, const cl::Buffer& b) {
    std::vector<float> out(b.getInfo<CL_MEM_SIZE>() / sizeof(float));
    rt.queue().enqueueReadBuffer(b, CL_TRUE, 0, out.size() * sizeof(float), out.data());
    return out;
}

TEST(Progress, SlicedPrecomputesReportAndMatchTheWholeBuild) {
    auto shared = runtime();
    HeightMap map = smooth_map(96);
    PassSettings s;
    s.scale = 0.06f;
    for (const auto& [method, params] :
         std::vector<std::pair<std::string, std::map<std::string, std::string>>>{
             {"sphere", {{"res", "48"}, {"layers", "20"}}}, {"cone", {}}}) {
        // Whole: no progress callback.
        auto whole_rt =
            std::make_shared<Runtime>(shared->context(), shared->device(), shared->queue());
        DeviceHeightField field = upload(*whole_rt, map, s);
        OffsetPass whole(whole_rt, method, params);
        whole.prepare(field, s);
        // Sliced: a callback that records what it is told.
        auto sliced_rt =
            std::make_shared<Runtime>(shared->context(), shared->device(), shared->queue());
        std::vector<double> seen;
        std::string what;
        sliced_rt->set_progress([&](const std::string& w, double f) {
            what = w;
            seen.push_back(f);
        });
        OffsetPass sliced(sliced_rt, method, params);
        sliced.prepare(field, s);

        ASSERT_GE(seen.size(), 3u) << method;
        EXPECT_EQ(seen.front(), 0.0) << method;
        EXPECT_EQ(seen.back(), 1.0) << method;
        EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end())) << method;
        EXPECT_NE(what.find(method + ":"), std::string::npos) << what;
        const auto a = read_all(*whole_rt, whole.precomputed_buffer());
        const auto b = read_all(*sliced_rt, sliced.precomputed_buffer());
        ASSERT_EQ(a.size(), b.size()) << method;
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << method;
    }
}

}  // namespace
}  // namespace omtest
