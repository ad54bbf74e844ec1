// A GL camera's frame rewritten in another engine's conventions (the depth convention and the row
// order), for the passes that read a depth buffer: the same world points, so each pass's output,
// read back into GL's terms, must be GL's to float rounding.
#pragma once
#include <array>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "offsetmap/engine_gbuffer.hpp"

namespace omtest {

struct CameraForm {
    offsetmap::DepthConvention depth = offsetmap::DepthConvention::GL;
    offsetmap::FirstRow first_row = offsetmap::FirstRow::Bottom;
    std::string name() const {
        const char* d[] = {"gl", "zero-one", "reversed"};
        return std::string(d[static_cast<int>(depth)]) +
               (first_row == offsetmap::FirstRow::Top ? "/top" : "/bottom");
    }
    // NDC z of this form -> GL's NDC z (a matrix on NDC points, column-major glm).
    glm::dmat4 to_gl_ndc() const {
        glm::dmat4 r(1.0);
        if (depth == offsetmap::DepthConvention::ZeroToOne) r[2][2] = 2.0, r[3][2] = -1.0;
        if (depth == offsetmap::DepthConvention::Reversed) r[2][2] = -2.0, r[3][2] = 1.0;
        return r;
    }
    // A GL window depth in this form, and back (the same NDC point: zero-one keeps it).
    float depth_from_gl(float d) const {
        return depth == offsetmap::DepthConvention::Reversed ? static_cast<float>(1.0 - d) : d;
    }
    float depth_to_gl(float d) const { return depth_from_gl(d); }
    // A plane of `c` values a pixel, rows bottom first (GL's), in this form's row order; and back.
    template <typename T>
    std::vector<T> rows(const std::vector<T>& in, int w, int h, int c = 1) const {
        if (first_row == offsetmap::FirstRow::Bottom) return in;
        std::vector<T> out(in.size());
        const size_t row = static_cast<size_t>(w) * c;
        for (int y = 0; y < h; ++y)
            std::copy_n(in.begin() + row * (h - 1 - y), row, out.begin() + row * y);
        return out;
    }
    std::vector<float> depth_plane(const std::vector<float>& gl, int w, int h) const {
        std::vector<float> out = rows(gl, w, h);
        for (float& d : out) d = depth_from_gl(d);
        return out;
    }
    std::vector<float> depth_plane_to_gl(const std::vector<float>& in, int w, int h) const {
        std::vector<float> out = rows(in, w, h);
        for (float& d : out) d = depth_to_gl(d);
        return out;
    }
    // The camera of a GL view-projection in this form: its inverse, depth convention and rows.
    offsetmap::EngineCamera camera(const glm::dmat4& gl_vp) const {
        offsetmap::EngineCamera c;
        c.inverse_view_projection = inverse_view_projection(gl_vp);
        c.depth = depth;
        c.first_row = first_row;
        return c;
    }
    // A GL view-projection (world -> GL clip) and its inverse in this form, as floats.
    std::array<float, 16> view_projection(const glm::dmat4& gl_vp) const {
        return floats(glm::inverse(to_gl_ndc()) * gl_vp);
    }
    std::array<float, 16> inverse_view_projection(const glm::dmat4& gl_vp) const {
        return floats(glm::inverse(gl_vp) * to_gl_ndc());
    }
    static std::array<float, 16> floats(const glm::dmat4& m) {
        std::array<float, 16> a;
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) a[4 * c + r] = static_cast<float>(m[c][r]);
        return a;
    }
};

// GL's own, then each other depth convention with each row order.
inline std::vector<CameraForm> camera_forms() {
    using offsetmap::DepthConvention;
    using offsetmap::FirstRow;
    return {
        {DepthConvention::GL, FirstRow::Bottom},     {DepthConvention::GL, FirstRow::Top},
        {DepthConvention::ZeroToOne, FirstRow::Top}, {DepthConvention::ZeroToOne, FirstRow::Bottom},
        {DepthConvention::Reversed, FirstRow::Top},  {DepthConvention::Reversed, FirstRow::Bottom}};
}

}  // namespace omtest
