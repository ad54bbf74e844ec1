// Test helpers: one shared runtime, small procedural height maps, and a one-call pass runner.
#pragma once
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <random>

#include "methods/maxmip_pyramid.h"
#include "offsetmap/evaluation.hpp"
#include "offsetmap/shared.h"

namespace omtest {
using namespace offsetmap;

// A world point from a pixel's window depth (GL's convention, rows top first), as the reconstruct
// pass places it (double).
inline glm::dvec3 unproject(const EngineScene& e, int x, int y, double d) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = e.camera.inverse_view_projection[4 * c + r];
    const glm::dvec4 ndc((2.0 * x + 1.0) / e.width - 1.0, 1.0 - (2.0 * y + 1.0) / e.height,
                         2.0 * d - 1.0, 1.0);
    const glm::dvec4 w = m * ndc;
    return glm::dvec3(w) / w.w;
}

// The message of the Error `f` throws ("" when it throws none).
template <typename F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

inline ::testing::AssertionResult contains(const std::string& text, const std::string& part) {
    if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// The PoCL (or chosen) runtime, created once: program builds are cached in it.
inline std::shared_ptr<Runtime> runtime() {
    static std::shared_ptr<Runtime> rt = Runtime::create();
    return rt;
}

// A read-only device copy of `values`.
inline cl::Buffer device_floats(Runtime& rt, const std::vector<float>& values) {
    return cl::Buffer(rt.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                      values.size() * sizeof(float), const_cast<float*>(values.data()));
}

// An out-of-order queue where the device has one, else an in-order queue (rusticl over llvmpipe
// has none): the tests built on one check that every step is ordered by events, and still run
// their frames in order elsewhere.
inline bool has_out_of_order_queue(const cl::Device& device) {
    return (device.getInfo<CL_DEVICE_QUEUE_PROPERTIES>() &
            CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE) != 0;
}
inline cl::CommandQueue out_of_order_queue(const cl::Context& context, const cl::Device& device) {
    return cl::CommandQueue(
        context, device,
        has_out_of_order_queue(device) ? CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE : 0);
}
// Skips a test whose whole point is an out-of-order queue on a device that lacks one, naming it.
// PoCL has one: there its absence still fails the test.
#define SKIP_WITHOUT_OUT_OF_ORDER_QUEUE(device)                                            \
    do {                                                                                   \
        if (has_out_of_order_queue(device)) break;                                         \
        const std::string lacks = runtime()->device_name() + " has no out-of-order queue"; \
        ASSERT_FALSE(runtime()->is_pocl()) << lacks;                                       \
        GTEST_SKIP() << lacks;                                                             \
    } while (0)

// A measured figure the README cites: tests/readme_figures.py checks each README number marked
// <!--f:test:KEY--> against it. Written to <build>/figures/<Suite.Test>.json ($OFFSETMAP_FIGURES
// overrides the folder), rewritten whole at every record.
inline void record_figure(const std::string& key, double value) {
    const char* dir = std::getenv("OFFSETMAP_FIGURES");
    if (!dir || !*dir) dir = OFFSETMAP_FIGURES_DIR;
    static std::map<std::string, std::map<std::string, double>> figures;  // per test
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "none";
    for (char& c : test)
        if (c == '/') c = '_';  // parameterised tests' names hold slashes
    auto& mine = figures[test];
    mine[key] = value;
    std::filesystem::create_directories(dir);
    std::ofstream out(std::string(dir) + "/" + test + ".json");
    out << "{";
    const char* sep = "\n";
    for (const auto& [k, v] : mine) {
        char num[32];
        std::snprintf(num, sizeof num, "%.17g", v);
        out << sep << "  \"" << k << "\": " << num;
        sep = ",\n";
    }
    out << "\n}\n";
}

// What a long run must not grow (soaks): resident memory, and the process's objects a leak of
// OpenCL or GL objects shows in (threads, open files, memory mappings: a driver's buffers and
// loaded kernel builds), from /proc/self.
struct ProcessCounts {
    double rss_kib = 0;
    long threads = 0, files = 0, mappings = 0;
};

inline ProcessCounts process_counts() {
    ProcessCounts c;
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmRSS:", 0) == 0) c.rss_kib = std::atof(line.c_str() + 6);
        if (line.rfind("Threads:", 0) == 0) c.threads = std::atol(line.c_str() + 8);
    }
    for (auto it = std::filesystem::directory_iterator("/proc/self/fd");
         it != std::filesystem::directory_iterator(); ++it)
        ++c.files;
    std::ifstream maps("/proc/self/maps");
    while (std::getline(maps, line)) ++c.mappings;
    return c;
}

// A soak's record: the counts after each frame (or each `frames_per_sample`); checks that from
// sample `settle` on resident
// memory stays within 1 % of its value there and the object counts do not grow at all.
// AddressSanitizer keeps freed memory in a quarantine (256 MiB) and maps its allocator's regions
// as the quarantine fills, so under it resident memory and the mapping count grow over a soak
// without any leak; LeakSanitizer checks leaks in that build instead.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kUnderAsan = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kUnderAsan = true;
#else
inline constexpr bool kUnderAsan = false;
#endif
#else
inline constexpr bool kUnderAsan = false;
#endif

struct Soak {
    int frames_per_sample = 1;
    std::vector<ProcessCounts> frames;
    void sample() { frames.push_back(process_counts()); }
    void check(const std::string& what, size_t settle, const std::string& figure) const {
        ASSERT_GT(frames.size(), settle);
        const ProcessCounts& base = frames[settle - 1];
        double peak = base.rss_kib;
        for (size_t k = settle; k < frames.size(); ++k) {
            const ProcessCounts& f = frames[k];
            peak = std::max(peak, f.rss_kib);
            EXPECT_LE(f.threads, base.threads) << what << ", frame " << k + 1;
            EXPECT_LE(f.files, base.files) << what << ", frame " << k + 1;
            if (!kUnderAsan) {
                EXPECT_LE(f.mappings, base.mappings) << what << ", frame " << k + 1;
            }
        }
        if (!kUnderAsan) {
            EXPECT_LE(peak, 1.01 * base.rss_kib) << what << ": resident memory grew";
        }
        std::printf("%s: resident MiB", what.c_str());
        for (size_t k : {size_t(0), settle - 1, frames.size() / 4, frames.size() / 2,
                         3 * frames.size() / 4, frames.size() - 1})
            std::printf(" %zu:%.1f", (k + 1) * frames_per_sample, frames[k].rss_kib / 1024.0);
        std::printf("; growth after frame %zu: %.2f %%; threads %ld, files %ld, mappings %ld\n",
                    settle * frames_per_sample, 100.0 * (peak / base.rss_kib - 1.0),
                    frames.back().threads, frames.back().files, frames.back().mappings);
        record_figure(figure + ".rss_growth_percent", 100.0 * (peak / base.rss_kib - 1.0));
    }
};

// A device buffer's first n elements, read on the runtime's queue.
template <typename T>
std::vector<T> read_plane(Runtime& rt, const cl::Buffer& b, size_t n) {
    std::vector<T> v(n);
    rt.queue().enqueueReadBuffer(b, CL_TRUE, 0, n * sizeof(T), v.data());
    return v;
}

inline HeightMap make_map(int w, int h, const std::function<float(int, int)>& f) {
    HeightMap m;
    m.width = w;
    m.height = h;
    m.h.resize(static_cast<size_t>(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) m.h[static_cast<size_t>(j) * w + i] = f(i, j);
    return m;
}

inline HeightMap constant_map(float c, int w = 16, int h = 16) {
    return make_map(w, h, [c](int, int) { return c; });
}

// Smooth: a few tiling sines, gentle slopes.
inline HeightMap smooth_map(int n = 64) {
    return make_map(n, n, [n](int i, int j) {
        double u = (i + 0.5) / n, v = (j + 0.5) / n;
        double h = 0.5 + 0.25 * std::sin(2 * M_PI * 2 * u) * std::cos(2 * M_PI * 3 * v) +
                   0.2 * std::sin(2 * M_PI * (u + v));
        return static_cast<float>(std::clamp(h, 0.0, 1.0));
    });
}

// Noisy: independent uniform texels.
inline HeightMap noisy_map(int n = 64, unsigned seed = 11) {
    std::mt19937 rng(seed);
    return make_map(n, n,
                    [&rng](int, int) { return static_cast<float>((rng() >> 8) * 0x1.0p-24); });
}

// Cliffs: 4x4-texel blocks of height 0.1 or 1.0 (vertical walls one texel wide).
inline HeightMap cliff_map(int n = 64, unsigned seed = 5) {
    std::mt19937 rng(seed);
    std::vector<float> block(static_cast<size_t>(n / 4) * (n / 4));
    for (auto& b : block) b = (rng() & 1) ? 1.0f : 0.1f;
    return make_map(n, n, [&](int i, int j) { return block[(j / 4) * (n / 4) + i / 4]; });
}

// Pass settings of a relief `scale` deep with its reference plane at `ref`, tiling.
inline PassSettings wrap_settings(float scale, float ref) {
    PassSettings s;
    s.scale = scale;
    s.reference_plane = ref;
    s.address = AddressMode::Wrap;
    return s;
}

// A G-buffer of explicit (uv, V) pixels in one row.
inline GBuffer row_gbuffer(const std::vector<std::array<float, 5>>& pixels) {
    GBuffer gb;
    gb.resize(static_cast<int>(pixels.size()), 1, false, false);
    for (size_t k = 0; k < pixels.size(); ++k) {
        gb.uv[k] = {{pixels[k][0], pixels[k][1]}};
        gb.view[k] = {{pixels[k][2], pixels[k][3], pixels[k][4], 0.0f}};
    }
    return gb;
}

inline OffsetResult run(const std::string& method, const HeightMap& map, const GBuffer& gb,
                        const PassSettings& settings,
                        const std::map<std::string, std::string>& params = {}) {
    auto rt = runtime();
    DeviceHeightField f = upload(*rt, map, settings);
    DeviceGBuffer g = upload(*rt, gb);
    OffsetPass pass(rt, method, params);
    return run_offset(*rt, pass, g, f, settings, 1);
}

// V at elevation `elev_deg` toward azimuth `az_deg` (from +u toward +v).
inline std::array<float, 3> view_dir(double elev_deg, double az_deg) {
    double e = elev_deg * M_PI / 180, a = az_deg * M_PI / 180;
    return {static_cast<float>(std::cos(e) * std::cos(a)),
            static_cast<float>(std::cos(e) * std::sin(a)), static_cast<float>(std::sin(e))};
}

inline std::vector<std::string> method_names() {
    std::vector<std::string> names;
    for (const auto& m : methods()) names.push_back(m.name);
    return names;
}

// Cell boundaries (lines through texel centres of a w x h grid whose cells are `block` cells
// wide) that the ray's footprint crosses for t in [ta, tb], plus one: the cells it visits. In the
// kernels' frame: wrap traces from the fractional uv, clamp clamps the start cell position to
// +-1e8.
// `float_slack` adds what float positions may shift the count by: at each end a position rounds
// by up to half its float spacing (a few cells at the clamp's 1e8), plus a cell for a point on a
// face that lands in the neighbour.
inline double cells_crossed(const PreparedRay& pr, const PassSettings& s, int w, int h, double ta,
                            double tb, int block = 1, bool float_slack = false) {
    auto axis = [&](double u, double d, int n) {
        if (s.address == AddressMode::Wrap) u -= std::floor(u);
        const double c0 = std::clamp(u * n - 0.5, -1e8, 1e8);  // the start is clamped
        auto pos = [&](double t) { return c0 - t * d * n; };
        double ca = pos(ta), cb = pos(tb);
        double count =
            std::fabs(std::floor(std::floor(cb) / block) - std::floor(std::floor(ca) / block));
        if (float_slack)
            count += 1.0 + std::ceil((std::fabs(ca) + std::fabs(cb)) * 0x1.0p-24 / block);
        return count;
    };
    return axis(pr.u, pr.V[0], w) + axis(pr.v, pr.V[1], h) + 1.0;
}

// The test rows: one per method, in one table (a method without a row fails
// Analytic.EveryMethodHasATestRow).
//  - plane: how far from the exact hit its answer may be on a constant height field, in lambda
//    (the slab from top plane, 0, to bottom plane, 1), for its parameters and a view with this
//    V.z; nullptr: it meets a plane exactly (float rounding).
//  - walk_cap: for the cell walks, the most height fetches a ray may cost, from the ray's
//    geometry rather than the kernels' loop caps (the marching methods' caps are their registry
//    rows', from their documented loop bounds). `exact` reads one patch per cell it enters: the
//    cells crossed, with float rounding's slack (cells_crossed), and +2 more under LOD (a coarser
//    level's cell lines are at most one more per axis than level 0's over the same stretch).
//    `cone`: each step leaves at least one cell or ends, and costs a cone fetch and at most one
//    patch. With `beam` on (cone, maxmip), plus the beam's steps. `maxmip`: each step tests one
//    block (or patch) and then descends a level or leaves the block; a climb follows only a leave,
//    so descents <= top + leaves, and leaves at level k <= the level-k blocks crossed: at most top
//    + 1 + 2 sum_k (blocks_k + 2). `sphere` with cells: a distance fetch per step, a patch per
//    cell, and each return to the cells may solve the cell it left once more: at most 2 steps +
//    cells.
struct WalkRay {
    const PassSettings& s;
    const HeightMap& map;
    const PreparedRay& pr;
    double t_end;  // its hit, or the bottom plane when the hit is not known
    const MethodParams& params;

    double cells(int block = 1) const {
        const double t_enter = -s.scale * (1.0 - s.reference_plane) / pr.V[2];
        return cells_crossed(pr, s, map.width, map.height, t_enter, t_end, block, true) +
               (s.lod.enabled ? 2.0 : 0.0);
    }
    // With `beam` on, the beam's steps count on each of its lanes (common/beam.cl); the walk
    // from its safe start crosses no more cells than from the top.
    double beam_steps() const {
        return params.method->beam && params["beam"] != 0 ? OM_BEAM_STEPS : 0.0;
    }
};

struct TestRow {
    const char* method;
    double (*plane)(const MethodParams& p, double vz) = nullptr;
    double (*walk_cap)(const WalkRay& ray) = nullptr;
};

inline const std::vector<TestRow>& test_rows() {
    static const std::vector<TestRow> rows = {
        {"none"},
        {"parallax"},
        {"parallax-limited"},
        {"parallax-slope"},
        {"parallax-iterative"},
        // The first layer at or below the plane.
        {"steep", [](const MethodParams& p, double) { return 1.0 / p["layers"]; }},
        {"relief", [](const MethodParams& p,
                      double) { return 1.0 / (p["linear"] * std::pow(2.0, p["binary"])); }},
        {"pom"},
        // sphere without cells stops once its voxel meets the plane (one layer), unless its steps
        // run out first: each step covers the box distance, at least the vertical gap less one
        // layer, along the ray, which lowers the gap by V.z of it: the gap left after n steps is
        // <= (1 - V.z)^n. With cells it walks them from there (or once out of steps): exact.
        {"sphere",
         [](const MethodParams& p, double vz) {
             return 1.0 / p["layers"] + std::pow(1.0 - vz, p["steps"]);
         },
         [](const WalkRay& r) { return 2 * r.params["steps"] + r.cells(); }},
        {"secant"},
        {"maxmip", nullptr,
         [](const WalkRay& r) {
             const int top =
                 om_maxmip_levels(r.map.width, r.map.height, static_cast<om_int>(r.s.address));
             double sum = 0;
             for (int k = 0; k <= top; ++k) sum += r.cells(1 << k);
             return top + 1 + 2 * sum + r.beam_steps();
         }},
        {"cone", nullptr, [](const WalkRay& r) { return 2 * r.cells() + r.beam_steps(); }},
        {"exact", nullptr, [](const WalkRay& r) { return r.cells(); }},
    };
    return rows;
}

inline const TestRow& test_row(const std::string& method) {
    for (const auto& row : test_rows())
        if (method == row.method) return row;
    throw Error("no test row for method " + method);
}

// The test row's plane tolerance at the method's defaults.
inline double constant_field_lambda_tolerance(const std::string& method, double vz) {
    const TestRow& row = test_row(method);
    return row.plane ? row.plane(resolve_params(find_method(method), {}), vz) : 0.0;
}

// The most height fetches one ray (prepare_ray's) may cost up to t_end, at the method's defaults
// (or `params`): the registry row's cap, or the test row's for the cell walks.
inline double ray_fetch_cap(const std::string& method, const PassSettings& s, const HeightMap& map,
                            const PreparedRay& pr, double t_end,
                            const std::map<std::string, std::string>& params = {}) {
    const MethodInfo& m = find_method(method);
    const MethodParams p = resolve_params(m, params);
    const double cap = m.fetch_cap(p);
    if (cap >= 0) return cap;
    const TestRow& row = test_row(method);
    if (!row.walk_cap) throw Error("no cell-walk fetch cap in the test row of " + method);
    return row.walk_cap(WalkRay{s, map, pr, t_end, p});
}

// The methods that have a test row, in the table's order.
inline std::vector<std::string> methods_with_rows() {
    std::vector<std::string> names;
    for (const auto& row : test_rows()) names.push_back(row.method);
    return names;
}

}  // namespace omtest
