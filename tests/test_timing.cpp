// The one median every timing reports, and a launch timed by the host's clock where a device's
// events carry no times.
#include <cmath>

#include "offsetmap/timing.hpp"
#include "support.hpp"

namespace omtest {
namespace {

TEST(Timing, TheMedianIsTheMiddleOrTheMeanOfTheTwo) {
    EXPECT_EQ(offsetmap::median({3.0, 1.0, 2.0}), 2.0);
    EXPECT_EQ(offsetmap::median({4.0, 1.0, 3.0, 2.0}), 2.5);
    EXPECT_EQ(offsetmap::median({}), 0.0);
    EXPECT_TRUE(std::isnan(offsetmap::median({}, NAN)));
}

TEST(Timing, AHostClockedLaunchIsTheEnqueueToItsEnd) {
    auto& rt = *runtime();
    const double ms = offsetmap::launch_ms(
        [&] {
            cl::Event e;
            rt.queue().enqueueMarkerWithWaitList(nullptr, &e);
            return e;
        },
        true);
    EXPECT_GE(ms, 0.0);
    EXPECT_TRUE(std::isfinite(ms));
}

}  // namespace
}  // namespace omtest
