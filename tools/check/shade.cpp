// The shade pass on the device against the shade kernel compiled as C++ (tools/peer/shade.cpp),
// fed the device's own normals and heights, so the case measures the shading alone.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "check.hpp"
#include "cpu_peer.hpp"
#include "shade_params.hpp"

namespace offsetmap::check {
namespace {

// A colour goes through fewer than 40 float roundings (bilinear taps, normalisations, dot products,
// the specular power) and builtins of at most 4 ulp each, on values below 2: two compilers differ
// by under 40 * 4 * 2^-23 * 2, about 4e-5, where no comparison flips. Twice that:
constexpr double kColourTolerance = 1e-4;

struct Variant {
    const char* name;
    ShadeSettings shade;
    bool albedo = false;     // an albedo image, else the checker
    bool per_pixel = false;  // L from the G-buffer's light plane
};

std::vector<Variant> variants() {
    std::vector<Variant> out;
    Variant lit{"lit, albedo, specular 64", ShadeSettings{}, true, false};
    lit.shade.shininess = 64.0f;
    out.push_back(lit);
    Variant hard{"hard shadows, sun at 8 deg, checker", ShadeSettings{}};
    hard.shade.shadow = ShadowMode::Hard;
    hard.shade.shadow_steps = 24;
    hard.shade.light[0] = 0.930f, hard.shade.light[1] = 0.339f, hard.shade.light[2] = 0.139f;
    out.push_back(hard);
    Variant soft{"soft shadows, L per pixel, albedo", ShadeSettings{}, true, true};
    soft.shade.shadow = ShadowMode::Soft;
    soft.shade.shadow_steps = 16;
    out.push_back(soft);
    return out;
}

Image4 albedo_image() {
    Image4 a{13, 7, {}};
    for (int j = 0; j < a.height; ++j)
        for (int i = 0; i < a.width; ++i)
            a.texels.push_back({{hashed(31, i, j), hashed(32, i, j), hashed(33, i, j), 1.0f}});
    return a;
}

// Light directions per pixel: elevations from below the polygon to overhead, any azimuth.
void light_plane(GBuffer& gb) {
    gb.light.resize(gb.pixels());
    for (size_t k = 0; k < gb.pixels(); ++k) {
        const int x = static_cast<int>(k % gb.width), y = static_cast<int>(k / gb.width);
        const double el = (hashed(41, x, y) * 1.1 - 0.1) * M_PI / 2,
                     az = hashed(42, x, y) * 2 * M_PI;
        gb.light[k] = {{static_cast<float>(std::cos(el) * std::cos(az)),
                        static_cast<float>(std::cos(el) * std::sin(az)),
                        static_cast<float>(std::sin(el)), 0.0f}};
    }
}

template <typename T>
std::vector<T> read(Runtime& rt, const cl::Buffer& b, size_t n) {
    std::vector<T> out(n);
    rt.queue().enqueueReadBuffer(b, CL_TRUE, 0, n * sizeof(T), out.data());
    return out;
}

double colour_distance(const cl_float4& a, const cl_float4& b) {
    double d = 0.0;
    for (int c = 0; c < 4; ++c) d = std::max(d, std::fabs(static_cast<double>(a.s[c]) - b.s[c]));
    return std::isnan(d) ? INFINITY : d;
}

std::string colour_text(const cl_float4& c) {
    char t[80];
    std::snprintf(t, sizeof t, "(%.6g, %.6g, %.6g, %.6g)", c.s[0], c.s[1], c.s[2], c.s[3]);
    return t;
}

// The shade kernel as C++ over the same inputs, the field's normals and level-0 heights as the
// device holds them.
std::vector<cl_float4> peer_shade(Runtime& rt, const GBuffer& gb, const OffsetResult& offsets,
                                  const DeviceHeightField& field, const Image4* albedo,
                                  const PassSettings& settings, const ShadeSettings& shade) {
    const size_t texels = static_cast<size_t>(field.width) * field.height;
    const std::vector<cl_float4> normals = read<cl_float4>(rt, field.normals, texels);
    const std::vector<float> heights = read<float>(rt, field.heights, texels);
    DeviceImage size_only;
    if (albedo) size_only.width = albedo->width, size_only.height = albedo->height;
    cpu_peer::ShadeArgs a{};
    a.params =
        shade_params(settings, shade, field.width, field.height, albedo ? &size_only : nullptr);
    a.params.gb_width = gb.width;
    a.params.gb_height = gb.height;
    a.params.has_light = gb.has_light() ? 1 : 0;
    a.uv = offsets.uv.data();
    a.flags = offsets.flags.data();
    a.view = gb.view.data();
    a.light = gb.has_light() ? gb.light.data() : nullptr;
    a.normals = normals.data();
    a.heights = heights.data();
    a.albedo = albedo ? albedo->texels.data() : nullptr;
    std::vector<cl_float4> out(gb.pixels());
    a.out_rgba = out.data();
    const int blocks = om_image_blocks(gb.width, gb.height, 1);
    const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (int t = 0; t < threads; ++t)
        pool.emplace_back(
            [&, t] { cpu_peer::shade(a, blocks * t / threads, blocks * (t + 1) / threads); });
    for (auto& th : pool) th.join();
    return out;
}

// The pixels of `apart` whose device colour stays within the tolerance when any of uv', V or L
// moves by 2^-20 of its size (the rest sit on a discontinuity of the kernel: a shadow's edge, a
// checker square's, the light's horizon).
std::vector<size_t> steady_pixels(Runtime& rt, ShadePass& pass, const GBuffer& gb,
                                  const OffsetResult& offsets, const std::vector<cl_float4>& got,
                                  const DeviceHeightField& field, const DeviceImage* albedo,
                                  const PassSettings& settings, const ShadeSettings& shade,
                                  const std::vector<size_t>& apart) {
    std::vector<size_t> steady;
    if (apart.empty()) return steady;
    const int inputs = gb.has_light() ? 8 : 5, copies = 2 * inputs;
    GBuffer moved;
    moved.resize(static_cast<int>(copies * apart.size()), 1, gb.has_light(), false);
    OffsetResult moved_offsets;
    moved_offsets.uv.resize(moved.pixels());
    moved_offsets.flags.resize(moved.pixels());
    for (size_t a = 0; a < apart.size(); ++a) {
        const size_t k = apart[a];
        for (int comp = 0; comp < inputs; ++comp)
            for (int side = 0; side < 2; ++side) {
                float in[8] = {offsets.uv[k].s[0],
                               offsets.uv[k].s[1],
                               gb.view[k].s[0],
                               gb.view[k].s[1],
                               gb.view[k].s[2],
                               0.0f,
                               0.0f,
                               0.0f};
                if (gb.has_light())
                    for (int c = 0; c < 3; ++c) in[5 + c] = gb.light[k].s[c];
                in[comp] +=
                    (side ? 1.0f : -1.0f) * std::ldexp(std::max(std::fabs(in[comp]), 1e-3f), -20);
                const size_t n = copies * a + 2 * comp + side;
                moved_offsets.uv[n] = {{in[0], in[1]}};
                moved_offsets.flags[n] = offsets.flags[k];
                moved.uv[n] = gb.uv[k];
                moved.view[n] = {{in[2], in[3], in[4], 0.0f}};
                if (gb.has_light()) moved.light[n] = {{in[5], in[6], in[7], 0.0f}};
            }
    }
    const std::vector<cl_float4> c =
        run_shade(rt, pass, moved_offsets, upload(rt, moved), field, albedo, settings, shade);
    for (size_t a = 0; a < apart.size(); ++a) {
        double jump = 0.0;
        for (int n = 0; n < copies; ++n)
            jump = std::max(jump, colour_distance(c[copies * a + n], got[apart[a]]));
        if (jump <= kColourTolerance) steady.push_back(apart[a]);
    }
    return steady;
}

void shade_case(const std::shared_ptr<Runtime>& rt, const MapCase& c, const Variant& v,
                const GBuffer& views, CaseResult& out) {
    out.measure = "colour from the C++ peer off its discontinuities";
    GBuffer gb = views;
    if (v.per_pixel) light_plane(gb);
    const DeviceGBuffer g = upload(*rt, gb);
    const DeviceHeightField field = upload(*rt, c.map, c.settings);
    OffsetPass offset(rt, "pom");
    const OffsetResult offsets = run_offset(*rt, offset, g, field, c.settings);
    const Image4 albedo = albedo_image();
    DeviceImage device_albedo;
    if (v.albedo) device_albedo = upload(*rt, albedo);
    const DeviceImage* da = v.albedo ? &device_albedo : nullptr;
    ShadePass pass(rt);
    const std::vector<cl_float4> got =
        run_shade(*rt, pass, offsets, g, field, da, c.settings, v.shade);
    const std::vector<cl_float4> want =
        peer_shade(*rt, gb, offsets, field, v.albedo ? &albedo : nullptr, c.settings, v.shade);
    // The pixels the self-shadows darken, so a case that shadows nothing is seen to.
    ShadeSettings unshadowed = v.shade;
    unshadowed.shadow = ShadowMode::None;
    const std::vector<cl_float4> open =
        peer_shade(*rt, gb, offsets, field, v.albedo ? &albedo : nullptr, c.settings, unshadowed);
    std::vector<size_t> apart;
    size_t shadowed = 0;
    for (size_t k = 0; k < gb.pixels(); ++k) {
        ++out.pixels;
        const double d = colour_distance(got[k], want[k]);
        if (d > kColourTolerance)
            apart.push_back(k);
        else
            out.worst = std::max(out.worst, d);
        shadowed += colour_distance(open[k], want[k]) > 0.01;
    }
    const std::vector<size_t> steady =
        steady_pixels(*rt, pass, gb, offsets, got, field, da, c.settings, v.shade, apart);
    for (size_t k : steady) {
        const double d = colour_distance(got[k], want[k]);
        if (d > out.worst) {
            out.worst = d;
            out.worst_pixel = pixel_name(k, gb.width) + ": " + colour_text(got[k]) +
                              ", the peer's " + colour_text(want[k]) + ", off any discontinuity";
        }
        out.passed = false;
    }
    char note[240];
    std::snprintf(note, sizeof note,
                  "%s; %zu pixels on a discontinuity; %zu darkened by self-shadows", c.name.c_str(),
                  apart.size() - steady.size(), shadowed);
    out.note = note;
}

}  // namespace

void check_shade(const std::shared_ptr<Runtime>& rt, const Options& o, DeviceReport& report) {
    const GBuffer views = case_views(o.quick);
    for (const MapCase& c : map_cases(o.quick))
        for (const Variant& v : variants()) {
            CaseResult out;
            out.kernel = "shade";
            // The map by its relief and size (its full description in the note).
            out.name = std::string(v.name) + "; " + c.name.substr(0, c.name.find(','));
            try {
                shade_case(rt, c, v, views, out);
            } catch (const std::exception& e) {
                out.passed = false;
                out.worst_pixel = std::string("no result: ") + e.what();
            }
            report.cases.push_back(out);
        }
}

}  // namespace offsetmap::check
