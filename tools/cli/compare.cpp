// `offsetmap compare`: every method on one scene: shaded PNG, uv-error and fetch-count heat maps
// per method, a labelled contact sheet, and a table of accuracy against `exact` and kernel time.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli.hpp"

namespace offsetmap::cli {

int run_compare(const std::string& out_dir, const ReliefOptions& relief,
                const ShadingOptions& shading, const SceneOptions& scene, int repeats) {
    scene.check();
    PassSettings settings = relief.settings();
    HeightMap map = load_height_map(relief.height_map, relief.load_options());
    GBuffer gb = scene.make();
    if (shading.light.size() == 3) gb.light.clear();  // an explicit light wins
    const ShadingOptions::Files files = shading.read_files();
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec) throw Error("cannot create output folder '" + out_dir + "': " + ec.message());

    auto rt = Runtime::create(relief.device);
    show_progress(*rt);
    DeviceHeightField field = upload(*rt, map, settings, files.normal_map());
    DeviceGBuffer dg = upload(*rt, gb);
    DeviceImage dalbedo;
    const DeviceImage* albedo_in = files.upload_albedo(*rt, dalbedo);
    ShadePass shade(rt);
    ShadeSettings ss = shading.shade_settings();

    OffsetPass exact_pass(rt, "exact");
    OffsetResult exact = run_offset(*rt, exact_pass, dg, field, settings, 1);

    const size_t traced_n = traced_pixels(exact);
    std::printf("offsetmap compare: %s (%dx%d, s = %g, r = %g) on %s, %s (%dx%d, %zu traced)\n",
                relief.height_map.c_str(), map.width, map.height, settings.scale,
                settings.reference_plane, rt->device_name().c_str(), scene.describe().c_str(),
                gb.width, gb.height, traced_n);
    if (traced_n == 0)
        std::printf(
            "no pixel is traced (every pixel is empty, back-facing or invalid): the "
            "errors and fetch counts below are not defined\n");
    std::printf("%-18s %10s %10s %10s %14s %10s %16s\n", "method", "mean err", "p95 err",
                ">1 texel", "fetches/pixel", "ns/pixel", "precomputed");
    std::vector<std::pair<std::string, Rgb8>> tiles;
    nlohmann::json table = nlohmann::json::array();
    for (const auto& m : methods()) {
        OffsetPass pass(rt, m.name);
        OffsetResult r = run_offset(*rt, pass, dg, field, settings, repeats + 1);
        r.kernel_ms.erase(r.kernel_ms.begin());  // the first launch includes PoCL's kernel JIT
        std::vector<float> err;
        ErrorStats st = uv_error(r, exact, map.width, map.height, &err);
        const double fetches = mean_fetches(r);
        double ns = r.median_kernel_ms() * 1e6 / static_cast<double>(gb.pixels());
        const auto& pre = pass.precomputed();
        char precomputed[64] = "-";
        if (pre.bytes)
            std::snprintf(precomputed, sizeof precomputed, "%.1f MB, %.0f ms",
                          pre.bytes / 1048576.0, pre.build_ms);
        if (st.count)
            std::printf("%-18s %10.4f %10.4f %9.2f%% %14.2f %10.2f %16s\n", m.name.c_str(), st.mean,
                        st.p95, 100.0 * st.wrong_share, fetches, ns, precomputed);
        else
            std::printf("%-18s %10s %10s %10s %14s %10.2f %16s\n", m.name.c_str(), "-", "-", "-",
                        "-", ns, precomputed);

        Rgb8 color = to_srgb8(gb.width, gb.height,
                              run_shade(*rt, shade, r, dg, field, albedo_in, settings, ss));
        Rgb8 heat = heat_map(gb.width, gb.height, err, 16.0f);
        std::vector<float> fetch_map(r.fetches.size());
        for (size_t k = 0; k < r.fetches.size(); ++k)
            fetch_map[k] = traced(r.flags[k]) ? static_cast<float>(r.fetches[k])
                                              : std::numeric_limits<float>::quiet_NaN();
        Rgb8 cost = heat_map(gb.width, gb.height, fetch_map, 256.0f);
        write_image(out_dir + "/" + m.name + ".png", color);
        write_image(out_dir + "/" + m.name + "-error.png", heat);
        write_image(out_dir + "/" + m.name + "-fetches.png", cost);
        char label[160];
        std::snprintf(label, sizeof label, "%s   mean %.2f / p95 %.2f texels", m.name.c_str(),
                      st.mean, st.p95);
        tiles.emplace_back(label, color);
        tiles.emplace_back(m.name + ": uv error (log, white = 16 texels)", heat);
        char fetch_label[160];
        std::snprintf(fetch_label, sizeof fetch_label, "%s: fetches (log, white = 256), mean %.1f",
                      m.name.c_str(), fetches);
        tiles.emplace_back(fetch_label, cost);
        table.push_back({{"method", m.name},
                         {"mean_err_texels", st.mean},
                         {"p95_err_texels", st.p95},
                         {"max_err_texels", st.max},
                         {"wrong_surface_share", st.wrong_share},
                         {"fetches_per_pixel", fetches},
                         {"ns_per_pixel", ns},
                         {"precomputed_bytes", pass.precomputed().bytes},
                         {"precompute_ms", pass.precomputed().build_ms}});
    }
    write_image(out_dir + "/contact-sheet.png", contact_sheet(tiles, 6));  // two methods a row
    nlohmann::json summary = {{"device", rt->device_name()},
                              {"height_map", relief.height_map},
                              {"gbuffer_source", scene.describe()},
                              {"traced_pixels", traced_n},
                              {"scale", settings.scale},
                              {"reference_plane", settings.reference_plane},
                              {"width", gb.width},
                              {"height", gb.height},
                              {"methods", table}};
    std::ofstream(out_dir + "/summary.json") << summary.dump(2) << "\n";
    std::printf(
        "wrote %s/{<method>.png, <method>-error.png, <method>-fetches.png, contact-sheet.png, "
        "summary.json}\n",
        out_dir.c_str());
    return 0;
}

}  // namespace offsetmap::cli
