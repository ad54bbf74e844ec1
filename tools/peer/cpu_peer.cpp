#include "cpu_peer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "offsetmap/error.hpp"
#include "offsetmap/registry.hpp"

namespace offsetmap::cpu_peer {

#define OM_PEER(name) void om_cpu_##name(const Args&, int, int);
#include "cpu_peer_methods.inc"
#undef OM_PEER

Entry entry_for(const std::string& kernel_file) {
#define OM_PEER(name) \
    if (kernel_file == #name ".cl") return &om_cpu_##name;
#include "cpu_peer_methods.inc"
#undef OM_PEER
    throw Error("no C++ peer for kernel file '" + kernel_file + "'");
}

namespace {

// The host side of the pyramid (what upload() builds on the device, box filter for box filter).
std::vector<float> host_pyramid(const HeightMap& map, int& levels) {
    levels = mip_level_count(map.width, map.height);
    std::vector<float> all(mip_pyramid_floats(map.width, map.height, levels));
    std::copy(map.h.begin(), map.h.end(), all.begin());
    int w = map.width, h = map.height;
    size_t offset = 0;
    for (int l = 1; l < levels; ++l) {
        int cw = std::max(1, w / 2), ch = std::max(1, h / 2);
        size_t child = offset + static_cast<size_t>(w) * h;
        for (int j = 0; j < ch; ++j)
            for (int i = 0; i < cw; ++i) {
                int x0 = i * w / cw, x1 = std::max(x0 + 1, (i + 1) * w / cw);
                int y0 = j * h / ch, y1 = std::max(y0 + 1, (j + 1) * h / ch);
                float sum = 0.0f;
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x)
                        sum += all[offset + static_cast<size_t>(y) * w + x];
                all[child + static_cast<size_t>(j) * cw + i] =
                    sum / static_cast<float>((x1 - x0) * (y1 - y0));
            }
        offset = child;
        w = cw;
        h = ch;
    }
    return all;
}

}  // namespace

Run run(const std::string& method, const std::map<std::string, std::string>& params,
        const GBuffer& gb, const HeightMap& map, const PassSettings& s, int repeats,
        unsigned threads) {
    const MethodInfo& m = find_method(method);
    if (m.precompute)
        throw Error("the C++ peer does not build precomputed data ('" + method + "')");
    validate(s);
    Entry entry = entry_for(m.kernel_file);
    std::vector<float> values = resolve_params(m, params).values;
    int levels = 1;
    std::vector<float> pyramid = host_pyramid(map, levels);

    Args a{};
    OmOffsetParams& p = a.params;
    p = offset_params(s, map.width, map.height, gb.width, gb.height);
    p.mip_levels = levels;
    std::copy(values.begin(), values.end(), p.p);

    Run out;
    OffsetResult& r = out.result;
    r.width = gb.width;
    r.height = gb.height;
    r.uv.resize(gb.pixels());
    r.depth.resize(gb.pixels());
    r.fetches.resize(gb.pixels());
    r.flags.resize(gb.pixels());
    a.uv = gb.uv.data();
    a.view = gb.view.data();
    a.heights = pyramid.data();
    a.out_uv = r.uv.data();
    a.out_depth = r.depth.data();
    a.out_fetches = r.fetches.data();
    a.out_flags = r.flags.data();

    unsigned n_threads = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
    const int n = static_cast<int>(gb.pixels());
    std::vector<double> times;
    for (int rep = 0; rep <= repeats; ++rep) {  // rep 0 warms caches and page tables
        auto t0 = std::chrono::steady_clock::now();
        std::vector<std::thread> pool;
        // Interleaved blocks of 64 pixels balance rows of different cost across threads.
        for (unsigned t = 0; t < n_threads; ++t)
            pool.emplace_back([&, t] {
                for (int b = static_cast<int>(t) * 64; b < n; b += static_cast<int>(n_threads) * 64)
                    entry(a, b, std::min(b + 64, n));
            });
        for (auto& th : pool) th.join();
        if (rep > 0)
            times.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
    }
    if (!times.empty()) {
        std::sort(times.begin(), times.end());
        out.median_ms = times[times.size() / 2];
    }
    return out;
}

}  // namespace offsetmap::cpu_peer
