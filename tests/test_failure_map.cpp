// The failure map over a rendered frame's views: each traced pixel counted once, in the row of the
// elevation nearest its own; pixels without a surface or facing away left out; rows no pixel is
// nearest to give no cells.
#include "support.hpp"

namespace omtest {
namespace {

cl_float4 view_at(double elevation_deg, double azimuth_deg) {
    const double e = elevation_deg * M_PI / 180.0, a = azimuth_deg * M_PI / 180.0;
    return {{float(std::cos(e) * std::cos(a)), float(std::cos(e) * std::sin(a)), float(std::sin(e)),
             0.0f}};
}

TEST(FailureMap, RenderedViewsBinnedByElevation) {
    GBuffer views;
    views.resize(6, 1, false, false);
    const double elev[6] = {88, 46, 44, 20, 30, -10};  // the last faces away
    for (int k = 0; k < 6; ++k) {
        views.uv[k] = {{0.1f * k + 0.05f, 0.3f}};
        views.view[k] = view_at(elev[k], 40.0 * k);
        views.view[k].s[0] *= 3.0f;  // not unit: the elevation is V's direction's
        views.view[k].s[1] *= 3.0f;
        views.view[k].s[2] *= 3.0f;
    }
    views.uv[4].s[0] = std::nanf("");  // no surface
    FailureMapOptions o;
    o.elevations_deg = {90, 45, 20, 10};
    o.scales = {0.05};
    o.samples = 4;
    o.methods = {"parallax", "exact"};
    o.views = &views;
    const HeightMap map = load_height_map(std::string(OFFSETMAP_SOURCE_DIR) + "/data/rocks.png");
    const std::vector<FailureCell> cells = run_failure_map(runtime(), map, o);
    std::map<std::pair<std::string, double>, FailureCell> by;
    for (const FailureCell& c : cells) by[{c.method, c.elevation_deg}] = c;
    const auto count = [&](const std::string& m, double e) {
        const auto it = by.find({m, e});
        return it == by.end() ? size_t(0) : it->second.uv.count;
    };
    ASSERT_EQ(cells.size(), 6u);  // rows 90, 45 and 20 for each method; none at 10
    for (const char* m : {"parallax", "exact"}) {
        EXPECT_EQ(count(m, 90), 1u);
        EXPECT_EQ(count(m, 45), 2u);
        EXPECT_EQ(count(m, 20), 1u);
        EXPECT_EQ(count(m, 10), 0u);
    }
    EXPECT_EQ(by.at({"exact", 45.0}).uv.max, 0.0);
    EXPECT_EQ(by.at({"parallax", 45.0}).fetches_mean, 1.0);
}

}  // namespace
}  // namespace omtest
