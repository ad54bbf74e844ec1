// An OpenGL 4.5 core context without a window: EGL's surfaceless platform (Mesa's llvmpipe on a
// machine without a GPU, the GPU's driver where there is one), current on the creating thread.
#pragma once
#include <memory>
#include <string>

namespace offsetmap::renderer {

class GlContext {
  public:
    // Throws Error naming what is missing: the EGL library's surfaceless platform, a display, an
    // OpenGL 4.5 core context.
    static std::unique_ptr<GlContext> create();
    ~GlContext();
    GlContext(const GlContext&) = delete;
    GlContext& operator=(const GlContext&) = delete;

    std::string renderer() const;  // GL_RENDERER
    std::string version() const;   // GL_VERSION
    // Makes this context current on the calling thread.
    void make_current() const;

  private:
    GlContext() = default;
    void* display_ = nullptr;
    void* context_ = nullptr;
};

}  // namespace offsetmap::renderer
