// The pixel depth offset (core's DepthOffsetPass) alone, no GL context (it also runs under
// Oclgrind): each point moved along its eye ray, against the same steps in double with the same
// float matrices, in every depth convention and row order an engine's camera may have.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/gtc/matrix_transform.hpp>
#include <random>

#include "camera_forms.hpp"
#include "offsetmap/depth_offset_pass.hpp"
#include "support.hpp"

namespace omtest {
namespace {

// GL's float matrices in double: what the expected values are computed with.
glm::dmat4 as_double(const std::array<float, 16>& a) {
    glm::dmat4 m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = a[4 * c + r];
    return m;
}

struct DepthFrame {
    int w = 0, h = 0;
    glm::dmat4 vp;  // world -> GL clip
    std::array<float, 3> eye{};
    bool orthographic = false;
    std::vector<float> depth, t, density;  // GL window depth, rows bottom first
};

// The pass over the frame's planes in `form`: the depth after, in the form's terms (rows and
// convention).
std::vector<float> depth_offset(const DepthFrame& f, const CameraForm& form) {
    auto rt = runtime();
    const size_t bytes = f.depth.size() * sizeof(float);
    DepthOffsetInputs p;
    p.width = f.w;
    p.height = f.h;
    p.camera = form.camera(f.vp);
    p.camera.eye = f.eye;
    p.camera.orthographic = f.orthographic;
    p.view_projection = form.view_projection(f.vp);
    p.depth = device_floats(*rt, form.depth_plane(f.depth, f.w, f.h));
    p.t = device_floats(*rt, form.rows(f.t, f.w, f.h));
    p.density = device_floats(*rt, form.rows(f.density, f.w, f.h));
    cl::Buffer out(rt->context(), CL_MEM_WRITE_ONLY, bytes);
    DepthOffsetPass(rt).enqueue(p, {out}).wait();
    std::vector<float> after(f.depth.size());
    rt->queue().enqueueReadBuffer(out, CL_TRUE, 0, bytes, after.data());
    return after;
}

// Sky and pixels with t = 0, NaN or infinite keep their depth bit for bit, in the form's terms.
bool kept(const DepthFrame& f, size_t k) {
    return f.depth[k] >= 1.0f || !(std::fabs(f.t[k]) > 0.0f) || std::isinf(f.t[k]);
}

// The room's camera (near 0.05, far 50) on a 37 x 23 frame: points 0.5 to 8 m away moved by t in
// [-0.05, 0.05] uv times a density in [0.5, 2]; sky (d = 1) and pixels with t = 0, NaN or infinite
// keep their depth bit for bit. The float steps place P to a few 1e-7 of its distance z (the
// unprojection's terms cancel by about far / near near the far plane); the window depth moves by
// near / z times that relative error (d'(z) = far near / ((far - near) z^2)), under 2e-6 as in the
// rendered frame's own test (Renderer.DepthOffsetIsTheHitsDepth). Each other convention is the
// same NDC points through matrices rounded apart, and reversed depth rounds 1 - d once more
// (6e-8): the same bound.
TEST(DepthOffset, KernelMovesEachPointAlongItsEyeRay) {
    DepthFrame f;
    f.w = 37, f.h = 23;
    const size_t n = static_cast<size_t>(f.w) * f.h;
    f.eye = {0.3f, 1.45f, 1.5f};
    const glm::dvec3 eye(f.eye[0], f.eye[1], f.eye[2]);
    const double near = 0.05, far = 50.0;
    f.vp = glm::perspective(glm::radians(60.0), double(f.w) / f.h, near, far) *
           glm::lookAt(eye, glm::dvec3(-0.1, 0.75, -2.0), glm::dvec3(0, 1, 0));
    std::mt19937 rng(41);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    f.depth.resize(n), f.t.resize(n), f.density.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const double z = 0.5 * std::pow(16.0, unit(rng));  // 0.5 to 8 m
        f.depth[k] = static_cast<float>(
            0.5 * ((far + near) / (far - near) - 2.0 * far * near / ((far - near) * z)) + 0.5);
        f.t[k] = static_cast<float>(0.1 * unit(rng) - 0.05);
        f.density[k] = static_cast<float>(0.5 + 1.5 * unit(rng));
    }
    const float nan = std::numeric_limits<float>::quiet_NaN(),
                inf = std::numeric_limits<float>::infinity();
    f.depth[3] = 1.0f;  // sky
    f.t[5] = 0.0f, f.t[6] = nan, f.t[7] = inf, f.t[8] = -inf;
    const glm::dmat4 vp32 = as_double(CameraForm::floats(f.vp)),
                     inv32 = as_double(CameraForm::floats(glm::inverse(f.vp)));
    for (const CameraForm& form : camera_forms()) {
        SCOPED_TRACE(form.name());
        const std::vector<float> raw = depth_offset(f, form);
        const std::vector<float> before = form.depth_plane(f.depth, f.w, f.h);
        const std::vector<float> after = form.depth_plane_to_gl(raw, f.w, f.h);
        double worst = 0.0;
        for (int y = 0; y < f.h; ++y)
            for (int x = 0; x < f.w; ++x) {
                const size_t k = static_cast<size_t>(y) * f.w + x;
                if (kept(f, k)) {
                    // Its place in the form's rows.
                    const size_t kf = form.first_row == FirstRow::Top
                                          ? static_cast<size_t>(f.h - 1 - y) * f.w + x
                                          : k;
                    EXPECT_EQ(std::memcmp(&raw[kf], &before[kf], sizeof(float)), 0) << k;
                    continue;
                }
                const glm::dvec4 ndc((2.0 * x + 1.0) / f.w - 1.0, (2.0 * y + 1.0) / f.h - 1.0,
                                     2.0 * f.depth[k] - 1.0, 1.0);
                const glm::dvec4 pw = inv32 * ndc;
                const glm::dvec3 p = glm::dvec3(pw) / pw.w;
                const glm::dvec3 q = p - double(f.t[k]) * f.density[k] * glm::normalize(eye - p);
                const glm::dvec4 c = vp32 * glm::dvec4(q, 1.0);
                const double expected = std::clamp(0.5 * c.z / c.w + 0.5, 0.0, 1.0);
                EXPECT_NEAR(after[k], expected, 2e-6) << x << "," << y;
                worst = std::max(worst, std::abs(after[k] - expected));
            }
        std::printf("depth offset kernel, %s: worst depth difference %.2e\n", form.name().c_str(),
                    worst);
    }
}

// A directional light's orthographic view (a shadow map's): every point moves along the one
// direction away from the light, and depth is linear in the distance along it.
TEST(DepthOffset, OrthographicViewMovesEveryPointAlongTheLight) {
    DepthFrame f;
    f.w = 19, f.h = 11;
    const size_t n = static_cast<size_t>(f.w) * f.h;
    const glm::dvec3 L = glm::normalize(glm::dvec3(-0.3, 0.8, 0.5));
    f.vp = glm::ortho(-3.0, 3.0, -2.0, 2.0, 1.0, 12.0) *
           glm::lookAt(6.0 * L, glm::dvec3(0), glm::dvec3(0, 0, 1));
    f.eye = {float(L.x), float(L.y), float(L.z)};
    f.orthographic = true;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    f.depth.resize(n), f.t.resize(n), f.density.resize(n);
    for (size_t k = 0; k < n; ++k) {
        f.depth[k] = static_cast<float>(0.2 + 0.6 * unit(rng));
        f.t[k] = static_cast<float>(0.1 * unit(rng) - 0.05);
        f.density[k] = static_cast<float>(0.5 + 1.5 * unit(rng));
    }
    const glm::dmat4 vp32 = as_double(CameraForm::floats(f.vp)),
                     inv32 = as_double(CameraForm::floats(glm::inverse(f.vp)));
    for (const CameraForm& form : camera_forms()) {
        SCOPED_TRACE(form.name());
        const std::vector<float> after = form.depth_plane_to_gl(depth_offset(f, form), f.w, f.h);
        // Window depth runs over the 11 m between the planes: a move of t density m along L
        // changes it by t density / 11 exactly; float rounding of the matrices and the point, a
        // few 1e-7.
        for (int y = 0; y < f.h; ++y)
            for (int x = 0; x < f.w; ++x) {
                const size_t k = static_cast<size_t>(y) * f.w + x;
                const glm::dvec4 pw =
                    inv32 * glm::dvec4((2.0 * x + 1.0) / f.w - 1.0, (2.0 * y + 1.0) / f.h - 1.0,
                                       2.0 * f.depth[k] - 1.0, 1.0);
                const glm::dvec3 q = glm::dvec3(pw) / pw.w - double(f.t[k]) * f.density[k] * L;
                const glm::dvec4 c = vp32 * glm::dvec4(q, 1.0);
                EXPECT_NEAR(after[k], 0.5 * c.z / c.w + 0.5, 2e-6) << x << "," << y;
                EXPECT_NEAR(after[k] - f.depth[k], double(f.t[k]) * f.density[k] / 11.0, 3e-6) << k;
            }
    }
}

// What the pass refuses before it enqueues anything: a view-projection that is not the camera's
// (an engine that left it unset), a buffer too small for the frame, a convention outside its enum.
TEST(DepthOffset, InconsistentInputsAreRefused) {
    auto rt = runtime();
    const int w = 4, h = 3;
    cl::Buffer b(rt->context(), CL_MEM_READ_WRITE, w * h * sizeof(float));
    DepthOffsetInputs in;
    in.width = w;
    in.height = h;
    const glm::dmat4 vp = glm::perspective(glm::radians(60.0), 4.0 / 3.0, 0.1, 10.0);
    in.camera.inverse_view_projection = CameraForm::floats(glm::inverse(vp));
    in.view_projection = CameraForm::floats(vp);
    in.depth = in.t = in.density = b;
    DepthOffsetPass pass(rt);
    EXPECT_EQ(error_of([&] { pass.enqueue(in, {b}).wait(); }), "");
    DepthOffsetInputs unset = in;
    unset.view_projection = {};
    EXPECT_TRUE(contains(error_of([&] { pass.enqueue(unset, {b}); }), "is not the inverse"));
    DepthOffsetInputs small = in;
    small.density = cl::Buffer(rt->context(), CL_MEM_READ_WRITE, 4);
    EXPECT_TRUE(contains(error_of([&] { pass.enqueue(small, {b}); }), "uv density buffer"));
    DepthOffsetInputs odd = in;
    odd.camera.depth = static_cast<DepthConvention>(7);
    EXPECT_TRUE(contains(error_of([&] { pass.enqueue(odd, {b}); }), "depth convention 7"));
}

}  // namespace
}  // namespace omtest
