// What the bench's parts share: timing in turns, the synthetic height map, camera G-buffers.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "offsetmap/evaluation.hpp"
#include "offsetmap/timing.hpp"

namespace offsetmap::bench {

struct Timing {
    double median_ms = 0, min_ms = 0;
    int runs = 0;
};

// Whether launches are timed by the host's clock: on a device whose events carry no times
// (Runtime::profiling false: rusticl in Mesa 22.3 stamps every command 0, 1, 2, 3 ns). Main sets
// it.
inline bool& host_clock() {
    static bool on = false;
    return on;
}

// One launch's milliseconds by the clock main chose (offsetmap/timing.hpp).
inline double launch_ms(const std::function<cl::Event()>& launch) {
    return offsetmap::launch_ms(launch, host_clock());
}

inline Timing time_launches(const std::function<cl::Event()>& launch, double target_ms) {
    launch().wait();  // warm-up: PoCL compiles per local size on first launch
    double t0 = std::max(launch_ms(launch), 1e-3);
    int runs = std::clamp(static_cast<int>(target_ms / t0), target_ms > 0 ? 3 : 1, 30);
    std::vector<double> ts = {t0};
    for (int r = 1; r < runs; ++r) ts.push_back(launch_ms(launch));
    return {median(ts), *std::min_element(ts.begin(), ts.end()), static_cast<int>(ts.size())};
}

// Runs (each returns its milliseconds) timed in turns (a, b, c, a, b, c, ...), each after a
// warm-up, at least 5 and at most 30 rounds within about `target_ms`: the machine's load changes
// within seconds, so kernels compared as a ratio are timed in the same window (timed minutes apart,
// the ratio of two fixed kernels moved by up to 2x on a shared machine).
inline std::vector<Timing> time_interleaved_ms(const std::vector<std::function<double()>>& runs,
                                               double target_ms) {
    double round = 0;
    for (const auto& run : runs) {
        run();
        round += std::max(run(), 1e-3);
    }
    int rounds = std::clamp(static_cast<int>(target_ms / round), target_ms > 0 ? 5 : 1, 30);
    std::vector<std::vector<double>> ts(runs.size());
    for (int r = 0; r < rounds; ++r)
        for (size_t k = 0; k < runs.size(); ++k) ts[k].push_back(runs[k]());
    std::vector<Timing> out;
    for (auto& t : ts) out.push_back({median(t), *std::min_element(t.begin(), t.end()), rounds});
    return out;
}

inline std::vector<Timing> time_interleaved(const std::vector<std::function<cl::Event()>>& launches,
                                            double target_ms) {
    std::vector<std::function<double()>> runs;
    for (const auto& launch : launches) runs.push_back([&launch] { return launch_ms(launch); });
    return time_interleaved_ms(runs, target_ms);
}

// The share of lane-steps that fetch for a live lane when pixels are grouped in tw x th tiles
// (one work-item each, or a GPU's SIMD group; rows of `tw` when th = 1 and the width is a
// multiple): each group runs as many steps as its slowest pixel. `group_steps`, when given, gets
// the lane-steps the groups run (their slowest pixel's steps times their pixels).
inline double lanes_busy(const std::vector<std::uint32_t>& fetches, int width, int height, int tw,
                         int th, double* group_steps = nullptr) {
    double busy = 0, steps = 0;
    for (int y0 = 0; y0 < height; y0 += th)
        for (int x0 = 0; x0 < width; x0 += tw) {
            std::uint32_t most = 0;
            int count = 0;
            for (int y = y0; y < std::min(height, y0 + th); ++y)
                for (int x = x0; x < std::min(width, x0 + tw); ++x) {
                    const std::uint32_t f = fetches[static_cast<size_t>(y) * width + x];
                    busy += f;
                    most = std::max(most, f);
                    ++count;
                }
            steps += static_cast<double>(most) * count;
        }
    if (group_steps) *group_steps = steps;
    return steps > 0 ? busy / steps : 1.0;
}

// Each material's method at its table's parameters (a renderer's `methods`; no `auto` rows).
inline std::vector<MethodParams> table_methods(const std::vector<LoadedMaterial>& table) {
    std::vector<MethodParams> methods;
    for (const LoadedMaterial& m : table)
        methods.push_back(resolve_params(find_method(m.spec.method), m.spec.params));
    return methods;
}

struct Resolution {
    const char* name;
    int w, h;
};

inline GBuffer camera_gbuffer(const Resolution& r) {
    PlaneScene p;
    p.width = r.w;
    p.height = r.h;
    return make_scene(p);
}

}  // namespace offsetmap::bench
