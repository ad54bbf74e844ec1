// Timing that the bench, the device check, the renderer and the lab share: one median, a launch's
// milliseconds and a stopwatch for passes timed by the host.
#pragma once
#include <chrono>
#include <functional>
#include <vector>

#include "offsetmap/cl.hpp"

namespace offsetmap {

// The middle value (the mean of the two middle ones for an even count); `none` for no values.
double median(std::vector<double> values, double none = 0.0);

// One launch's milliseconds, waited for: its profiling event's, or with `host_clock` (a device
// whose events carry no times: Runtime::profiling false) the host's clock from the enqueue to the
// event's end, which adds the enqueue and the wake-up (tens of microseconds).
double launch_ms(const std::function<cl::Event()>& launch, bool host_clock);

// Wall-clock milliseconds on the host: laps (since the last lap or the start) and the total.
class Stopwatch {
  public:
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
        last_ = now;
        return ms;
    }
    double total() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
    }

  private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
};

}  // namespace offsetmap
