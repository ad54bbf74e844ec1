#include "offsetmap/timing.hpp"

#include <algorithm>

#include "offsetmap/runtime.hpp"

namespace offsetmap {

double median(std::vector<double> v, double none) {
    if (v.empty()) return none;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double launch_ms(const std::function<cl::Event()>& launch, bool host_clock) {
    Stopwatch clock;
    cl::Event e = launch();
    e.wait();
    return host_clock ? clock.total() : event_ms(e);
}

}  // namespace offsetmap
