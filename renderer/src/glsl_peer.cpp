#include "offsetmap/renderer/glsl_peer.hpp"

#include <cmath>

#include "offsetmap/error.hpp"
#include "offsetmap/renderer/context.hpp"
#include "offsetmap/renderer/frame.hpp"
#include "offsetmap/timing.hpp"
#include "raster.hpp"

namespace offsetmap::renderer {

struct GlslPeer::Impl {
    std::unique_ptr<GlContext> gl;
    int width = 0, height = 0;
    HeightMap map;
    PassSettings settings;
    ForwardMaterial material;
    Program program;
    Texture uv, view, curvature, offset;
    Framebuffer fbo;
    VertexArray empty_vao;
};

GlslPeer::GlslPeer(const GBuffer& gbuffer, const HeightMap& map, const PassSettings& settings)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.gl = GlContext::create();
    m.width = gbuffer.width;
    m.height = gbuffer.height;
    m.map = map;
    m.settings = settings;
    m.program = make_program("fullscreen_vert.glsl", "peer_frag.glsl", glsl_method_defines());
    m.uv = make_texture(GL_RG32F, m.width, m.height);
    glTextureSubImage2D(m.uv.get(), 0, 0, 0, m.width, m.height, GL_RG, GL_FLOAT, gbuffer.uv.data());
    m.view = make_texture(GL_RGBA32F, m.width, m.height);
    glTextureSubImage2D(m.view.get(), 0, 0, 0, m.width, m.height, GL_RGBA, GL_FLOAT,
                        gbuffer.view.data());
    if (gbuffer.has_curvature()) {
        m.curvature = make_texture(GL_RGBA32F, m.width, m.height);
        glTextureSubImage2D(m.curvature.get(), 0, 0, 0, m.width, m.height, GL_RGBA, GL_FLOAT,
                            gbuffer.curvature.data());
    }
    m.offset = make_texture(GL_RGBA32F, m.width, m.height);
    GLuint fbo = 0, vao = 0;
    glCreateFramebuffers(1, &fbo);
    m.fbo = Framebuffer(fbo);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, m.offset.get(), 0);
    glCreateVertexArrays(1, &vao);
    m.empty_vao = VertexArray(vao);
    if (glCheckNamedFramebufferStatus(fbo, GL_DRAW_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("OpenGL: the full-screen peer's target is incomplete");
    check_gl("setting up the full-screen peer");
}

GlslPeer::~GlslPeer() = default;

std::string GlslPeer::gl_renderer() const { return impl_->gl->renderer(); }

void GlslPeer::set_method(const MethodParams& method) {
    if (const std::string why = forward_method_unsupported(method); !why.empty())
        throw Error("the GLSL peer: " + why);
    Impl& m = *impl_;
    m.gl->make_current();
    m.material = forward_material(1, m.map, m.settings, method);
}

double GlslPeer::run() {
    Impl& m = *impl_;
    m.gl->make_current();
    glFinish();
    const Stopwatch clock;
    glViewport(0, 0, m.width, m.height);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m.fbo.get());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(m.program.get());
    bind_forward_material(m.program, &m.material);
    glBindTextureUnit(1, m.uv.get());
    glUniform1i(uniform(m.program, "u_uv"), 1);
    glBindTextureUnit(2, m.view.get());
    glUniform1i(uniform(m.program, "u_view"), 2);
    glUniform1i(uniform(m.program, "u_curved"), m.curvature.get() != 0);
    if (m.curvature.get()) {
        glBindTextureUnit(3, m.curvature.get());
        glUniform1i(uniform(m.program, "u_curvature"), 3);
    }
    glBindVertexArray(m.empty_vao.get());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glFinish();
    const double ms = clock.total();
    check_gl("the full-screen peer's draw");
    return ms;
}

OffsetResult GlslPeer::result() const {
    const Impl& m = *impl_;
    m.gl->make_current();
    const std::vector<float> px =
        read_pixels(m.fbo.get(), GL_COLOR_ATTACHMENT0, GL_RGBA, 4, m.width, m.height);
    OffsetResult r;
    r.width = m.width;
    r.height = m.height;
    const size_t n = static_cast<size_t>(m.width) * m.height;
    r.uv.resize(n);
    r.depth.resize(n);
    r.fetches.resize(n);
    r.flags.resize(n);
    for (size_t k = 0; k < n; ++k) {
        r.uv[k] = {{px[4 * k], px[4 * k + 1]}};
        r.depth[k] = px[4 * k + 2];
        r.fetches[k] = static_cast<std::uint32_t>(std::abs(px[4 * k + 3]));
        r.flags[k] = std::isnan(px[4 * k])  ? OM_FLAG_EMPTY
                     : px[4 * k + 3] < 0.0f ? OM_FLAG_SILHOUETTE
                                            : 0u;
    }
    return r;
}

}  // namespace offsetmap::renderer
