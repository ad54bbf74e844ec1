// The reconstruct pass (an engine's G-buffer forms into tangent-space V and L) against the double
// reference from the stored values, within its per-pixel float bound (engine_reference.hpp).
#include <cmath>
#include <cstdio>

#include "check.hpp"
#include "offsetmap/engine_reference.hpp"

namespace offsetmap::check {
namespace {

const EngineLight kSun{LightKind::Directional, {0.3f, -0.4f, 0.8f}};
const EngineLight kLamp{LightKind::Point, {0.2f, 0.1f, 0.6f}};

// Both frame forms, the three depth conventions, both row orders, every storage, buffers and
// images, no light, a sun and a lamp.
std::vector<engine_ref::Encoding> encodings(bool quick) {
    std::vector<engine_ref::Encoding> out = {
        {"tangent, float buffers, [0,1] depth, sun", FrameForm::NormalTangent,
         DepthConvention::ZeroToOne, FirstRow::Top, Storage::Float, Storage::Float, Storage::Float,
         false, kSun},
        {"quaternion, snorm16 images, GL unorm16 depth, sun", FrameForm::Quaternion,
         DepthConvention::GL, FirstRow::Top, Storage::Unorm16, Storage::Snorm16, Storage::Float,
         true, kSun},
        {"tangent, half images, reversed depth, sun", FrameForm::NormalTangent,
         DepthConvention::Reversed, FirstRow::Top, Storage::Float, Storage::Half, Storage::Half,
         true, kSun},
    };
    if (quick) return out;
    const std::vector<engine_ref::Encoding> more = {
        {"tangent, float images, GL depth, rows up, lamp", FrameForm::NormalTangent,
         DepthConvention::GL, FirstRow::Bottom, Storage::Float, Storage::Float, Storage::Float,
         true, kLamp},
        {"tangent, snorm16 buffers, GL unorm16 depth, half uv", FrameForm::NormalTangent,
         DepthConvention::GL, FirstRow::Top, Storage::Unorm16, Storage::Snorm16, Storage::Half,
         false, EngineLight{}},
        {"quaternion, float buffers, reversed, rows up, lamp", FrameForm::Quaternion,
         DepthConvention::Reversed, FirstRow::Bottom, Storage::Float, Storage::Float,
         Storage::Float, false, kLamp},
        {"quaternion, half buffers, [0,1] depth", FrameForm::Quaternion, DepthConvention::ZeroToOne,
         FirstRow::Top, Storage::Float, Storage::Half, Storage::Float, false, EngineLight{}},
    };
    out.insert(out.end(), more.begin(), more.end());
    return out;
}

// A plane seen from above the horizon (sky pixels too), 102 wide: partial blocks of lanes.
PlaneScene plane(bool quick) {
    PlaneScene s;
    s.width = 102;
    s.height = quick ? 40 : 64;
    s.pitch_deg = 25.0;
    s.camera_x = 0.3;
    s.camera_y = -0.7;
    s.tile = 0.5;
    return s;
}

void reconstruct_case(const std::shared_ptr<Runtime>& rt, const engine_ref::Encoding& e, bool quick,
                      CaseResult& out) {
    using namespace engine_ref;
    out.measure = "share of the float bound";
    EngineFrame f = encoded_frame(plane(quick), e, 7);
    if (!device_reads_images(rt->context(), f)) {
        out.note = "not run: the device has no image format for a plane";
        return;
    }
    EngineGBuffer in = f.to_device(rt->context());
    in.light = e.light;
    const bool lit = e.light.kind != LightKind::None;
    const Decoded d = reconstruct(rt, in, lit);
    size_t sky = 0;
    auto fail = [&](size_t k, const std::string& what) {
        if (out.passed) out.worst_pixel = pixel_name(k, f.width) + ": " + what;
        out.passed = false;
    };
    for (size_t k = 0; k < f.pixels(); ++k) {
        const Reference ref = reference(f, k, e.light);
        if (ref.sky) {
            ++sky;
            if (!std::isnan(d.uv[k].s[0]) || !std::isnan(d.uv[k].s[1]))
                fail(k, "sky in the depth plane, yet uv is not NaN (empty)");
            continue;
        }
        ++out.pixels;
        for (int i = 0; i < 2; ++i) {
            const double want = stored_value(f.uv.v[2 * k + i], f.uv.storage);
            if (!(std::fabs(d.uv[k].s[i] - want) <= decode_error(f.uv.storage) * std::fabs(want)))
                fail(k, "uv " + std::to_string(d.uv[k].s[i]) + ", stored " + std::to_string(want));
        }
        for (int i = 0; i < 3; ++i) {
            const double share = std::fabs(d.view[k].s[i] - ref.v_ts[i]) / ref.bound;
            const double l_share =
                lit ? std::fabs(d.light[k].s[i] - ref.l_ts[i]) / ref.l_bound : 0.0;
            const double worst = std::max(share, l_share);
            if (!(worst <= out.worst)) {
                out.worst = std::isnan(worst) ? INFINITY : worst;
                char text[200];
                std::snprintf(text, sizeof text,
                              "%s[%d] %.8g, the reference %.8g, %.3g of its bound",
                              share >= l_share ? "V" : "L", i,
                              share >= l_share ? d.view[k].s[i] : d.light[k].s[i],
                              share >= l_share ? ref.v_ts[i] : ref.l_ts[i], out.worst);
                if (out.passed) out.worst_pixel = pixel_name(k, f.width) + ": " + text;
            }
        }
    }
    if (out.worst > 1.0) out.passed = false;
    char note[80];
    std::snprintf(note, sizeof note, "%zu sky pixels", sky);
    out.note = note;
}

}  // namespace

void check_reconstruct(const std::shared_ptr<Runtime>& rt, const Options& o, DeviceReport& report) {
    for (const engine_ref::Encoding& e : encodings(o.quick)) {
        CaseResult out;
        out.kernel = "reconstruct";
        out.name = e.name;
        try {
            reconstruct_case(rt, e, o.quick, out);
        } catch (const std::exception& ex) {
            out.passed = false;
            out.worst_pixel = std::string("no result: ") + ex.what();
        }
        report.cases.push_back(out);
    }
}

}  // namespace offsetmap::check
