// Frames against the truth (the displaced mesh drawn by the same raster): what each pixel shows,
// where the two disagree, and the truth's own bound.
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>

#include "offsetmap/evaluate.hpp"
#include "offsetmap/oracle.hpp"
#include "offsetmap/renderer/truth.hpp"
#include "offsetmap/settings.hpp"
#include "offsetmap/triplanar.hpp"

namespace offsetmap::renderer {

namespace {

const LoadedMaterial* material_of(const std::vector<LoadedMaterial>& table, float id) {
    if (!(id > 0.0f)) return nullptr;
    for (const LoadedMaterial& m : table)
        if (static_cast<float>(m.spec.id) == id) return &m;
    return nullptr;
}

ErrorSummary summary(std::vector<double> values) {
    const ErrorStats s = error_stats(std::move(values));
    return {s.mean, s.p95, s.max};
}

}  // namespace

std::vector<std::uint8_t> silhouette_band(const std::vector<float>& material,
                                          const std::vector<float>& depth,
                                          const std::vector<std::uint32_t>& flags, int w, int h) {
    const size_t n = static_cast<size_t>(w) * h;
    // Edge pixels first: a neighbour to the right or below shows another surface. Window depth is
    // affine in the pixel coordinates over a plane (and nearly so over a smooth surface), so a
    // step between two pixels that is 4 times the steps beside it is a depth discontinuity.
    std::vector<std::uint8_t> edge(n, 0);
    auto step = [&](long long a, long long b) {
        return std::fabs(static_cast<double>(depth[b]) - depth[a]);
    };
    auto differs = [&](size_t a, size_t b, long long before, long long after) {
        const bool sky_a = depth[a] >= 1.0f, sky_b = depth[b] >= 1.0f;
        if (sky_a || sky_b) return sky_a != sky_b;
        if (material[a] != material[b]) return true;
        if (!flags.empty() && ((flags[a] ^ flags[b]) & (OM_FLAGS_NOT_SHOWN & ~OM_FLAG_EMPTY)))
            return true;
        double beside = 0.0;
        if (before >= 0 && depth[before] < 1.0f) beside = std::max(beside, step(before, a));
        if (after >= 0 && depth[after] < 1.0f) beside = std::max(beside, step(b, after));
        return step(a, b) > 4.0 * beside + 1e-6;
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t k = static_cast<size_t>(y) * w + x;
            if (x + 1 < w && differs(k, k + 1, x > 0 ? static_cast<long long>(k) - 1 : -1,
                                     x + 2 < w ? static_cast<long long>(k) + 2 : -1))
                edge[k] = edge[k + 1] = 1;
            if (y + 1 < h && differs(k, k + w, y > 0 ? static_cast<long long>(k) - w : -1,
                                     y + 2 < h ? static_cast<long long>(k + 2 * w) : -1))
                edge[k] = edge[k + w] = 1;
        }
    std::vector<std::uint8_t> band(n, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            if (!edge[static_cast<size_t>(y) * w + x]) continue;
            for (int j = std::max(0, y - 2); j <= std::min(h - 1, y + 2); ++j)
                for (int i = std::max(0, x - 2); i <= std::min(w - 1, x + 2); ++i)
                    band[static_cast<size_t>(j) * w + i] = 1;
        }
    return band;
}

GeometryFrame triplanar_truth_uv(GeometryFrame truth, const std::vector<std::int8_t>& first,
                                 const std::vector<LoadedMaterial>& table) {
    if (truth.base_point.empty() || first.size() != truth.depth.size()) return truth;
    for (size_t k = 0; k < first.size(); ++k) {
        const LoadedMaterial* m = material_of(table, truth.material[k]);
        if (first[k] < 0 || !m || !m->spec.triplanar.enabled || truth.depth[k] >= 1.0f) continue;
        const TriplanarFrame f = triplanar_frame(first[k]);
        const double ws = m->spec.triplanar.world_scale;
        const float* p = &truth.base_point[3 * k];
        truth.uv[2 * k] = static_cast<float>(ws * (p[0] * f.t[0] + p[1] * f.t[1] + p[2] * f.t[2]));
        truth.uv[2 * k + 1] =
            static_cast<float>(ws * (p[0] * f.b[0] + p[1] * f.b[1] + p[2] * f.b[2]));
    }
    return truth;
}

namespace {

// uv a - b in texels of m, a whole tile apart being the same texel under wrap.
double texel_distance(double au, double av, double bu, double bv, const LoadedMaterial& m) {
    double du = au - bu, dv = av - bv;
    if (m.spec.settings.address == AddressMode::Wrap) {
        du -= std::round(du);
        dv -= std::round(dv);
    }
    return std::hypot(du * m.map.width, dv * m.map.height);
}

// How far (texels) the relief can move uv' from the base's uv at pixel k: s max(r, 1 - r) along
// V.xy / V.z (the grazing rule's least V.z), and two texels for the raster's footprint.
double reach_texels(const GBuffer& base, size_t k, const LoadedMaterial& m) {
    const PassSettings& s = m.spec.settings;
    const double vx = base.view[k].s[0], vy = base.view[k].s[1], vz = base.view[k].s[2];
    const double len = std::sqrt(vx * vx + vy * vy + vz * vz);
    const double z =
        std::max(vz / len, static_cast<double>(grazing_rule(s, m.map.width, m.map.height).min_vz));
    const double depth = s.scale * std::max(s.reference_plane, 1.0f - s.reference_plane) / z;
    return depth * std::hypot(vx / len * m.map.width, vy / len * m.map.height) + 2.0;
}

// How far (world units, along the ray) the relief can move the surface from its base: s max(r,
// 1 - r) / cos uv units, times the uv density, `cos` the ray's cosine with the surface's normal.
double depth_reach(const LoadedMaterial& m, double density, double cosine) {
    const PassSettings& s = m.spec.settings;
    return density * s.scale * std::max(s.reference_plane, 1.0f - s.reference_plane) / cosine *
               1.01 +
           1e-4;
}

}  // namespace

TruthComparison compare_to_truth(const GeometryFrame& truth, const ShownFrame& f,
                                 const GBuffer& base, const std::vector<float>& base_depth,
                                 const std::vector<float>& base_normal,
                                 const std::vector<std::uint8_t>& band,
                                 const std::vector<LoadedMaterial>& table,
                                 const std::array<float, 16>& inverse_vp, int w, int h) {
    glm::dmat4 inv;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) inv[c][r] = inverse_vp[4 * c + r];
    auto world = [&](int x, int y, double d) {
        const glm::dvec4 p = inv * glm::dvec4((2.0 * x + 1.0) / w - 1.0, 1.0 - (2.0 * y + 1.0) / h,
                                              2.0 * d - 1.0, 1.0);
        return glm::dvec3(p) / p.w;
    };
    TruthComparison out;
    out.mode = f.mode;
    const size_t n = static_cast<size_t>(w) * h;
    out.uv_error.assign(n, std::nanf(""));
    out.mismatched.assign(n, 0);
    std::vector<double> uv_errors, depth_errors;
    for (size_t k = 0; k < n; ++k) {
        const LoadedMaterial* t =
            truth.depth[k] < 1.0f ? material_of(table, truth.material[k]) : nullptr;
        const bool shown = (*f.depth)[k] < 1.0f && !((*f.flags)[k] & OM_FLAGS_NOT_SHOWN) &&
                           std::isfinite((*f.uv)[k].s[0]);
        const LoadedMaterial* m = shown ? material_of(table, (*f.material)[k]) : nullptr;
        if (!t && !m) continue;
        // The same material on another surface (a box's other face, the far side of a seam)
        // lies beyond the relief's reach from the base G-buffer's uv: that is coverage too.
        bool same = t == m;
        const int x = static_cast<int>(k % w), y = static_cast<int>(k / w);
        const bool other_base =
            t && !base.material.empty() && base.material[k] != float(t->spec.id);
        if (same && std::isfinite(base.uv[k].s[0]) && other_base) {
            // Neither shows the base surface (a layer behind, or what a discarded fragment let
            // through): the same surface if their points lie within the relief's depth of each
            // other along the ray, at the angle the truth's normal makes with it.
            const glm::dvec3 pt = world(x, y, truth.depth[k]), pf = world(x, y, (*f.depth)[k]);
            const glm::dvec3 ray = glm::normalize(world(x, y, 1.0) - world(x, y, 0.0));
            const glm::dvec3 nt(truth.normal[3 * k], truth.normal[3 * k + 1],
                                truth.normal[3 * k + 2]);
            const double cosine = std::fabs(glm::dot(ray, nt)) / std::max(glm::length(nt), 1e-12);
            const double min_vz =
                grazing_rule(t->spec.settings, t->map.width, t->map.height).min_vz;
            same =
                glm::length(pt - pf) <= depth_reach(*t, truth.density[k], std::max(cosine, min_vz));
        } else if (same && std::isfinite(base.uv[k].s[0])) {
            const double reach = reach_texels(base, k, *t);
            const double vz = base.view[k].s[2] / std::sqrt(base.view[k].s[0] * base.view[k].s[0] +
                                                            base.view[k].s[1] * base.view[k].s[1] +
                                                            base.view[k].s[2] * base.view[k].s[2]);
            const double along = depth_reach(*t, truth.density[k], std::max(vz, 1e-3));
            // And facing as the base does there (within 45 degrees: not a box's other face),
            // where the frame shows geometry with its normals (the truth, a tessellation).
            auto near = [&](double u, double v, double depth, const float* n) {
                const float* bn = &base_normal[4 * k];
                return (!n || n[0] * bn[0] + n[1] * bn[1] + n[2] * bn[2] > 0.7071f) &&
                       texel_distance(u, v, base.uv[k].s[0], base.uv[k].s[1], *t) <= reach &&
                       glm::length(world(x, y, depth) - world(x, y, base_depth[k])) <= along;
            };
            const bool truth_near =
                near(truth.uv[2 * k], truth.uv[2 * k + 1], truth.depth[k], &truth.normal[3 * k]);
            const bool frame_near = near((*f.uv)[k].s[0], (*f.uv)[k].s[1], (*f.depth)[k],
                                         f.normal ? &(*f.normal)[3 * k] : nullptr);
            same = truth_near == frame_near;
        }
        if (!same) {
            out.mismatched[k] = 1;
            ++out.mismatch;
            (band[k] ? out.mismatch_band : out.mismatch_interior) += 1;
            continue;
        }
        ++out.compared_pixels;
        const double e = texel_distance((*f.uv)[k].s[0], (*f.uv)[k].s[1], truth.uv[2 * k],
                                        truth.uv[2 * k + 1], *t);
        out.uv_error[k] = static_cast<float>(e);
        uv_errors.push_back(e);
        depth_errors.push_back(
            glm::length(world(x, y, truth.depth[k]) - world(x, y, (*f.depth)[k])));
    }
    out.uv_err_texels = summary(uv_errors);
    out.depth_err = summary(depth_errors);
    return out;
}

namespace {

// Each bilinear cell's twist |H00 - H10 - H01 + H11| (cell (i, j) between the centres of texels i,
// i + 1 and j, j + 1, wrapped or clamped as the material addresses them).
struct Twists {
    int w = 0, h = 0;
    bool wrap = false;
    std::vector<float> cell;
    float max = 0.0f;

    explicit Twists(const LoadedMaterial& m)
        : w(m.map.width), h(m.map.height), wrap(m.spec.settings.address == AddressMode::Wrap) {
        cell.resize(static_cast<size_t>(w) * h);
        for (int j = 0; j < h; ++j)
            for (int i = 0; i < w; ++i) {
                const float d = std::fabs(at(m.map, i, j) - at(m.map, i + 1, j) -
                                          at(m.map, i, j + 1) + at(m.map, i + 1, j + 1));
                cell[static_cast<size_t>(j) * w + i] = d;
                max = std::max(max, d);
            }
    }
    float at(const HeightMap& m, int i, int j) const {
        return m.h[static_cast<size_t>(index(j, h)) * w + index(i, w)];
    }
    int index(int i, int n) const { return wrap ? ((i % n) + n) % n : std::clamp(i, 0, n - 1); }
    // Cell (i, j)'s twist, unwrapped indices; past a clamped edge the field is flat across the
    // cells there (twist 0).
    float of(long long i, long long j) const {
        if (!wrap && (i < 0 || j < 0 || i >= w - 1 || j >= h - 1)) return 0.0f;
        const long long a = ((i % w) + w) % w, b = ((j % h) + h) % h;
        return cell[static_cast<size_t>(b) * w + static_cast<size_t>(a)];
    }
};

}  // namespace

std::vector<float> truth_bound_texels(const GBuffer& gb, const std::vector<float>& material,
                                      const std::vector<LoadedMaterial>& table,
                                      const Tessellation& truth) {
    std::vector<float> out(gb.pixels(), std::nanf(""));
    std::vector<Twists> twists;
    for (const LoadedMaterial& m : table) twists.emplace_back(m);
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const LoadedMaterial* m = material_of(table, material[k]);
        if (!m || !std::isfinite(gb.uv[k].s[0])) continue;
        // A piece of a lattice cell a texels a side inside a bilinear cell of twist d departs from
        // it by at most |d| a^2 / 4: the error of the linear interpolant of d x y on a triangle is
        // d times the covariance of x and y over its corners, at most (a / 2)^2 (Popoviciu).
        double quad = -1.0;
        for (const TessellatedMesh& t : truth.meshes)
            if (static_cast<float>(t.material) == material[k] && std::isfinite(t.height_bound))
                quad = std::max(quad, static_cast<double>(t.texels_per_quad));
        double V[3] = {gb.view[k].s[0], gb.view[k].s[1], gb.view[k].s[2]};
        const double len = std::sqrt(V[0] * V[0] + V[1] * V[1] + V[2] * V[2]);
        if (!(len > 0.0) || !(V[2] > 0.0) || !(quad > 0.0)) continue;
        for (double& c : V) c /= len;
        const Twists& tw = twists[static_cast<size_t>(m - table.data())];
        const double u = gb.uv[k].s[0], v = gb.uv[k].s[1];
        // Each cell's bound: the surface lies between the field raised and lowered by it cell
        // by cell, so its first hit lies between theirs.
        const double scale = quad * quad / 4.0;
        const CellLift up{[&](long long i, long long j) { return tw.of(i, j) * scale; }, 0.0,
                          tw.max * scale};
        const CellLift down{[&](long long i, long long j) { return -tw.of(i, j) * scale; },
                            -tw.max * scale, 0.0};
        const ExactHit a = exact_hit(m->map, u, v, V, m->spec.settings, up);
        const ExactHit b = exact_hit(m->map, u, v, V, m->spec.settings, down);
        out[k] =
            static_cast<float>(std::hypot((a.u - b.u) * m->map.width, (a.v - b.v) * m->map.height));
    }
    return out;
}

}  // namespace offsetmap::renderer
