// OpenGL objects owned by RAII handles, shader programs from the embedded GLSL files, and the
// checks every GL call site shares. GL 4.5 core entry points come from libOpenGL (glvnd).
#pragma once
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <string>
#include <utility>
#include <vector>

namespace offsetmap::renderer {

// A GL name with its deleter: textures, framebuffers, buffers, vertex arrays, queries, programs.
template <void (*Delete)(GLuint)>
class GlName {
  public:
    GlName() = default;
    explicit GlName(GLuint id) : id_(id) {}
    ~GlName() {
        if (id_) Delete(id_);
    }
    GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    GlName& operator=(GlName&& o) noexcept {
        std::swap(id_, o.id_);
        return *this;
    }
    GLuint get() const { return id_; }

  private:
    GLuint id_ = 0;
};

void delete_texture(GLuint id);
void delete_framebuffer(GLuint id);
void delete_buffer(GLuint id);
void delete_vertex_array(GLuint id);
void delete_query(GLuint id);
void delete_program(GLuint id);
using Texture = GlName<delete_texture>;
using Framebuffer = GlName<delete_framebuffer>;
using BufferObject = GlName<delete_buffer>;
using VertexArray = GlName<delete_vertex_array>;
using Query = GlName<delete_query>;
using Program = GlName<delete_program>;

// A 2D texture of `format` (GL_R32F, GL_RGBA32F, GL_DEPTH_COMPONENT32F, ...), one level.
Texture make_texture(GLenum format, int width, int height);
// A program from the embedded vertex and fragment files, each prefixed by `defines` after the
// version line. Throws Error naming the file and the compiler's log.
Program make_program(const std::string& vertex, const std::string& fragment,
                     const std::string& defines = "");
// Throws Error naming `what` when GL reports an error.
void check_gl(const std::string& what);
GLint uniform(const Program& p, const char* name);

// Reads `components` floats per pixel of a framebuffer attachment (rows bottom first, as GL
// stores them). For the depth attachment pass GL_DEPTH_COMPONENT.
std::vector<float> read_pixels(GLuint framebuffer, GLenum attachment, GLenum format, int components,
                               int width, int height);
// The same into `out` (width x height x the format's components floats): the caller's memory,
// such as a mapped OpenCL buffer, so the pixels are copied once.
void read_pixels_into(GLuint framebuffer, GLenum attachment, GLenum format, int width, int height,
                      float* out);
// A rectangle of them into `out`, its rows `row_length` pixels apart.
void read_pixels_into(GLuint framebuffer, GLenum attachment, GLenum format, int x, int y, int width,
                      int height, int row_length, float* out);

}  // namespace offsetmap::renderer
