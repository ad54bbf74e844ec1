#ifdef OFFSETMAP_HAVE_RENDERER
#include "report.hpp"

#include <cstdio>

namespace offsetmap::cli {

using namespace offsetmap::renderer;

namespace {

// The modes table's name: `forward + pre-pass` for frame.json's forward-prepass.
std::string mode_name(const FrameRun& r) {
    return r.mode == FrameMode::Forward && r.prepass ? "forward + pre-pass" : run_name(r);
}

nlohmann::json material_rows(const FrameRequest& q, const std::vector<MaterialError>& stats) {
    nlohmann::json mats = nlohmann::json::array();
    for (size_t s = 0; s < q.table.size(); ++s)
        mats.push_back({{"id", q.table[s].spec.id},
                        {"name", q.table[s].spec.name},
                        {"method", q.methods[s].method->name},
                        {"method_text", method_text(q.methods[s])},
                        {"auto", q.table[s].spec.method == "auto"},
                        {"pixels", stats[s].pixels},
                        {"fetches_per_pixel", stats[s].fetches},
                        {"mean_err_texels", stats[s].error.mean},
                        {"p95_err_texels", stats[s].error.p95},
                        {"max_err_texels", stats[s].error.max}});
    return mats;
}

// A run's row: its passes, its overdraw, its materials against exact on the first layer (only
// where the frame shows the first layer's surface).
nlohmann::json mode_row(const FrameRequest& q, const FrameRuns& f, const FrameRun& r,
                        std::vector<float>& err) {
    const double overdraw = f.covered ? double(r.shaded_fragments) / double(f.covered) : 0.0;
    std::printf("%-22s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %10.2f\n",
                mode_name(r).c_str(), r.ms.gbuffer, r.ms.to_device, r.ms.reconstruct, r.ms.offset,
                r.ms.shade, r.ms.depth_offset, r.ms.to_gl, r.ms.total, overdraw);
    OffsetResult first_layer = r.offset;
    for (std::uint32_t& flags : first_layer.flags)
        if (flags & OM_FLAG_BEHIND) flags |= OM_FLAG_EMPTY;
    const std::vector<MaterialError> stats =
        material_errors(f.gb, first_layer, f.exact, q.table, &err);
    nlohmann::json mode = {{"mode", mode_name(r)},
                           {"passes", pass_json(r)},
                           {"offset_kernel_ms", r.offset_kernel_ms},
                           {"shaded_fragments", r.shaded_fragments},
                           {"shaded_fragments_per_covered_pixel", overdraw},
                           {"materials", material_rows(q, stats)}};
    const size_t projected = r.projections[0] + r.projections[1] + r.projections[2];
    if (projected > 0)
        mode["triplanar"] = {{"pixels", projected},
                             {"one_projection", r.projections[0]},
                             {"two_projections", r.projections[1]},
                             {"three_projections", r.projections[2]}};
    return mode;
}

// Each material's error against exact, a column a run.
void print_error_table(const FrameRequest& q, const FrameRuns& f, const nlohmann::json& modes) {
    std::printf("%4s %-10s %-10s %8s", "id", "material", "method", "pixels");
    for (const FrameRun& r : f.runs)
        std::printf("  %s", r.mode == FrameMode::Deferred ? (r.layers == 2 ? "2 layers mean/p95"
                                                             : r.curved    ? "curved mean/p95"
                                                                           : "deferred mean/p95")
                            : r.prepass                   ? "fwd+pre mean/p95"
                                                          : "forward mean/p95");
    std::printf("  (texels vs exact)\n");
    for (size_t s = 0; s < q.table.size(); ++s) {
        std::printf("%4d %-10s %-10s %8zu", q.table[s].spec.id, q.table[s].spec.name.c_str(),
                    q.methods[s].method->name.c_str(),
                    modes[0]["materials"][s]["pixels"].get<size_t>());
        for (size_t r = 0; r < f.runs.size(); ++r)
            std::printf("  %8.4f /%7.4f", modes[r]["materials"][s]["mean_err_texels"].get<double>(),
                        modes[r]["materials"][s]["p95_err_texels"].get<double>());
        std::printf("\n");
    }
}

// Triplanar pixels by the projections traced: one grey, two orange, three red; the frame dimmed
// beneath.
Rgb8 projections_picture(int w, int h, const FrameRun& run) {
    Rgb8 picture = to_srgb8(w, h, run.color);
    const std::uint8_t shade[4][3] = {{0, 0, 0}, {150, 150, 150}, {245, 150, 40}, {220, 40, 40}};
    for (size_t k = 0; k < run.projection_count.size(); ++k) {
        const int c = static_cast<int>(run.projection_count[k]);
        for (int i = 0; i < 3; ++i) {
            std::uint8_t& v = picture.rgb[3 * k + i];
            v = c == 0 ? std::uint8_t(v / 3) : std::uint8_t((v + 2 * shade[c][i]) / 3);
        }
    }
    return picture;
}

}  // namespace

nlohmann::json modes_section(const FrameRequest& q, const FrameRuns& f, Runtime& rt,
                             std::vector<std::vector<float> >& errors) {
    const FrameCommand& cmd = *q.cmd;
    const FrameRun& deferred = f.runs[0];
    std::printf("frame: %s scene %dx%d, %zu materials; GL: %s; OpenCL: %s; %s\n",
                q.scene.name.c_str(), cmd.width, cmd.height, q.table.size(),
                f.renderer->gl_renderer().c_str(), rt.device_name().c_str(),
                f.renderer->interop().c_str());
    if (const std::array<size_t, 3>& p = deferred.projections; p[0] + p[1] + p[2] > 0) {
        const double all = double(p[0] + p[1] + p[2]);
        std::printf(
            "triplanar: %zu pixels, traced in one projection %.1f %%, two %.1f %%, three %.1f %%\n",
            p[0] + p[1] + p[2], 100.0 * p[0] / all, 100.0 * p[1] / all, 100.0 * p[2] / all);
    }
    std::printf("%-22s %9s %9s %9s %9s %9s %9s %9s %9s %10s\n", "mode", "G-buffer", "to CL",
                "reconstr", "offset", "shade", "depth off", "to GL", "total", "frag/px");
    nlohmann::json modes = nlohmann::json::array();
    errors.resize(f.runs.size());
    for (size_t r = 0; r < f.runs.size(); ++r)
        modes.push_back(mode_row(q, f, f.runs[r], errors[r]));
    print_error_table(q, f, modes);
    return modes;
}

Tiles write_frame_pictures(const FrameRequest& q, const FrameRuns& f,
                           const std::vector<std::vector<float> >& errors) {
    const FrameCommand& cmd = *q.cmd;
    const int w = cmd.width, h = cmd.height;
    const std::string d = cmd.out_dir + "/";
    const FrameRun& deferred = f.runs[0];
    const FrameRun& shown = f.runs[f.shown_at];
    write_image(d + "final.png", to_srgb8(w, h, shown.color));
    save_engine_gbuffer(d + "gbuffer.exr", f.engine);
    write_depth_exr(d + "depth-before.exr", w, h, f.engine.depth);
    write_depth_exr(d + "depth-after.exr", w, h, shown.depth_after);
    Tiles tiles = {
        {"deferred frame (offset pass on the OpenCL device)", to_srgb8(w, h, deferred.color)},
        {"uv error vs exact (log, white = 16 texels)", heat_map(w, h, errors[0], 16.0f)},
        {"depth offset written back (log, white = 16e-4)",
         depth_change_image(w, h, f.engine.depth, deferred.depth_after)}};
    if (!deferred.projection_count.empty()) {
        const Rgb8 picture = projections_picture(w, h, deferred);
        write_image(d + "triplanar.png", picture);
        tiles.push_back(
            {"triplanar projections traced: one (grey), two (orange), three (red)", picture});
    }
    if (cmd.curvature)
        tiles.push_back(
            {"deferred over the curved base (--curvature; rays that leave the relief "
             "show the background)",
             to_srgb8(w, h, f.runs[1].color)});
    if (cmd.layers == 2)
        tiles.push_back(
            {"deferred with the layer behind (--layers 2): what the rays that leave "
             "show",
             to_srgb8(w, h, shown.color)});
    if (cmd.forward) {
        const FrameRun& forward = f.runs[f.forward_at];
        write_image(d + "final-forward.png", to_srgb8(w, h, forward.color));
        tiles.push_back(
            {"forward frame (the methods in the fragment shader)", to_srgb8(w, h, forward.color)});
        tiles.push_back({"forward uv error vs exact", heat_map(w, h, errors[f.forward_at], 16.0f)});
    }
    return tiles;
}

}  // namespace offsetmap::cli
#endif
