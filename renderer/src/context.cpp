#include "offsetmap/renderer/context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <mutex>

#include "gl.hpp"
#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

namespace {

std::string egl_error() {
    char text[32];
    std::snprintf(text, sizeof text, "EGL error 0x%04x", eglGetError());
    return text;
}

// Every context of the process shares the one surfaceless display, and eglTerminate ends all of
// them: the last context to go terminates it.
std::mutex display_mutex;
int display_users = 0;

}  // namespace

std::unique_ptr<GlContext> GlContext::create() {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client || std::string(client).find("EGL_MESA_platform_surfaceless") == std::string::npos)
        throw Error(
            "OpenGL: EGL offers no surfaceless platform (EGL_MESA_platform_surfaceless); the "
            "renderer needs Mesa's EGL (Debian: libegl-mesa0 libgl1-mesa-dri)");
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display) throw Error("OpenGL: EGL has no eglGetPlatformDisplayEXT");
    EGLDisplay display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor))
        throw Error("OpenGL: cannot open EGL's surfaceless display (" + egl_error() +
                    "); is a Mesa driver installed (Debian: libgl1-mesa-dri)?");
    std::unique_ptr<GlContext> gl(new GlContext);
    {
        std::lock_guard<std::mutex> lock(display_mutex);
        ++display_users;
    }
    gl->display_ = display;
    if (!eglBindAPI(EGL_OPENGL_API)) throw Error("OpenGL: EGL cannot bind the OpenGL API");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT)
        throw Error("OpenGL: the driver gives no OpenGL 4.5 core context (" + egl_error() + ")");
    gl->context_ = context;
    gl->make_current();
    return gl;
}

GlContext::~GlContext() {
    if (context_) {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
    }
    if (display_) {
        std::lock_guard<std::mutex> lock(display_mutex);
        if (--display_users == 0) eglTerminate(display_);
    }
}

void GlContext::make_current() const {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
        throw Error("OpenGL: cannot make the context current (" + egl_error() + ")");
}

std::string GlContext::renderer() const {
    return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}

std::string GlContext::version() const {
    return reinterpret_cast<const char*>(glGetString(GL_VERSION));
}

}  // namespace offsetmap::renderer
