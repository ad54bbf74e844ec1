// The rebuild bench: a field rewritten in place, then each method's precomputed data built again,
// as for a height field that changes every frame (water, deformable terrain).
#include "bench_rebuild.hpp"

#include <algorithm>
#include <array>
#include <cstdio>
#include <string>

#include "offsetmap/timing.hpp"

namespace offsetmap::bench {
namespace {

using json = nlohmann::json;

void wait_for(const DeviceHeightField& f) {
    for (const cl::Event& e : field_ready(f)) e.wait();
}

// The map's heights as an engine keeps them on the device: unorm16 codes.
DeviceHeights device_words(Runtime& rt, const HeightMap& map) {
    std::vector<cl_ushort> words(map.h.size());
    for (size_t k = 0; k < words.size(); ++k)
        words[k] = static_cast<cl_ushort>(map.h[k] * 65535.0f + 0.5f);
    DeviceHeights d;
    d.width = map.width;
    d.height = map.height;
    d.texels.storage = Storage::Unorm16;
    d.texels.buffer = cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                 words.size() * sizeof(cl_ushort), words.data());
    return d;
}

// A second map of the same size whose heights differ everywhere (the first, shifted and mirrored).
HeightMap other_map(const HeightMap& m) {
    HeightMap o = m;
    for (int j = 0; j < m.height; ++j)
        for (int i = 0; i < m.width; ++i)
            o.h[static_cast<size_t>(j) * m.width + i] =
                m.at((m.width - 1 - i + m.width / 3) % m.width, j);
    return o;
}

}  // namespace

json bench_rebuild(std::shared_ptr<Runtime> rt, const std::vector<int>& sizes, int rounds) {
    PassSettings s;
    s.scale = 0.05f;
    std::vector<const MethodInfo*> precomputing;
    for (const MethodInfo& m : methods())
        if (m.precompute) precomputing.push_back(&m);
    std::printf(
        "\nrebuild after an in-place update (ms, medians of %d; wall: enqueue to completion, "
        "kernel: profiling events)\n  %-7s %-22s %10s %10s\n",
        rounds, "map", "step", "wall", "kernel");
    json rows = json::array();
    for (int size : sizes) {
        const std::array<HeightMap, 2> maps = {bench_map(size), other_map(bench_map(size))};
        const std::array<DeviceHeights, 2> on_device = {device_words(*rt, maps[0]),
                                                        device_words(*rt, maps[1])};
        DeviceHeightField field = upload(*rt, maps[0], s);
        wait_for(field);
        std::vector<std::unique_ptr<OffsetPass>> passes;
        for (const MethodInfo* m : precomputing) {
            passes.push_back(std::make_unique<OffsetPass>(rt, m->name));
            passes.back()->prepare(field, s);  // compiles the prep programs
            passes.back()->precomputed();
        }
        std::vector<double> host_ms, device_ms;
        std::vector<std::vector<double>> wall(precomputing.size()), kernel(precomputing.size());
        for (int r = 0; r <= rounds; ++r) {  // round 0 warms up
            const int next = (r + 1) % 2;
            Stopwatch clock;
            update(*rt, field, maps[next], s);
            wait_for(field);
            const double host = clock.lap();
            update(*rt, field, on_device[next], s);
            wait_for(field);
            const double device = clock.lap();
            if (r > 0) host_ms.push_back(host), device_ms.push_back(device);
            for (size_t k = 0; k < passes.size(); ++k) {
                clock.lap();
                passes[k]->prepare(field, s);
                const double ms = passes[k]->precomputed().build_ms;  // waits for the build
                if (r == 0) continue;
                wall[k].push_back(clock.lap());
                kernel[k].push_back(ms);
            }
        }
        json row = {{"map_size", size},
                    {"update_from_host_ms", median(host_ms)},
                    {"update_from_device_ms", median(device_ms)}};
        const std::string label = std::to_string(size) + "^2";
        std::printf("  %-7s %-22s %10.3f %10s\n", label.c_str(), "update from the host",
                    median(host_ms), "");
        std::printf("  %-7s %-22s %10.3f %10s\n", label.c_str(), "update from the device",
                    median(device_ms), "");
        json builds = json::array();
        for (size_t k = 0; k < passes.size(); ++k) {
            const std::string name = precomputing[k]->name;
            builds.push_back({{"method", name},
                              {"wall_ms", median(wall[k])},
                              {"kernel_ms", median(kernel[k])},
                              {"bytes", passes[k]->precomputed().bytes}});
            std::printf("  %-7s %-22s %10.3f %10.3f\n", label.c_str(), (name + " data").c_str(),
                        median(wall[k]), median(kernel[k]));
        }
        row["precomputed"] = builds;
        rows.push_back(row);
    }
    return rows;
}

}  // namespace offsetmap::bench
