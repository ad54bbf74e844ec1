// The forward methods (parallax, pom, steep, relief) in GLSL as a full-screen pass over an
// explicit G-buffer: the fragment shader's per-pixel cost of the method alone, on the same uv, V
// and height map as the offset kernels, so the two can be timed in turns and their uv' compared.
#pragma once
#include <memory>
#include <string>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/settings.hpp"

namespace offsetmap::renderer {

class GlslPeer {
  public:
    // Creates its GL context (throws Error naming what is missing) and uploads the G-buffer's uv
    // and V (and curvature: traced over the curved base) and the map (level 0, linear, the
    // settings' address mode).
    GlslPeer(const GBuffer& gbuffer, const HeightMap& map, const PassSettings& settings);
    ~GlslPeer();

    // The method to trace; throws Error for one without a GLSL version
    // (forward_method_unsupported).
    void set_method(const MethodParams& method);
    // One full-screen draw, finished: its wall-clock milliseconds.
    double run();
    // The last run's uv', t and fetch count (rows as the G-buffer's; flags 0 where traced, EMPTY
    // where V was not usable, as the forward frame reports them, SILHOUETTE where the ray left a
    // curved base).
    OffsetResult result() const;
    std::string gl_renderer() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace offsetmap::renderer
