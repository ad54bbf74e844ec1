#include "raster.hpp"

#include <cstddef>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <limits>

#include "offsetmap/error.hpp"

namespace offsetmap::renderer {

namespace {

std::array<float, 16> to_array(const glm::mat4& m) {
    std::array<float, 16> a{};
    const float* p = glm::value_ptr(m);
    std::copy(p, p + 16, a.begin());
    return a;
}

const GLenum kTargets[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                           GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4, GL_COLOR_ATTACHMENT5,
                           GL_COLOR_ATTACHMENT6, GL_COLOR_ATTACHMENT7};
constexpr int kTargetCount = 8;  // GL 4.5 guarantees 8 draw buffers

}  // namespace

int glsl_method(const MethodInfo& method) {
    return method.glsl.empty() ? -1 : static_cast<int>(&method - methods().data());
}

std::string glsl_method_defines() {
    std::string out;
    for (const MethodInfo& m : methods())
        if (!m.glsl.empty())
            out += "#define OM_GLSL_" + m.glsl + " " + std::to_string(glsl_method(m)) + "\n";
    return out;
}

ForwardMaterial forward_material(int id, const HeightMap& map, const PassSettings& settings,
                                 const MethodParams& method, const Triplanar& triplanar) {
    ForwardMaterial f;
    f.id = id;
    if (triplanar.enabled)
        f.triplanar = {triplanar.world_scale, triplanar.sharpness, triplanar.cutoff, 1.0f};
    f.method = glsl_method(*method.method);
    for (size_t k = 0; k < method.values.size() && k < 4; ++k) f.params[k] = method.values[k];
    f.scale = settings.scale;
    f.ref = settings.reference_plane;
    f.min_vz = grazing_rule(settings, map.width, map.height).min_vz;
    f.limit = settings.grazing == GrazingPolicy::Limit;
    f.tile_mask = settings.out_of_tile_mask;
    f.tile_bounds = kernel_tile_bounds(settings);
    f.heights = make_texture(GL_R32F, map.width, map.height);
    glTextureSubImage2D(f.heights.get(), 0, 0, 0, map.width, map.height, GL_RED, GL_FLOAT,
                        map.h.data());
    const GLint address = settings.address == AddressMode::Wrap ? GL_REPEAT : GL_CLAMP_TO_EDGE;
    glTextureParameteri(f.heights.get(), GL_TEXTURE_WRAP_S, address);
    glTextureParameteri(f.heights.get(), GL_TEXTURE_WRAP_T, address);
    glTextureParameteri(f.heights.get(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(f.heights.get(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    check_gl("the height texture of material " + std::to_string(id));
    return f;
}

void bind_forward_material(const Program& p, const ForwardMaterial* fm) {
    static const int no_relief = glsl_method(find_method("none"));
    glUniform1i(uniform(p, "u_method"), fm ? fm->method : no_relief);
    if (!fm) return;
    glBindTextureUnit(0, fm->heights.get());
    glUniform1i(uniform(p, "u_heights"), 0);
    glUniform4fv(uniform(p, "u_params"), 1, fm->params.data());
    glUniform1f(uniform(p, "u_scale"), fm->scale);
    glUniform1f(uniform(p, "u_ref"), fm->ref);
    glUniform1f(uniform(p, "u_min_vz"), fm->min_vz);
    glUniform1i(uniform(p, "u_limit"), fm->limit ? 1 : 0);
    glUniform1i(uniform(p, "u_tile_mask"), fm->tile_mask ? 1 : 0);
    glUniform4fv(uniform(p, "u_tile_bounds"), 1, fm->tile_bounds.data());
    glUniform4fv(uniform(p, "u_triplanar"), 1, fm->triplanar.data());
}

View make_view(const Camera& c, int width, int height) {
    const glm::vec3 eye(c.eye[0], c.eye[1], c.eye[2]),
        target(c.target[0], c.target[1], c.target[2]);
    // Both matrices in double: the inverse is what the reconstruct pass places pixels with. Up is
    // +y, or +z for a view straight up or down (a light overhead), where +y is no up.
    const glm::dvec3 toward = glm::normalize(glm::dvec3(eye) - glm::dvec3(target));
    const glm::dvec3 up = std::abs(toward.y) > 0.9999 ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    const glm::dmat4 view = glm::lookAt(glm::dvec3(eye), glm::dvec3(target), up);
    const double aspect = double(width) / double(height);
    const double hh = c.ortho_half_height;
    const glm::dmat4 projection = c.orthographic
                                      ? glm::ortho(-hh * aspect, hh * aspect, -hh, hh,
                                                   double(c.near_plane), double(c.far_plane))
                                      : glm::perspective(glm::radians(double(c.fov_y_deg)), aspect,
                                                         double(c.near_plane), double(c.far_plane));
    const glm::dmat4 vp = projection * view;
    View v;
    v.view_projection = to_array(glm::mat4(vp));
    v.inverse_view_projection = to_array(glm::mat4(glm::inverse(vp)));
    v.eye = c.orthographic ? Vec3{float(toward.x), float(toward.y), float(toward.z)} : c.eye;
    v.orthographic = c.orthographic;
    return v;
}

Raster::Raster(const Scene& scene, int width, int height) : width_(width), height_(height) {
    for (const Mesh& m : scene.meshes) {
        if (m.indices.empty()) continue;  // GL takes no empty buffer (a mesh culled away)
        DrawMesh d;
        d.material = m.material;
        GLuint ids[3];
        glCreateVertexArrays(1, ids);
        glCreateBuffers(2, ids + 1);
        d.vao = VertexArray(ids[0]);
        d.vertices = BufferObject(ids[1]);
        d.indices = BufferObject(ids[2]);
        glNamedBufferStorage(ids[1], m.vertices.size() * sizeof(Vertex), m.vertices.data(), 0);
        glNamedBufferStorage(ids[2], m.indices.size() * sizeof(std::uint32_t), m.indices.data(), 0);
        glVertexArrayVertexBuffer(ids[0], 0, ids[1], 0, sizeof(Vertex));
        glVertexArrayElementBuffer(ids[0], ids[2]);
        const struct {
            GLint size;
            size_t offset;
        } attributes[] = {{3, offsetof(Vertex, position)},       {3, offsetof(Vertex, normal)},
                          {4, offsetof(Vertex, tangent)},        {2, offsetof(Vertex, uv)},
                          {1, offsetof(Vertex, uv_density)},     {3, offsetof(Vertex, curvature)},
                          {1, offsetof(Vertex, uv_log_stretch)}, {3, offsetof(Vertex, dpdu)},
                          {3, offsetof(Vertex, dpdv)},           {3, offsetof(Vertex, gamma_u)},
                          {3, offsetof(Vertex, gamma_v)}};
        for (GLuint a = 0; a < 11; ++a) {
            glEnableVertexArrayAttrib(ids[0], a);
            glVertexArrayAttribFormat(ids[0], a, attributes[a].size, GL_FLOAT, GL_FALSE,
                                      static_cast<GLuint>(attributes[a].offset));
            glVertexArrayAttribBinding(ids[0], a, 0);
        }
        d.count = static_cast<GLsizei>(m.indices.size());
        meshes_.push_back(std::move(d));
    }
    const std::string methods = glsl_method_defines();  // relief.glsl's, in every G-buffer shader
    deferred_ = make_program("gbuffer_vert.glsl", "gbuffer_frag.glsl", methods);
    forward_ =
        make_program("gbuffer_vert.glsl", "gbuffer_frag.glsl", methods + "#define OM_FORWARD 1\n");
    deferred_count_ =
        make_program("gbuffer_vert.glsl", "gbuffer_frag.glsl", methods + "#define OM_COUNT 1\n");
    forward_count_ = make_program("gbuffer_vert.glsl", "gbuffer_frag.glsl",
                                  methods + "#define OM_FORWARD 1\n#define OM_COUNT 1\n");
    depth_only_ = make_program("gbuffer_vert.glsl", "depth_only_frag.glsl");
    deferred_peel_ =
        make_program("gbuffer_vert.glsl", "gbuffer_frag.glsl", methods + "#define OM_PEEL 1\n");
    glProgramUniform1i(deferred_peel_.get(), uniform(deferred_peel_, "u_front_depth"), 1);
    peel_depth_ = make_program("gbuffer_vert.glsl", "peel_depth_frag.glsl");
    glProgramUniform1i(peel_depth_.get(), uniform(peel_depth_, "u_front_depth"), 1);
    peel_mask_ = make_program("peel_mask_vert.glsl", "peel_mask_frag.glsl");
    metric_program_ = make_program("gbuffer_vert.glsl", "uv_metric_frag.glsl");
    glProgramUniform1i(peel_mask_.get(), uniform(peel_mask_, "u_width"), width);
    glProgramUniform2f(peel_mask_.get(), uniform(peel_mask_, "u_size"), float(width),
                       float(height));
    {
        GLuint ids[2];
        glCreateVertexArrays(1, ids);
        glCreateBuffers(1, ids + 1);
        mask_vao_ = VertexArray(ids[0]);
        mask_pixels_ = BufferObject(ids[1]);
        glVertexArrayVertexBuffer(ids[0], 0, ids[1], 0, 2 * sizeof(std::uint32_t));
        glEnableVertexArrayAttrib(ids[0], 0);
        glVertexArrayAttribIFormat(ids[0], 0, 2, GL_UNSIGNED_INT, 0);
        glVertexArrayAttribBinding(ids[0], 0, 0);
        glVertexArrayBindingDivisor(ids[0], 0, 1);
    }

    depth_ = make_texture(GL_DEPTH_COMPONENT32F, width, height);
    normal_ = make_texture(GL_RGBA32F, width, height);
    tangent_ = make_texture(GL_RGBA32F, width, height);
    uv_ = make_texture(GL_RG32F, width, height);
    derivatives_ = make_texture(GL_RGBA32F, width, height);
    material_ = make_texture(GL_RG32F, width, height);
    offset_ = make_texture(GL_RGBA32F, width, height);
    offset2_ = make_texture(GL_RGBA32F, width, height);
    curvature_ = make_texture(GL_RGBA32F, width, height);
    color_ = make_texture(GL_RGBA32F, width, height);
    for (Texture& t : metric_) t = make_texture(GL_RGBA32F, width, height);
    depth_after_ = make_texture(GL_DEPTH_COMPONENT32F, width, height);
    GLuint f[3];
    glCreateFramebuffers(3, f);
    fbo_ = Framebuffer(f[0]);
    depth_fbo_ = Framebuffer(f[1]);
    metric_fbo_ = Framebuffer(f[2]);
    const GLenum metric_targets[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1,
                                      GL_COLOR_ATTACHMENT2};
    for (int i = 0; i < 3; ++i)
        glNamedFramebufferTexture(f[2], metric_targets[i], metric_[i].get(), 0);
    glNamedFramebufferTexture(f[2], GL_DEPTH_ATTACHMENT, depth_.get(), 0);
    glNamedFramebufferDrawBuffers(f[2], 3, metric_targets);
    const GLuint colour[] = {normal_.get(),   tangent_.get(), uv_.get(),        derivatives_.get(),
                             material_.get(), offset_.get(),  curvature_.get(), offset2_.get()};
    for (int i = 0; i < kTargetCount; ++i)
        glNamedFramebufferTexture(f[0], kTargets[i], colour[i], 0);
    glNamedFramebufferTexture(f[0], GL_DEPTH_ATTACHMENT, depth_.get(), 0);
    glNamedFramebufferTexture(f[1], GL_DEPTH_ATTACHMENT, depth_after_.get(), 0);
    glNamedFramebufferDrawBuffer(f[1], GL_NONE);
    glNamedFramebufferReadBuffer(f[1], GL_NONE);
    glNamedFramebufferDrawBuffers(f[0], kTargetCount, kTargets);
    for (GLuint fb : f)
        if (glCheckNamedFramebufferStatus(fb, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw Error("OpenGL: the G-buffer's render targets are not complete at " +
                        std::to_string(width) + "x" + std::to_string(height));
    GLuint counter = 0;
    glCreateBuffers(1, &counter);
    counter_ = BufferObject(counter);
    glNamedBufferStorage(counter, sizeof(GLuint), nullptr,
                         GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    check_gl("setting up the G-buffer pass");
}

void Raster::draw(const View& view, const std::vector<ForwardMaterial>* forward, bool prepass,
                  bool derivatives, bool curvature, bool curved) {
    // The targets this draw keeps: the uv derivatives and the curvature only when asked (the
    // file keeps them), the offset plane only forward. A target set to GL_NONE is neither
    // cleared nor written.
    GLenum targets[kTargetCount];
    std::copy(std::begin(kTargets), std::end(kTargets), targets);
    if (!derivatives) targets[3] = GL_NONE;
    if (!forward) targets[5] = targets[7] = GL_NONE;
    if (!curvature) targets[6] = GL_NONE;
    glNamedFramebufferDrawBuffers(fbo_.get(), kTargetCount, targets);
    draw_with(view, forward, prepass, forward ? forward_ : deferred_, curved);
    glNamedFramebufferDrawBuffers(fbo_.get(), kTargetCount, kTargets);
}

void Raster::draw_behind(const View& view, const Raster& front, bool curvature,
                         const std::vector<std::uint32_t>* pixels) {
    if (front.width_ != width_ || front.height_ != height_)
        throw Error("the second layer's raster is not the size of the first's");
    GLenum targets[kTargetCount];
    std::copy(std::begin(kTargets), std::end(kTargets), targets);
    targets[3] = targets[5] = targets[7] = GL_NONE;
    if (!curvature) targets[6] = GL_NONE;
    glNamedFramebufferDrawBuffers(fbo_.get(), kTargetCount, targets);
    // The scissor is the context's: off again however the draw ends.
    struct ScissorOff {
        ~ScissorOff() { glDisable(GL_SCISSOR_TEST); }
    } scissor_off;
    if (pixels) {
        // No clear: the clear's values and a depth at the far plane are written at those pixels
        // alone (a rectangle a run along a row), and the depth is 0 elsewhere, which no fragment
        // passes: cleared once (and after a whole layer), then only the last call's runs closed
        // again. Nothing is drawn outside the pixels' bounding box, whose tiles the raster then
        // skips. (A box per cluster costs a pass over the vertices each, more than the tiles it
        // skips.) The peel's test against the first layer's depth is a discard, which costs
        // llvmpipe its early depth test (every fragment in the box is shaded): it runs in a
        // depth-only pass, and the G-buffer follows at GL_EQUAL without one, as after a forward
        // depth pre-pass.
        glViewport(0, 0, width_, height_);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_.get());
        // The pixels' bounding box, and the pixels as runs along their rows (first, length).
        int x0 = width_, y0 = height_, x1 = -1, y1 = -1;
        std::vector<std::uint32_t> runs;
        for (std::uint32_t k : *pixels) {
            const int x = static_cast<int>(k % width_), y = static_cast<int>(k / width_);
            x0 = std::min(x0, x);
            x1 = std::max(x1, x);
            y0 = std::min(y0, y);
            y1 = std::max(y1, y);
            if (!runs.empty() && k == runs[runs.size() - 2] + runs.back() && x != 0)
                ++runs.back();
            else
                runs.insert(runs.end(), {k, 1u});
        }
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        glDepthMask(GL_TRUE);
        glDisable(GL_CULL_FACE);
        glUseProgram(peel_mask_.get());
        glBindVertexArray(mask_vao_.get());
        if (!peel_closed_) {
            const float near = 0.0f;
            glClearNamedFramebufferfv(fbo_.get(), GL_DEPTH, 0, &near);
            peel_closed_ = true;
        } else if (open_runs_ > 0) {
            glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
            glUniform1f(uniform(peel_mask_, "u_depth"), -1.0f);
            glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, open_runs_);
            glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        }
        glEnable(GL_SCISSOR_TEST);
        glScissor(x0, y0, std::max(0, x1 - x0 + 1), std::max(0, y1 - y0 + 1));
        glNamedBufferData(mask_pixels_.get(), runs.size() * sizeof(std::uint32_t), runs.data(),
                          GL_STREAM_DRAW);
        open_runs_ = static_cast<GLsizei>(runs.size() / 2);
        glUniform1f(uniform(peel_mask_, "u_depth"), 1.0f);
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, open_runs_);
    }
    glBindTextureUnit(1, front.depth_.get());
    if (pixels) {
        draw_with(view, nullptr, true, deferred_, false, false, &peel_depth_);
    } else {
        draw_with(view, nullptr, false, deferred_peel_, false, true);
        peel_closed_ = false;
    }
    glBindTextureUnit(1, 0);
    glNamedFramebufferDrawBuffers(fbo_.get(), kTargetCount, kTargets);
}

std::int64_t Raster::count_fragments(const View& view, const std::vector<ForwardMaterial>* forward,
                                     bool prepass, bool curved) {
    const GLuint zero = 0;
    glNamedBufferSubData(counter_.get(), 0, sizeof zero, &zero);
    glBindBufferBase(GL_ATOMIC_COUNTER_BUFFER, 0, counter_.get());
    draw_with(view, forward, prepass, forward ? forward_count_ : deferred_count_, curved);
    GLuint count = 0;
    glGetNamedBufferSubData(counter_.get(), 0, sizeof count, &count);
    check_gl("counting the G-buffer pass's fragments");
    return count;
}

void Raster::set_scissor(const PixelRegion* region) {
    scissor_.reset();
    if (region) scissor_ = *region;
}

namespace {

// Back faces culled, counter-clockwise in front; a light's (orthographic) view keeps them: a
// single-sided wall the light sees from behind still casts its shadow (the offset pass flags them
// BACKFACING and leaves their depth).
void cull_for(const View& view) {
    if (view.orthographic || view.two_sided)
        glDisable(GL_CULL_FACE);
    else
        glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
}

}  // namespace

void Raster::draw_with(const View& view, const std::vector<ForwardMaterial>* forward, bool prepass,
                       const Program& program, bool curved, bool clear,
                       const Program* prepass_program) {
    glViewport(0, 0, width_, height_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo_.get());
    // The clears too keep to the scissor; off again however the draw ends.
    struct ScissorOff {
        ~ScissorOff() { glDisable(GL_SCISSOR_TEST); }
    } scissor_off;
    if (scissor_) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(scissor_->x, scissor_->y, scissor_->width, scissor_->height);
    }
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float sky_uv[4] = {nan, nan, 0.0f, 0.0f}, zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < kTargetCount && clear; ++i)
        glClearNamedFramebufferfv(fbo_.get(), GL_COLOR, i, i == 2 || i == 5 ? sky_uv : zero);
    if (clear) glClearNamedFramebufferfi(fbo_.get(), GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glEnable(GL_DEPTH_TEST);
    cull_for(view);
    auto draw_meshes = [&](const Program& p, bool with_materials) {
        glUseProgram(p.get());
        glUniformMatrix4fv(uniform(p, "u_view_projection"), 1, GL_FALSE,
                           view.view_projection.data());
        if (with_materials && forward) {
            glUniform3f(uniform(p, "u_eye"), view.eye[0], view.eye[1], view.eye[2]);
            glUniform1i(uniform(p, "u_curved"), curved ? 1 : 0);
            glUniform1i(uniform(p, "u_metric"), forward_metric_ ? 1 : 0);
        }
        for (const DrawMesh& m : meshes_) {
            if (with_materials) {
                glUniform1f(uniform(p, "u_material"), float(m.material));
                if (forward) {
                    const ForwardMaterial* fm = nullptr;
                    for (const ForwardMaterial& f : *forward)
                        if (f.id == m.material) fm = &f;
                    bind_forward_material(p, fm);
                }
            }
            glBindVertexArray(m.vao.get());
            glDrawElements(GL_TRIANGLES, m.count, GL_UNSIGNED_INT, nullptr);
        }
    };
    if (prepass) {
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        draw_meshes(prepass_program ? *prepass_program : depth_only_, false);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthFunc(GL_EQUAL);
        glDepthMask(GL_FALSE);
    } else {
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
    }
    draw_meshes(program, true);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glFinish();
    check_gl(forward ? "the forward G-buffer pass" : "the G-buffer pass");
}

void Raster::draw_metric(const View& view) {
    glViewport(0, 0, width_, height_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, metric_fbo_.get());
    const float zero[4] = {0, 0, 0, 0};
    for (int i = 0; i < 3; ++i) glClearNamedFramebufferfv(metric_fbo_.get(), GL_COLOR, i, zero);
    glEnable(GL_DEPTH_TEST);
    cull_for(view);
    glDepthFunc(GL_EQUAL);
    glDepthMask(GL_FALSE);
    glUseProgram(metric_program_.get());
    glUniformMatrix4fv(uniform(metric_program_, "u_view_projection"), 1, GL_FALSE,
                       view.view_projection.data());
    for (const DrawMesh& m : meshes_) {
        glBindVertexArray(m.vao.get());
        glDrawElements(GL_TRIANGLES, m.count, GL_UNSIGNED_INT, nullptr);
    }
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glFinish();
    check_gl("the uv metric's draw");
}

std::vector<float> Raster::read_metric() const {
    std::vector<float> out(12 * static_cast<size_t>(width_) * height_);
    read_metric_into(out.data());
    return out;
}

void Raster::read_metric_into(float* out, const std::vector<PixelRegion>* regions) const {
    const size_t n = static_cast<size_t>(width_) * height_;
    const std::vector<PixelRegion> whole{{0, 0, width_, height_}};
    for (const PixelRegion& r : regions ? *regions : whole)
        for (int i = 0; i < 3; ++i)
            read_pixels_into(metric_fbo_.get(), GL_COLOR_ATTACHMENT0 + i, GL_RGBA, r.x, r.y,
                             r.width, r.height, width_,
                             out + 4 * (n * i + static_cast<size_t>(r.y) * width_ + r.x));
}

RasterPlanes Raster::read(bool forward) const {
    RasterPlanes p;
    const GLuint f = fbo_.get();
    p.depth = read_pixels(f, GL_NONE, GL_DEPTH_COMPONENT, 1, width_, height_);
    p.normal = read_pixels(f, GL_COLOR_ATTACHMENT0, GL_RGBA, 4, width_, height_);
    p.tangent = read_pixels(f, GL_COLOR_ATTACHMENT1, GL_RGBA, 4, width_, height_);
    p.uv = read_pixels(f, GL_COLOR_ATTACHMENT2, GL_RG, 2, width_, height_);
    p.material = read_pixels(f, GL_COLOR_ATTACHMENT4, GL_RG, 2, width_, height_);
    if (forward) p.offset = read_pixels(f, GL_COLOR_ATTACHMENT5, GL_RGBA, 4, width_, height_);
    return p;
}

std::vector<float> Raster::read_offset() const {
    return read_pixels(fbo_.get(), GL_COLOR_ATTACHMENT5, GL_RGBA, 4, width_, height_);
}

std::vector<float> Raster::read_offset_yz() const {
    return read_pixels(fbo_.get(), GL_COLOR_ATTACHMENT7, GL_RGBA, 4, width_, height_);
}

void Raster::read_into(const PlanePointers& p, const std::vector<PixelRegion>* regions) const {
    const GLuint f = fbo_.get();
    const std::vector<PixelRegion> whole{{0, 0, width_, height_}};
    for (const PixelRegion& r : regions ? *regions : whole) {
        auto read = [&](GLenum attachment, GLenum format, int components, float* out) {
            read_pixels_into(f, attachment, format, r.x, r.y, r.width, r.height, width_,
                             out + (static_cast<size_t>(r.y) * width_ + r.x) * components);
        };
        read(GL_NONE, GL_DEPTH_COMPONENT, 1, p.depth);
        read(GL_COLOR_ATTACHMENT0, GL_RGBA, 4, p.normal);
        read(GL_COLOR_ATTACHMENT1, GL_RGBA, 4, p.tangent);
        read(GL_COLOR_ATTACHMENT2, GL_RG, 2, p.uv);
        read(GL_COLOR_ATTACHMENT4, GL_RED, 1, p.material);
        read(GL_COLOR_ATTACHMENT4, GL_GREEN, 1, p.density);
        if (p.curvature) read(GL_COLOR_ATTACHMENT6, GL_RGBA, 4, p.curvature);
    }
}

std::vector<float> Raster::read_uv_derivatives() const {
    return read_pixels(fbo_.get(), GL_COLOR_ATTACHMENT3, GL_RGBA, 4, width_, height_);
}

std::vector<float> Raster::read_curvature() const {
    return read_pixels(fbo_.get(), GL_COLOR_ATTACHMENT6, GL_RGBA, 4, width_, height_);
}

void Raster::write_results(const float* color, const float* depth_after) {
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTextureSubImage2D(color_.get(), 0, 0, 0, width_, height_, GL_RGBA, GL_FLOAT, color);
    glTextureSubImage2D(depth_after_.get(), 0, 0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT,
                        depth_after);
    glFinish();
    check_gl("writing the frame's colour and depth to GL");
}

std::vector<float> Raster::depth_after() const {
    return read_pixels(depth_fbo_.get(), GL_NONE, GL_DEPTH_COMPONENT, 1, width_, height_);
}

}  // namespace offsetmap::renderer
