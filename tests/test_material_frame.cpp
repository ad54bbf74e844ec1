// The material frame: tiles classified by material, one dispatch per method, each pixel with the
// bits its material's pass alone gives it; shading per material; bad tables and ids refused.
#include <cstring>
#include <limits>
#include <set>
#include <thread>

#include "support.hpp"

namespace omtest {
namespace {

struct TableRow {
    int id;
    std::string method;
    std::map<std::string, std::string> params;
    HeightMap map;
    PassSettings settings;
    bool albedo = false;
};

// Five materials, two pairs sharing a method with other parameters, maps of odd and unequal sizes,
// both address modes, and a method with precomputed data (gathered per method).
std::vector<TableRow> table_rows() {
    std::vector<TableRow> rows;
    PassSettings a;
    rows.push_back({1, "pom", {{"min_samples", "8"}}, smooth_map(64), a, true});
    PassSettings b;
    b.scale = 0.08f;
    b.reference_plane = 0.7f;
    b.address = AddressMode::Clamp;
    rows.push_back(
        {5,
         "pom",
         {{"min_samples", "4"}, {"max_samples", "16"}},
         make_map(37, 29, [](int i, int j) { return 0.5f + 0.4f * std::sin(i * 0.7f + j); }),
         b});
    PassSettings c;
    c.scale = 0.03f;
    rows.push_back({2, "cone", {}, cliff_map(32), c});
    PassSettings d;
    d.grazing = GrazingPolicy::Limit;
    d.heights = HeightStorage::Unorm16;  // the field's words gathered with its floats
    rows.push_back({9, "relief", {}, noisy_map(48), d, true});
    // A second cone material: the method's precomputed data gathered from two maps.
    PassSettings e;
    e.scale = 0.06f;
    rows.push_back({7,
                    "cone",
                    {{"max_ratio", "16"}},
                    make_map(24, 16, [](int i, int j) { return (i / 3 + j / 2) % 3 * 0.4f; }),
                    e});
    return rows;
}

Image4 checker_albedo(int w, int h) {
    Image4 img;
    img.width = w;
    img.height = h;
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            float c = ((i / 4 + j / 4) & 1) ? 0.9f : 0.2f;
            img.texels.push_back({{c, 0.5f, 1.0f - c, 1.0f}});
        }
    return img;
}

// Random views and uv over a w x h frame whose material ids mix: blocks of one material, a band
// where every pixel picks one of all ids at random (tiles of three and more materials), id 0 and
// empty pixels (NaN uv) scattered through both.
GBuffer mixed_gbuffer(int w, int h, const std::vector<int>& ids, unsigned seed = 3) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    GBuffer gb;
    gb.resize(w, h, true, false);
    gb.material.resize(gb.pixels());
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            const double elev = 5.0 + 85.0 * unit(rng), az = 360.0 * unit(rng);
            const auto v = view_dir(elev, az);
            gb.view[k] = {{v[0], v[1], v[2], 0.0f}};
            gb.light[k] = {{0.4f, -0.3f, 0.85f, 0.0f}};
            gb.uv[k] = {{3.0f * unit(rng) - 1.0f, 3.0f * unit(rng) - 1.0f}};
            int id;
            if (y < h / 3)
                id = ids[(x / 21) % ids.size()];  // blocks wider than a tile
            else if (y < 2 * h / 3)
                id = rng() % 5 == 0 ? 0 : ids[rng() % ids.size()];
            else
                id = x < w / 2 ? ids[0] : 0;
            if (rng() % 23 == 0) gb.uv[k].s[0] = std::nanf("");
            gb.material[k] = static_cast<float>(id);
        }
    return gb;
}

struct Table {
    std::vector<TableRow> rows;
    std::vector<DeviceHeightField> fields;
    std::vector<DeviceImage> albedos;
    std::vector<FrameMaterial> materials;
};

Table make_table(Runtime& rt, std::vector<TableRow> rows) {
    Table t;
    t.rows = std::move(rows);
    for (const TableRow& r : t.rows) {
        FrameMaterial m;
        m.id = r.id;
        m.name = r.method + " map";
        m.field = upload(rt, r.map, r.settings);
        m.settings = r.settings;
        m.params = resolve_params(find_method(r.method), r.params);
        if (r.albedo) m.albedo = upload(rt, checker_albedo(r.map.width / 2 + 3, r.map.height / 2));
        t.fields.push_back(m.field);
        t.albedos.push_back(m.albedo);
        t.materials.push_back(m);
    }
    return t;
}

template <typename T>
bool same_bits(const T& a, const T& b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Every pixel of the frame against its material's pass alone, bit for bit.
void expect_each_material_alone(const Table& table, const GBuffer& gb, const OffsetResult& frame) {
    auto rt = runtime();
    DeviceGBuffer g = upload(*rt, gb);
    std::map<int, size_t> checked;
    for (size_t s = 0; s < table.rows.size(); ++s) {
        const TableRow& row = table.rows[s];
        OffsetPass alone(rt, row.method, row.params);
        const OffsetResult ref = run_offset(*rt, alone, g, table.fields[s], row.settings);
        size_t bad = 0;
        for (size_t k = 0; k < gb.pixels(); ++k) {
            if (gb.material[k] != static_cast<float>(row.id)) continue;
            ++checked[row.id];
            if (!same_bits(ref.uv[k], frame.uv[k]) || !same_bits(ref.depth[k], frame.depth[k]) ||
                ref.fetches[k] != frame.fetches[k] || ref.flags[k] != frame.flags[k]) {
                if (++bad <= 3)
                    ADD_FAILURE() << "material " << row.id << " pixel " << k << ": frame uv ("
                                  << frame.uv[k].s[0] << ", " << frame.uv[k].s[1] << ") alone ("
                                  << ref.uv[k].s[0] << ", " << ref.uv[k].s[1] << "), fetches "
                                  << frame.fetches[k] << " vs " << ref.fetches[k];
            }
        }
        EXPECT_EQ(bad, 0u) << "material " << row.id;
        EXPECT_GT(checked[row.id], 0u) << "material " << row.id << " has no pixels";
    }
    size_t none = 0;
    for (size_t k = 0; k < gb.pixels(); ++k) {
        if (gb.material[k] != 0.0f) continue;
        ++none;
        ASSERT_TRUE(same_bits(gb.uv[k], frame.uv[k])) << "id 0 pixel " << k << ": uv' = uv";
        ASSERT_EQ(frame.depth[k], 0.0f);
        ASSERT_EQ(frame.fetches[k], 0u);
        ASSERT_EQ(frame.flags[k], std::isnan(gb.uv[k].s[0]) ? OM_FLAG_EMPTY : 0u);
    }
    EXPECT_GT(none, 0u);
}

TEST(MaterialFrame, EachPixelGetsItsMaterialsPassAloneBitForBit) {
    auto rt = runtime();
    const int lanes = rt->lanes();
    Table table = make_table(*rt, table_rows());
    // 77 x 45: partial tiles at the right and bottom, blocks cut by the image's right and bottom
    // edges and by the tile's bottom. Tile rows 8, 3 and 1 give blocks 4, 2 and 1 rows tall at 16
    // lanes (2, 2, 1 at 8 lanes), an even and an odd count of them per tile for lane pairs.
    const GBuffer gb = mixed_gbuffer(77, 45, {1, 5, 2, 9, 7});
    DeviceGBuffer g = upload(*rt, gb);
    for (int lane_count : {lanes, 8, 1}) {
        rt->set_lanes(lane_count);
        for (int rows : {kDefaultTileRows, 3, 1}) {
            SCOPED_TRACE("lanes " + std::to_string(lane_count) + ", tile rows " +
                         std::to_string(rows));
            MaterialFrame frame(rt, table.materials, rows);
            const OffsetResult r = run_material_frame(*rt, frame, g);
            expect_each_material_alone(table, gb, r);
            // pom, cone and relief: one dispatch each, pom's over both its materials' tiles.
            ASSERT_EQ(frame.dispatches().size(), 3u);
            EXPECT_EQ(frame.dispatches()[0].method->name, "pom");
        }
    }
    rt->set_lanes(lanes);
}

// A material on a tenth of the screen costs a tenth: its dispatch covers only its tiles.
TEST(MaterialFrame, DispatchCoversOnlyTheTilesAMaterialTouches) {
    auto rt = runtime();
    Table table = make_table(*rt, table_rows());
    GBuffer gb = mixed_gbuffer(160, 80, {1});
    for (int y = 0; y < gb.height; ++y)
        for (int x = 0; x < gb.width; ++x)  // material 9 on columns 16..31: 10 % of the screen
            gb.material[static_cast<size_t>(y) * gb.width + x] = x >= 16 && x < 32 ? 9.0f : 1.0f;
    DeviceGBuffer g = upload(*rt, gb);
    MaterialFrame frame(rt, table.materials);
    run_material_frame(*rt, frame, g);
    ASSERT_EQ(frame.dispatches().size(), 2u);
    const size_t tiles = (160 / OM_TILE_W) * (80 / kDefaultTileRows);
    EXPECT_EQ(frame.dispatches()[0].entries, tiles - tiles / 10);  // pom: every other column
    EXPECT_EQ(frame.dispatches()[1].method->name, "relief");
    EXPECT_EQ(frame.dispatches()[1].entries, tiles / 10);
}

TEST(MaterialFrame, ShadesEachMaterialWithItsOwnMaps) {
    auto rt = runtime();
    Table table = make_table(*rt, table_rows());
    const GBuffer gb = mixed_gbuffer(64, 40, {1, 5, 2, 9, 7});
    DeviceGBuffer g = upload(*rt, gb);
    MaterialFrame frame(rt, table.materials);
    const OffsetResult r = run_material_frame(*rt, frame, g);
    ShadeSettings shade;
    shade.shadow = ShadowMode::Soft;
    const size_t n = gb.pixels();
    cl::Buffer uv(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_float2),
                  const_cast<cl_float2*>(r.uv.data()));
    cl::Buffer flags(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(cl_uint),
                     const_cast<std::uint32_t*>(r.flags.data()));
    cl::Buffer rgba(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(cl_float4));
    std::vector<cl_float4> color(n);
    frame.shade(g, {uv, flags}, shade, {rgba}).wait();
    rt->queue().enqueueReadBuffer(rgba, CL_TRUE, 0, n * sizeof(cl_float4), color.data());
    ShadePass alone(rt);
    for (size_t s = 0; s < table.rows.size(); ++s) {
        const TableRow& row = table.rows[s];
        const DeviceImage* albedo = table.albedos[s].texels() ? &table.albedos[s] : nullptr;
        const auto ref = run_shade(*rt, alone, r, g, table.fields[s], albedo, row.settings, shade);
        for (size_t k = 0; k < n; ++k) {
            if (gb.material[k] != static_cast<float>(row.id)) continue;
            ASSERT_TRUE(same_bits(ref[k], color[k])) << "material " << row.id << " pixel " << k;
        }
    }
    // Id 0: flat, as a constant relief without shadows shades it.
    PassSettings flat;
    DeviceHeightField level = upload(*rt, constant_map(0.5f), flat);
    shade.shadow = ShadowMode::None;
    const auto ref = run_shade(*rt, alone, r, g, level, nullptr, flat, shade);
    for (size_t k = 0; k < n; ++k) {
        if (gb.material[k] != 0.0f) continue;
        ASSERT_TRUE(same_bits(ref[k], color[k])) << "id 0 pixel " << k;
    }
}

// Every step chained by events: an out-of-order queue of the context gives the same frame.
TEST(MaterialFrame, AnOutOfOrderQueueGivesTheSameFrame) {
    auto rt = runtime();
    SKIP_WITHOUT_OUT_OF_ORDER_QUEUE(rt->device());
    Table table = make_table(*rt, table_rows());
    const GBuffer gb = mixed_gbuffer(50, 30, {1, 5, 2, 9, 7}, 8);
    DeviceGBuffer g = upload(*rt, gb);
    MaterialFrame frame(rt, table.materials);
    const OffsetResult in_order = run_material_frame(*rt, frame, g);
    cl::CommandQueue ooo(rt->context(), rt->device(), CL_QUEUE_OUT_OF_ORDER_EXEC_MODE_ENABLE);
    const size_t n = gb.pixels();
    OffsetTargets t;
    t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    t.flags = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    cl::Event done = frame.enqueue(g, t, {}, ooo);
    std::vector<cl_float2> uv(n);
    std::vector<std::uint32_t> flags(n);
    const std::vector<cl::Event> after{done};
    ooo.enqueueReadBuffer(t.uv, CL_TRUE, 0, n * sizeof(cl_float2), uv.data(), &after);
    ooo.enqueueReadBuffer(t.flags, CL_TRUE, 0, n * sizeof(cl_uint), flags.data(), &after);
    for (size_t k = 0; k < n; ++k) {
        ASSERT_TRUE(same_bits(uv[k], in_order.uv[k])) << "pixel " << k;
        ASSERT_EQ(flags[k], in_order.flags[k]) << "pixel " << k;
    }
}

TEST(MaterialFrame, RefusesBadTablesAndUnknownIds) {
    auto rt = runtime();
    Table table = make_table(*rt, table_rows());
    auto with = [&](auto change) {
        std::vector<FrameMaterial> m = table.materials;
        change(m);
        return error_of([&] { MaterialFrame frame(rt, m); });
    };
    EXPECT_TRUE(contains(with([](auto& m) { m[2].id = 5; }), "material id 5 appears twice"));
    EXPECT_TRUE(contains(with([](auto& m) { m[1].id = 0; }), "material 0 (pom map): the id"));
    EXPECT_TRUE(contains(with([](auto& m) { m[0].settings.scale = -1; }), "material 1"));
    EXPECT_TRUE(contains(with([](auto& m) { m.clear(); }), "the material table is empty"));
    EXPECT_TRUE(contains(with([](auto& m) { m[3].field = DeviceHeightField(); }),
                         "material 9 (relief map): the height field has not been uploaded"));

    GBuffer gb = mixed_gbuffer(40, 20, {1, 5, 2, 9, 7});
    gb.material[17 * 40 + 33] = 8.0f;
    gb.material[18 * 40 + 2] = 2.5f;
    MaterialFrame frame(rt, table.materials);
    DeviceGBuffer g = upload(*rt, gb);
    OffsetTargets t;
    t.uv = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, gb.pixels() * sizeof(cl_float2));
    EXPECT_TRUE(contains(error_of([&] { frame.enqueue(g, t); }),
                         "material id 8 at pixel (33, 17) has no entry in the material table (2 "
                         "pixels"));
    EXPECT_TRUE(frame.dispatches().empty()) << "nothing is traced";
    g.material = cl::Buffer();
    EXPECT_TRUE(contains(error_of([&] { frame.enqueue(g, t); }), "no material buffer"));
}

// A G-buffer on the device in buffers the frame may write (a layer behind overwrites the first
// layer's planes where it shows), and read-write targets.
DeviceGBuffer writable(Runtime& rt, const GBuffer& gb) {
    DeviceGBuffer d = upload(rt, gb);
    auto copy = [&](cl::Buffer& b) {
        if (!b()) return;
        const size_t bytes = b.getInfo<CL_MEM_SIZE>();
        cl::Buffer w(rt.context(), CL_MEM_READ_WRITE, bytes);
        rt.queue().enqueueCopyBuffer(b, w, 0, 0, bytes);
        b = w;
    };
    for (cl::Buffer* b : {&d.uv, &d.view, &d.light, &d.lod, &d.material, &d.curvature}) copy(*b);
    rt.queue().finish();
    return d;
}

OffsetTargets read_write_targets(Runtime& rt, size_t n) {
    OffsetTargets t;
    t.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
    t.depth = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(float));
    t.fetches = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    t.flags = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
    return t;
}

// A frame with a layer behind: the first layer's tile-masked material over a curved base (rays
// that leave it, uv' off its tile), the second layer other rays and materials with id 0 and empty
// pixels. A pixel the first layer shows is its frame alone's, bit for bit, its planes untouched;
// one it does not show takes the second layer's frame alone's result (flags with BEHIND) and
// planes where that shows a surface, and keeps its own result where that shows none. In one
// enqueue, and in two (the first layer, then the layer behind), in order and out of order.
TEST(MaterialFrame, LayerBehindShowsWhatTheFirstLayerDoesNot) {
    auto rt = runtime();
    std::vector<TableRow> rows = table_rows();
    rows[0].settings.out_of_tile_mask = true;
    Table table = make_table(*rt, rows);
    MaterialFrame frame(rt, table.materials);
    GBuffer first = mixed_gbuffer(77, 45, {1, 5, 9}, 3), second = mixed_gbuffer(77, 45, {2, 7}, 11);
    first.curvature.assign(first.pixels(), {{4.0f, 0.0f, 4.0f, 1.0f}});
    const size_t n = first.pixels();
    const OffsetResult alone1 = run_material_frame(*rt, frame, upload(*rt, first));
    size_t first_entries = 0;
    for (const MaterialFrame::Dispatch& d : frame.dispatches()) first_entries += d.entries;
    const OffsetResult alone2 = run_material_frame(*rt, frame, upload(*rt, second));
    const cl::CommandQueue ooo = out_of_order_queue(rt->context(), rt->device());
    for (int variant : {0, 1, 2}) {
        const bool two_steps = variant > 0;
        SCOPED_TRACE(variant == 0   ? "one enqueue"
                     : variant == 1 ? "enqueue, then enqueue_behind"
                                    : "the two steps on an out-of-order queue, no events passed");
        // In two steps the second layer holds anything at the pixels the first shows (an engine
        // draws it only where needed): NaN, infinities, ids of no material.
        GBuffer drawn = second;
        const float nan = std::nanf(""), inf = std::numeric_limits<float>::infinity();
        for (size_t k = 0; k < n && two_steps; ++k)
            if (!(alone1.flags[k] & OM_FLAGS_SEE_BEHIND)) {
                drawn.uv[k] = {{nan, inf}};
                drawn.view[k] = {{inf, nan, -inf, nan}};
                drawn.material[k] = k % 2 ? nan : 1e30f;
            }
        const DeviceGBuffer g = writable(*rt, first), behind = upload(*rt, drawn);
        const OffsetTargets t = read_write_targets(*rt, n), t2 = read_write_targets(*rt, n);
        if (variant == 2) {
            frame.enqueue(g, t, {}, ooo);
            frame.enqueue_behind(g, t, LayerBehind{behind, t2}, {}, ooo).wait();
        } else if (two_steps) {
            frame.enqueue(g, t);
            frame.enqueue_behind(g, t, LayerBehind{behind, t2}).wait();
        } else {
            frame.enqueue(g, t, LayerBehind{behind, t2}).wait();
        }
        // The second layer's classification lists only the tiles of the pixels it traces: one entry
        // per tile and material among them (id 0 needs none).
        std::set<std::pair<size_t, float> > wanted;
        for (size_t k = 0; k < n; ++k)
            if ((alone1.flags[k] & OM_FLAGS_SEE_BEHIND) && second.material[k] != 0.0f)
                wanted.insert(
                    {k % first.width / OM_TILE_W + k / first.width / kDefaultTileRows * 1000,
                     second.material[k]});
        size_t entries = 0;
        for (const MaterialFrame::Dispatch& d : frame.dispatches()) entries += d.entries;
        EXPECT_EQ(entries - first_entries, wanted.size());
        OffsetResult r;
        r.uv = read_plane<cl_float2>(*rt, t.uv, n);
        r.depth = read_plane<float>(*rt, t.depth, n);
        r.fetches = read_plane<std::uint32_t>(*rt, t.fetches, n);
        r.flags = read_plane<std::uint32_t>(*rt, t.flags, n);
        const auto uv = read_plane<cl_float2>(*rt, g.uv, n);
        const auto view = read_plane<cl_float4>(*rt, g.view, n);
        const auto ids = read_plane<float>(*rt, g.material, n);
        size_t shown = 0, taken = 0, neither = 0;
        for (size_t k = 0; k < n; ++k) {
            SCOPED_TRACE("pixel " + std::to_string(k));
            const bool see_behind = alone1.flags[k] & OM_FLAGS_SEE_BEHIND;
            const bool take = see_behind && !(alone2.flags[k] & OM_FLAGS_NOT_SHOWN);
            const OffsetResult& want = take ? alone2 : alone1;
            const GBuffer& planes = take ? second : first;
            shown += !see_behind;
            taken += take;
            neither += see_behind && !take;
            ASSERT_TRUE(same_bits(r.uv[k], want.uv[k]));
            ASSERT_TRUE(same_bits(r.depth[k], want.depth[k]));
            ASSERT_EQ(r.fetches[k], want.fetches[k]);
            ASSERT_EQ(r.flags[k], want.flags[k] | (take ? OM_FLAG_BEHIND : 0u));
            ASSERT_TRUE(same_bits(uv[k], planes.uv[k]));
            ASSERT_TRUE(same_bits(view[k], planes.view[k]));
            ASSERT_EQ(ids[k], planes.material[k]);
        }
        std::printf(
            "layer behind: %zu pixels shown by the first layer, %zu by the second, %zu by "
            "neither\n",
            shown, taken, neither);
        EXPECT_GT(taken, n / 20);
        EXPECT_GT(neither, 0u);
        EXPECT_GT(shown, n / 4);
    }
    // The layers' sizes must match, and the first layer's flags are what picks its pixels.
    const DeviceGBuffer g = writable(*rt, first), behind = upload(*rt, second);
    const OffsetTargets t = read_write_targets(*rt, n), t2 = read_write_targets(*rt, n);
    GBuffer small = second;
    small.resize(40, 20, true, false);
    small.material.assign(small.pixels(), 2.0f);
    EXPECT_TRUE(contains(error_of([&] {
                             frame.enqueue(g, t, LayerBehind{upload(*rt, small), t2});
                         }),
                         "the layer behind is 40x20; the G-buffer is 77x45"));
    EXPECT_TRUE(contains(error_of([&] {
                             frame.enqueue_behind(g, t, LayerBehind{upload(*rt, small), t2});
                         }),
                         "the layer behind is 40x20; the G-buffer is 77x45"));
    OffsetTargets no_flags = t;
    no_flags.flags = cl::Buffer();
    EXPECT_TRUE(contains(error_of([&] {
                             frame.enqueue(g, no_flags, LayerBehind{behind, t2});
                         }),
                         "needs the offset pass's flags output"));
}

// One frame of the material frame and its shade on `queue`, into `t` and `rgba` (reused), read
// back: uv' and colour.
struct FrameOut {
    std::vector<cl_float2> uv;
    std::vector<cl_float4> rgba;
    bool operator==(const FrameOut& o) const {
        return uv.size() == o.uv.size() && rgba.size() == o.rgba.size() &&
               std::memcmp(uv.data(), o.uv.data(), uv.size() * sizeof(cl_float2)) == 0 &&
               std::memcmp(rgba.data(), o.rgba.data(), rgba.size() * sizeof(cl_float4)) == 0;
    }
};

struct FrameTargets {
    OffsetTargets t;
    cl::Buffer rgba;
    FrameTargets(Runtime& rt, size_t n) {
        t.uv = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float2));
        t.flags = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_uint));
        rgba = cl::Buffer(rt.context(), CL_MEM_READ_WRITE, n * sizeof(cl_float4));
    }
};

void one_frame(MaterialFrame& frame, const DeviceGBuffer& g, FrameTargets& ft,
               const cl::CommandQueue& queue, FrameOut* out) {
    const size_t n = static_cast<size_t>(g.width) * g.height;
    ShadeSettings shade;
    shade.shadow = ShadowMode::Hard;
    const cl::Event offset = frame.enqueue(g, ft.t, {}, queue);
    const cl::Event shaded =
        frame.shade(g, frame_shade_inputs(ft.t), shade, {ft.rgba}, {offset}, queue);
    if (out) {
        out->uv.resize(n);
        out->rgba.resize(n);
        const std::vector<cl::Event> after{shaded};
        queue.enqueueReadBuffer(ft.t.uv, CL_FALSE, 0, n * sizeof(cl_float2), out->uv.data(),
                                &after);
        queue.enqueueReadBuffer(ft.rgba, CL_FALSE, 0, n * sizeof(cl_float4), out->rgba.data(),
                                &after);
    }
    queue.finish();
}

// 500 frames on one runtime, buffers reused: resident memory flat after 10 frames (within 1 %),
// no thread, file or mapping more; every frame the first one.
TEST(Soak, MaterialFrame500FramesHoldMemoryFlat) {
    auto rt = runtime();
    Table table = make_table(*rt, table_rows());
    const GBuffer gb = mixed_gbuffer(160, 90, {1, 5, 2, 9, 7}, 4);
    const DeviceGBuffer g = upload(*rt, gb);
    MaterialFrame frame(rt, table.materials);
    FrameTargets ft(*rt, gb.pixels());
    FrameOut first, each;
    Soak soak;
    for (int k = 0; k < 500; ++k) {
        one_frame(frame, g, ft, rt->queue(), k == 0 ? &first : (k % 50 == 49 ? &each : nullptr));
        if (k % 50 == 49) {
            EXPECT_TRUE(each == first) << "frame " << k + 1;
        }
        soak.sample();
    }
    soak.check("material frame 160x90, 5 materials, 500 frames", 10, "soak.material_frame");
}

// Two threads, each with its own queue and frame objects on one runtime, run their frames at the
// same time: each gets, every frame, what one thread alone gets.
TEST(Soak, TwoThreadsOnTwoQueuesGiveOneThreadsFrames) {
    auto rt = runtime();
    Table table = make_table(*rt, table_rows());
    const GBuffer gba = mixed_gbuffer(96, 60, {1, 5, 2, 9, 7}, 11),
                  gbb = mixed_gbuffer(96, 60, {7, 9, 1}, 12);
    const DeviceGBuffer ga = upload(*rt, gba), gb = upload(*rt, gbb);
    FrameOut alone_a, alone_b;
    {
        MaterialFrame frame(rt, table.materials);
        FrameTargets ft(*rt, gba.pixels());
        one_frame(frame, ga, ft, rt->queue(), &alone_a);
        one_frame(frame, gb, ft, rt->queue(), &alone_b);
    }
    ASSERT_FALSE(alone_a == alone_b);
    auto worker = [&](const DeviceGBuffer* g, const FrameOut* expected, int* mismatches) {
        const cl::CommandQueue queue(rt->context(), rt->device());
        MaterialFrame frame(rt, table.materials);
        FrameTargets ft(*rt, gba.pixels());
        FrameOut out;
        for (int k = 0; k < 40; ++k) {
            one_frame(frame, *g, ft, queue, &out);
            *mismatches += !(out == *expected);
        }
    };
    int bad_a = 0, bad_b = 0;
    std::thread a(worker, &ga, &alone_a, &bad_a), b(worker, &gb, &alone_b, &bad_b);
    a.join();
    b.join();
    EXPECT_EQ(bad_a, 0) << "thread A's frames that differ from one thread's";
    EXPECT_EQ(bad_b, 0) << "thread B's frames that differ from one thread's";
}

}  // namespace
}  // namespace omtest
