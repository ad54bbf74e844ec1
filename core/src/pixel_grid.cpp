#include "pixel_grid.hpp"

#include <algorithm>
#include <cmath>

#include "offsetmap/error.hpp"

namespace offsetmap {

bool finite(const float* v, size_t n) {
    for (size_t k = 0; k < n; ++k)
        if (!std::isfinite(v[k])) return false;
    return true;
}

void check_camera(const EngineCamera& cam, const std::string& what) {
    if (cam.depth != DepthConvention::GL && cam.depth != DepthConvention::ZeroToOne &&
        cam.depth != DepthConvention::Reversed)
        throw Error(what + "'s depth convention " + std::to_string(static_cast<int>(cam.depth)) +
                    " is not GL, zero-one or reversed");
    if (cam.first_row != FirstRow::Top && cam.first_row != FirstRow::Bottom)
        throw Error(what + "'s first row must be Top or Bottom");
    if (!finite(cam.inverse_view_projection.data(), 16) || !finite(cam.eye.data(), 3))
        throw Error(what + "'s inverse view-projection and eye must be finite");
    if (cam.orthographic &&
        !(std::fabs(cam.eye[0]) + std::fabs(cam.eye[1]) + std::fabs(cam.eye[2]) > 0.0f))
        throw Error(what + " is orthographic and its eye (its view direction) is the zero vector");
}

OmPixelGrid pixel_grid(const EngineCamera& cam, int width, int height, const std::string& what) {
    check_camera(cam, what);
    const bool gl = cam.depth == DepthConvention::GL;
    const bool reversed = cam.depth == DepthConvention::Reversed;
    OmPixelGrid g{};
    g.width = width;
    g.height = height;
    g.depth_scale = gl ? 2.0f : 1.0f;
    g.depth_offset = gl ? -1.0f : 0.0f;
    g.ndc_depth_scale = gl ? 0.5f : 1.0f;
    g.ndc_depth_offset = gl ? 0.5f : 0.0f;
    g.far_depth = reversed ? 0.0f : 1.0f;
    g.far_sign = reversed ? -1.0f : 1.0f;
    g.row0_ndc_y = static_cast<float>(static_cast<int>(cam.first_row));
    return g;
}

void check_inverse(const std::array<float, 16>& vp, const EngineCamera& cam,
                   const std::string& what) {
    if (!finite(vp.data(), 16)) throw Error(what + "'s view-projection must be finite");
    const std::array<float, 16>& inv = cam.inverse_view_projection;
    double worst = 0.0;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) {
            double sum = 0.0;
            for (int k = 0; k < 4; ++k) sum += double(vp[4 * k + r]) * inv[4 * c + k];
            worst = std::max(worst, std::fabs(sum - (r == c ? 1.0 : 0.0)));
        }
    if (!(worst <= 1e-3))
        throw Error(what +
                    "'s view-projection is not the inverse of its camera's "
                    "inverse_view_projection (their product is " +
                    std::to_string(worst) + " from the identity)");
}

}  // namespace offsetmap
