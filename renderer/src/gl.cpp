#include "gl.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "offsetmap/error.hpp"

namespace offsetmap {
const std::vector<std::pair<std::string, std::string>>& embedded_shaders();
}

namespace offsetmap::renderer {

void delete_texture(GLuint id) { glDeleteTextures(1, &id); }
void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
void delete_query(GLuint id) { glDeleteQueries(1, &id); }
void delete_program(GLuint id) { glDeleteProgram(id); }

void check_gl(const std::string& what) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        char text[32];
        std::snprintf(text, sizeof text, "0x%04x", e);
        throw Error("OpenGL: " + what + " failed (GL error " + text + ")");
    }
}

Texture make_texture(GLenum format, int width, int height) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    Texture t(id);
    glTextureStorage2D(id, 1, format, width, height);
    glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    check_gl("a " + std::to_string(width) + "x" + std::to_string(height) + " texture");
    return t;
}

namespace {

// The shader's text: the embedded copy, or with OFFSETMAP_SHADER_DIR set that folder's file (as
// OFFSETMAP_KERNEL_DIR does for the kernels: the mutation check plants its GLSL bugs in a copy
// there instead of rebuilding the renderer for each).
std::string shader_text(const std::string& file) {
    if (const char* dir = std::getenv("OFFSETMAP_SHADER_DIR"); dir && *dir) {
        const std::string path = std::string(dir) + "/" + file;
        std::ifstream in(path, std::ios::binary);
        if (!in)
            throw Error("OpenGL: cannot read shader '" + path + "' (OFFSETMAP_SHADER_DIR is set)");
        std::ostringstream text;
        text << in.rdbuf();
        return text.str();
    }
    for (const auto& [name, text] : embedded_shaders())
        if (name == file) return text;
    throw Error("OpenGL: no embedded shader '" + file + "'");
}

// The file's text with `#include "name"` lines replaced by the named file (one level).
std::string expand(const std::string& file) {
    std::string out;
    const std::string text = shader_text(file);
    size_t pos = 0;
    while (pos < text.size()) {
        size_t end = text.find('\n', pos);
        if (end == std::string::npos) end = text.size();
        const std::string line = text.substr(pos, end - pos);
        if (line.rfind("#include \"", 0) == 0)
            out += shader_text(line.substr(10, line.size() - 11)) + "\n";
        else
            out += line + "\n";
        pos = end + 1;
    }
    return out;
}

GLuint compile(GLenum kind, const std::string& file, const std::string& defines) {
    const std::string version = "#version 450 core\n";
    const std::string text = version + defines + "#line 1\n" + expand(file);
    const GLuint s = glCreateShader(kind);
    const char* src = text.c_str();
    glShaderSource(s, 1, &src, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetShaderInfoLog(s, sizeof log, nullptr, log);
        glDeleteShader(s);
        throw Error("OpenGL: shader '" + file + "' does not compile: " + log);
    }
    return s;
}

}  // namespace

Program make_program(const std::string& vertex, const std::string& fragment,
                     const std::string& defines) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertex, defines);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragment, defines);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    Program p(glCreateProgram());
    glAttachShader(p.get(), vs);
    glAttachShader(p.get(), fs);
    glLinkProgram(p.get());
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(p.get(), GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[4096] = {};
        glGetProgramInfoLog(p.get(), sizeof log, nullptr, log);
        throw Error("OpenGL: program '" + vertex + "' + '" + fragment + "' does not link: " + log);
    }
    return p;
}

GLint uniform(const Program& p, const char* name) { return glGetUniformLocation(p.get(), name); }

std::vector<float> read_pixels(GLuint framebuffer, GLenum attachment, GLenum format, int components,
                               int width, int height) {
    std::vector<float> out(static_cast<size_t>(width) * height * components);
    read_pixels_into(framebuffer, attachment, format, width, height, out.data());
    return out;
}

void read_pixels_into(GLuint framebuffer, GLenum attachment, GLenum format, int width, int height,
                      float* out) {
    read_pixels_into(framebuffer, attachment, format, 0, 0, width, height, width, out);
}

void read_pixels_into(GLuint framebuffer, GLenum attachment, GLenum format, int x, int y, int width,
                      int height, int row_length, float* out) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    if (format != GL_DEPTH_COMPONENT) glReadBuffer(attachment);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glPixelStorei(GL_PACK_ROW_LENGTH, row_length == width ? 0 : row_length);
    glReadPixels(x, y, width, height, format, GL_FLOAT, out);
    glPixelStorei(GL_PACK_ROW_LENGTH, 0);
    check_gl("reading back the G-buffer");
}

}  // namespace offsetmap::renderer
