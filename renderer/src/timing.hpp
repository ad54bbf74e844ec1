// Wall-clock times of a frame's passes (each ends in a finish) and their medians.
#pragma once
#include <algorithm>
#include <chrono>
#include <vector>

namespace offsetmap::renderer {

class Stopwatch {
  public:
    // Milliseconds since the last lap (or the start).
    double lap() {
        const auto now = std::chrono::steady_clock::now();
        const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
        last_ = now;
        return ms;
    }
    // Milliseconds since the start, laps aside.
    double total() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
            .count();
    }

  private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now(), last_ = start_;
};

inline double median(std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace offsetmap::renderer
