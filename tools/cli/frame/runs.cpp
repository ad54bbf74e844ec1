#ifdef OFFSETMAP_HAVE_RENDERER
#include "runs.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>

namespace offsetmap::cli {

using namespace offsetmap::renderer;

std::string run_name(const FrameRun& r) {
    if (r.mode == FrameMode::Deferred)
        return r.layers == 2 ? "deferred-two-layers" : r.curved ? "deferred-curved" : "deferred";
    return r.prepass ? "forward-prepass" : "forward";
}

namespace {

// auto calibrates each material on its own pixels of this frame, so the G-buffer is drawn once
// first (its materials traced with none).
void choose_auto(FrameRequest& r, const std::shared_ptr<Runtime>& rt) {
    if (r.auto_slots.empty()) return;
    const FrameCommand& cmd = *r.cmd;
    FrameRenderer probe(rt, r.scene, r.table, r.methods, cmd.width, cmd.height, r.shading);
    probe.render(FrameMode::Deferred, false, 1);
    for (size_t s : r.auto_slots) {
        const MaterialSpec& spec = r.table[s].spec;
        // With --forward both frames run the same method: one with a GLSL version.
        AutoOptions options;
        if (cmd.forward) {
            options.admits = [](const MethodParams& p) {
                return forward_method_unsupported(p).empty();
            };
            options.admits_text = "with a GLSL version (--forward)";
        }
        const AutoChoice a = choose_method(rt, r.table[s], probe.explicit_gbuffer(), options);
        r.methods[s] = a.chosen.params;
        std::printf(
            "material %d (%s): auto, %s <= %g texels -> %s (of %zu candidates on %zu of its "
            "pixels)\n",
            spec.id, spec.name.c_str(), budget_statistic_name(spec.budget), spec.budget.texels,
            method_text(r.methods[s]).c_str(), a.candidates.size(), a.pixels);
    }
}

void add_run(FrameRuns& f, FrameRun run) {
    f.shown_ids.push_back(run.material);
    f.runs.push_back(std::move(run));
}

// The deferred variants: the tangent plane, the curved base, the layer behind.
void render_deferred(const FrameCommand& cmd, FrameRuns& f) {
    FrameRenderer& renderer = *f.renderer;
    add_run(f, renderer.render(FrameMode::Deferred, false, cmd.repeats));
    f.exact = renderer.exact();
    f.gb = renderer.explicit_gbuffer();
    f.engine = renderer.gbuffer();
    f.covered = renderer.covered_pixels();
    if (cmd.curvature) {
        renderer.set_curvature(true);
        renderer.set_uv_metric(cmd.uv_metric);
        add_run(f, renderer.render(FrameMode::Deferred, false, cmd.repeats));
    }
    if (cmd.layers == 2) {
        renderer.set_layers(2);
        add_run(f, renderer.render(FrameMode::Deferred, false, cmd.repeats));
        std::printf(
            "two layers: %zu pixels show the surface behind, %zu show neither (the "
            "background)\n",
            f.runs.back().behind_pixels, f.runs.back().missed_pixels);
    }
    f.shown_at = f.runs.size() - 1;
}

// The shown frame's mask and the light's maps: the shown run's own with --shadows map, else the
// shown frame once more with the map (its shading is not shown).
void render_sun(const FrameRequest& r, FrameRuns& f) {
    if (!r.sun && !r.spot) return;
    FrameRenderer& renderer = *f.renderer;
    if (r.shadow_map) {
        f.sun = f.runs[f.shown_at];
        f.light_maps = renderer.light_maps();
        return;
    }
    ShadowMapSettings map;
    map.size = r.cmd->shadow_size;
    renderer.set_shadow_map(map);
    f.sun = renderer.render(FrameMode::Deferred, false, 1);
    f.light_maps = renderer.light_maps();
    renderer.set_shadow_map(std::nullopt);
}

// The forward peer, with and without a depth pre-pass (over the curved base with --curvature).
void render_forward(const FrameCommand& cmd, FrameRuns& f) {
    FrameRenderer& renderer = *f.renderer;
    renderer.set_layers(1);
    f.forward_at = f.runs.size();
    if (!cmd.forward) return;
    const std::vector<float>& deferred_uv = f.engine.uv;
    for (bool prepass : {false, true}) {
        add_run(f, renderer.render(FrameMode::Forward, prepass, cmd.repeats));
        // Where the forward shader dropped a fragment (the tile mask, a ray that left the curved
        // base) the pixel shows the surface behind it (flagged BEHIND, as the two-layer frame's),
        // or none after a pre-pass.
        const std::vector<float>& uv = renderer.gbuffer().uv;
        for (size_t k = 0; k < f.gb.pixels(); ++k)
            if (std::memcmp(&uv[2 * k], &deferred_uv[2 * k], 2 * sizeof(float)) != 0)
                f.runs.back().offset.flags[k] |=
                    std::isnan(uv[2 * k]) ? OM_FLAG_EMPTY : OM_FLAG_BEHIND;
    }
}

}  // namespace

FrameRuns render_runs(FrameRequest& r, const std::shared_ptr<Runtime>& rt) {
    const FrameCommand& cmd = *r.cmd;
    choose_auto(r, rt);
    FrameRuns f;
    f.renderer = std::make_unique<FrameRenderer>(rt, r.scene, r.table, r.methods, cmd.width,
                                                 cmd.height, r.shading);
    f.renderer->set_shadow_map(r.shadow_map);
    render_deferred(cmd, f);
    render_sun(r, f);
    render_forward(cmd, f);
    f.renderer->set_curvature(false);
    f.renderer->set_uv_metric(false);
    return f;
}

}  // namespace offsetmap::cli
#endif
