// The material frame on the device: three materials (one with precomputed data, one clamped), id 0
// and empty pixels, each pixel against its material's pass alone, bit for bit.
#include <cmath>
#include <cstring>
#include <limits>

#include "check.hpp"

namespace offsetmap::check {
namespace {

struct Row {
    int id;
    const char* method;
    HeightMap map;
    PassSettings settings;
};

HeightMap wave_map(int w, int h, double fu, double fv) {
    HeightMap m;
    m.width = w;
    m.height = h;
    m.h.resize(static_cast<size_t>(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            m.h[static_cast<size_t>(j) * w + i] = static_cast<float>(
                0.5 + 0.45 * std::sin(fu * (i + 0.5) / w * 2 * M_PI) * std::cos(fv * j / 3.0));
    return m;
}

template <typename T>
bool same_bits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

void check_material_frame(const std::shared_ptr<Runtime>& rt, const Options& o,
                          DeviceReport& report) {
    CaseResult out;
    out.kernel = "material frame";
    out.name = "pom, cone, relief; ids 0, 2, 5, 9, empty pixels";
    out.measure = "pixels unlike their material's pass";
    try {
        std::vector<Row> rows;
        rows.push_back({2, "pom", wave_map(64, 64, 3, 1), PassSettings{}});
        PassSettings clamped;
        clamped.address = AddressMode::Clamp;
        clamped.scale = 0.08f;
        rows.push_back({5, "cone", wave_map(45, 31, 2, 2), clamped});
        PassSettings words;
        words.heights = HeightStorage::Unorm16;
        words.reference_plane = 0.6f;
        rows.push_back({9, "relief", wave_map(32, 48, 5, 1), words});
        std::vector<FrameMaterial> table;
        std::vector<DeviceHeightField> fields;
        for (const Row& r : rows) {
            FrameMaterial m;
            m.id = r.id;
            m.name = r.method;
            m.field = upload(*rt, r.map, r.settings);
            m.settings = r.settings;
            m.params = resolve_params(find_method(r.method), {});
            fields.push_back(m.field);
            table.push_back(m);
        }
        // 83 x 41: partial tiles and blocks at the right and bottom; the ids in runs and mixed.
        GBuffer gb = make_scene(RandomScene{83, o.quick ? 21 : 41, 77, 5.0, 90.0});
        gb.material.resize(gb.pixels());
        const int ids[] = {0, 2, 5, 9};
        for (size_t k = 0; k < gb.pixels(); ++k) {
            const int x = static_cast<int>(k % gb.width), y = static_cast<int>(k / gb.width);
            gb.material[k] = static_cast<float>(y < gb.height / 2 ? ids[(x / 20) % 4]
                                                                  : ids[(x * 7 + y * 13) % 4]);
            if (k % 29 == 0) gb.uv[k].s[0] = std::numeric_limits<float>::quiet_NaN();
        }
        const DeviceGBuffer g = upload(*rt, gb);
        MaterialFrame frame(rt, table);
        const OffsetResult got = run_material_frame(*rt, frame, g);
        size_t bad = 0;
        auto wrong = [&](size_t k, const std::string& what) {
            if (bad++ == 0) out.worst_pixel = pixel_name(k, gb.width) + ": " + what;
        };
        for (size_t r = 0; r < rows.size(); ++r) {
            OffsetPass alone(rt, table[r].params);
            const OffsetResult want = run_offset(*rt, alone, g, fields[r], rows[r].settings);
            for (size_t k = 0; k < gb.pixels(); ++k) {
                if (gb.material[k] != static_cast<float>(rows[r].id)) continue;
                ++out.pixels;
                if (!same_bits(got.uv[k], want.uv[k]) || !same_bits(got.depth[k], want.depth[k]) ||
                    got.fetches[k] != want.fetches[k] || got.flags[k] != want.flags[k])
                    wrong(k, "material " + std::to_string(rows[r].id) + " (" + rows[r].method +
                                 ") differs from its pass alone");
            }
        }
        for (size_t k = 0; k < gb.pixels(); ++k) {
            if (gb.material[k] != 0.0f) continue;
            ++out.pixels;
            const std::uint32_t flags = std::isnan(gb.uv[k].s[0]) ? OM_FLAG_EMPTY : 0u;
            if (!same_bits(got.uv[k], gb.uv[k]) || got.depth[k] != 0.0f || got.fetches[k] != 0 ||
                got.flags[k] != flags)
                wrong(k, "id 0 must pass uv through with depth 0, no fetches");
        }
        out.worst = static_cast<double>(bad);
        out.passed = bad == 0;
    } catch (const std::exception& e) {
        out.passed = false;
        out.worst_pixel = std::string("no result: ") + e.what();
    }
    report.cases.push_back(out);
}

}  // namespace offsetmap::check
