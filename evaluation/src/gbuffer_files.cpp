// G-buffer files: the OpenEXR contract (channels found by name) read and written.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <sstream>

#include "image_read.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/image_io.hpp"

namespace offsetmap {

namespace {

const char* depth_name(DepthConvention d) {
    return d == DepthConvention::GL          ? "gl"
           : d == DepthConvention::ZeroToOne ? "zero-one"
                                             : "reversed";
}

std::string numbers(const float* v, int n) {
    std::string out;
    for (int k = 0; k < n; ++k) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", v[k]);  // 9 digits: the float again on reading
        out += (k ? " " : "") + std::string(text);
    }
    return out;
}

// `count` finite numbers from an attribute's text; throws Error naming the file and attribute.
std::vector<float> parse_numbers(const std::string& text, int count, const std::string& file,
                                 const std::string& name) {
    std::istringstream in(text);
    std::vector<float> out;
    float x;
    while (in >> x) out.push_back(x);
    if (!in.eof() || static_cast<int>(out.size()) != count)
        throw Error(file + ": attribute " + name + " must hold " + std::to_string(count) +
                    " numbers, got '" + text + "'");
    for (float v : out)
        if (!std::isfinite(v)) throw Error(file + ": attribute " + name + " is not finite");
    return out;
}

}  // namespace

void save_engine_gbuffer(const std::string& path, const EngineScene& e) {
    const bool quaternion = e.frame == FrameForm::Quaternion;
    std::vector<std::string> names = {"depth", "u", "v"};
    for (const char* n : quaternion ? std::vector<const char*>{"Qx", "Qy", "Qz", "Qw"}
                                    : std::vector<const char*>{"Nx", "Ny", "Nz"})
        names.push_back(n);
    if (!quaternion) names.insert(names.end(), {"Tx", "Ty", "Tz", "Tw"});
    const bool ids = !e.material.empty();
    if (ids) names.push_back("material");
    const bool derivatives = !e.uv_derivatives.empty();
    if (derivatives) names.insert(names.end(), {"dudx", "dvdx", "dudy", "dvdy"});
    const bool curvature = !e.curvature.empty();
    if (curvature) names.insert(names.end(), {"kuu", "kuv", "kvv"});
    const bool stretch = curvature && !e.uv_stretch.empty();
    if (stretch) names.push_back("stretch");
    const int nc = static_cast<int>(names.size());
    std::vector<float> data(e.pixels() * nc);
    for (size_t k = 0; k < e.pixels(); ++k) {
        float* px = &data[k * nc];
        int c = 0;
        px[c++] = e.depth[k];
        px[c++] = e.uv[2 * k];
        px[c++] = e.uv[2 * k + 1];
        for (int a = 0; a < (quaternion ? 4 : 3); ++a) px[c++] = e.normal[4 * k + a];
        if (!quaternion)
            for (int a = 0; a < 4; ++a) px[c++] = e.tangent[4 * k + a];
        if (ids) px[c++] = e.material[k];
        if (derivatives)
            for (int a = 0; a < 4; ++a) px[c++] = e.uv_derivatives[4 * k + a];
        if (curvature)
            for (int a = 0; a < 3; ++a) px[c++] = e.curvature[3 * k + a];
        if (stretch) px[c++] = e.uv_stretch[k];
    }
    std::map<std::string, std::string> attributes = {
        {"offsetmap:inverseViewProjection", numbers(e.camera.inverse_view_projection.data(), 16)},
        {"offsetmap:eye", numbers(e.camera.eye.data(), 3)},
        {"offsetmap:depth", depth_name(e.camera.depth)},
        {"offsetmap:firstRow", e.camera.first_row == FirstRow::Top ? "top" : "bottom"}};
    // Written only for an orthographic view, so a perspective frame's file is as it was.
    if (e.camera.orthographic) attributes["offsetmap:projection"] = "orthographic";
    if (e.light.kind != LightKind::None)
        attributes["offsetmap:light"] =
            std::string(e.light.kind == LightKind::Point ? "point " : "directional ") +
            numbers(e.light.vector.data(), 3);
    write_float_exr(path, "G-buffer", e.width, e.height, names, data, attributes);
}

namespace {

// A G-buffer file opened once: its reader, its name for messages, its channels by name.
struct GBufferFile {
    std::string path;
    std::unique_ptr<OIIO::ImageInput> in;
    std::string file;  // "G-buffer 'path'"
    std::map<std::string, int> index;

    GBufferFile(const std::string& p, size_t max_bytes)
        : path(p), in(open_image(p, "G-buffer", max_bytes)), file(describe_file("G-buffer", p)) {
        const OIIO::ImageSpec& spec = in->spec();
        for (int c = 0; c < spec.nchannels; ++c) index[spec.channelnames[c]] = c;
    }
    bool engine_form() const { return index.count("depth") && !index.count("Vx"); }
};

// The 'material' channel's values, checked to be material ids.
std::vector<float> material_ids(const std::string& file, const GBuffer& gb,
                                const std::function<float(size_t)>& value) {
    std::vector<float> ids(gb.pixels());
    for (size_t k = 0; k < ids.size(); ++k) {
        const float m = value(k);
        if (!(m >= 0.0f && m <= 65535.0f && m == std::floor(m)))
            throw Error(file + ": channel 'material' holds " + std::to_string(m) + " at pixel (" +
                        std::to_string(k % gb.width) + ", " + std::to_string(k / gb.width) +
                        "); material ids are integers in [0, 65535]");
        ids[k] = m;
    }
    return ids;
}

// The optional curvature channels of either form: kuu kuv kvv (all or none) and stretch beside
// them; every value finite.
struct CurvatureChannels {
    bool curvature = false, stretch = false;

    CurvatureChannels(const GBufferFile& g) {
        const int count =
            static_cast<int>(g.index.count("kuu") + g.index.count("kuv") + g.index.count("kvv"));
        if (count != 0 && count != 3)
            throw Error(g.file + ": the curvature needs all three channels kuu kuv kvv, or none");
        curvature = count == 3;
        stretch = g.index.count("stretch") != 0;
        if (stretch && !curvature)
            throw Error(g.file + ": channel stretch needs the curvature's kuu kuv kvv beside it");
        // Integer channels would be scaled to [0,1] on read.
        for (const char* n : {"kuu", "kuv", "kvv", "stretch"}) {
            if (!g.index.count(n)) continue;
            const OIIO::TypeDesc t = g.in->spec().channelformat(g.index.at(n));
            if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT)
                throw Error(g.file + " stores channel '" + n + "' as " + t.c_str() +
                            "; G-buffer channels must be half or float");
        }
    }
    // Pixel k's (kuu, kuv, kvv, stretch: 1 without the channel) from `ch(k, name)`.
    template <class Channel>
    cl_float4 at(const GBufferFile& g, int width, size_t k, const Channel& ch) const {
        auto finite = [&](const char* name) {
            const float c = ch(k, name);
            if (!std::isfinite(c))
                throw Error(g.file + ": channel " + name + " is not finite at pixel (" +
                            std::to_string(k % width) + ", " + std::to_string(k / width) + ")");
            return c;
        };
        return {{finite("kuu"), finite("kuv"), finite("kvv"), stretch ? finite("stretch") : 1.0f}};
    }
};

EngineScene read_engine_form(GBufferFile& g, size_t max_bytes) {
    const std::string what = "G-buffer";
    const std::string& path = g.path;
    const std::string& file = g.file;
    OIIO::ImageInput* in = g.in.get();
    const OIIO::ImageSpec& spec = in->spec();
    std::map<std::string, int>& index = g.index;
    const bool quaternion = index.count("Qx") != 0;
    std::vector<const char*> needed = {"depth", "u", "v"};
    for (const char* n : quaternion
                             ? std::vector<const char*>{"Qx", "Qy", "Qz", "Qw"}
                             : std::vector<const char*>{"Nx", "Ny", "Nz", "Tx", "Ty", "Tz", "Tw"})
        needed.push_back(n);
    std::string missing;
    for (const char* n : needed) {
        if (!index.count(n)) {
            missing += std::string(missing.empty() ? "" : " ") + n;
            continue;
        }
        const OIIO::TypeDesc t = spec.channelformat(index[n]);
        if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT)
            throw Error(file + " stores channel '" + n + "' as " + t.c_str() +
                        "; G-buffer channels must be half or float");
    }
    if (!missing.empty())
        throw Error(file + " (engine form) lacks channel(s) " + missing +
                    " (needs depth u v and Nx Ny Nz Tx Ty Tz Tw or Qx Qy Qz Qw)");
    auto attribute = [&](const char* name) {
        const std::string text = spec.get_string_attribute(name);
        if (text.empty()) throw Error(file + " (engine form) lacks attribute " + name);
        return text;
    };
    EngineScene e;
    e.width = spec.width;
    e.height = spec.height;
    e.frame = quaternion ? FrameForm::Quaternion : FrameForm::NormalTangent;
    const auto m = parse_numbers(attribute("offsetmap:inverseViewProjection"), 16, file,
                                 "offsetmap:inverseViewProjection");
    std::copy(m.begin(), m.end(), e.camera.inverse_view_projection.begin());
    const auto eye = parse_numbers(attribute("offsetmap:eye"), 3, file, "offsetmap:eye");
    std::copy(eye.begin(), eye.end(), e.camera.eye.begin());
    const std::string depth = attribute("offsetmap:depth");
    if (depth == "gl")
        e.camera.depth = DepthConvention::GL;
    else if (depth == "zero-one")
        e.camera.depth = DepthConvention::ZeroToOne;
    else if (depth == "reversed")
        e.camera.depth = DepthConvention::Reversed;
    else
        throw Error(file + ": attribute offsetmap:depth must be gl, zero-one or reversed, got '" +
                    depth + "'");
    const std::string row = attribute("offsetmap:firstRow");
    if (row != "top" && row != "bottom")
        throw Error(file + ": attribute offsetmap:firstRow must be top or bottom, got '" + row +
                    "'");
    e.camera.first_row = row == "top" ? FirstRow::Top : FirstRow::Bottom;
    if (const std::string proj = spec.get_string_attribute("offsetmap:projection"); !proj.empty()) {
        if (proj != "orthographic" && proj != "perspective")
            throw Error(file +
                        ": attribute offsetmap:projection must be perspective or orthographic, "
                        "got '" +
                        proj + "'");
        e.camera.orthographic = proj == "orthographic";
    }
    if (const std::string light = spec.get_string_attribute("offsetmap:light"); !light.empty()) {
        const size_t space = light.find(' ');
        const std::string kind = light.substr(0, space);
        if (kind != "directional" && kind != "point")
            throw Error(file +
                        ": attribute offsetmap:light must start with directional or point, "
                        "got '" +
                        light + "'");
        e.light.kind = kind == "point" ? LightKind::Point : LightKind::Directional;
        const auto v = parse_numbers(space == std::string::npos ? "" : light.substr(space + 1), 3,
                                     file, "offsetmap:light");
        std::copy(v.begin(), v.end(), e.light.vector.begin());
    }
    check_gbuffer_size(spec.width, spec.height, file);
    check_decode_size(spec, path, what, spec.nchannels * sizeof(float) + 11 * sizeof(float),
                      max_bytes);
    std::vector<float> data = read_float_pixels(*in, path, what, 0, spec.nchannels);
    const size_t n = e.pixels();
    const int nc = spec.nchannels;
    e.depth.resize(n);
    e.uv.resize(2 * n);
    e.normal.assign(4 * n, 0.0f);
    if (!quaternion) e.tangent.resize(4 * n);
    auto ch = [&](size_t k, const char* name) { return data[k * nc + index[name]]; };
    const char* const derivative[] = {"dudx", "dvdx", "dudy", "dvdy"};
    const bool derivatives = std::all_of(std::begin(derivative), std::end(derivative),
                                         [&](const char* d) { return index.count(d) != 0; });
    if (derivatives) e.uv_derivatives.resize(4 * n);
    const CurvatureChannels curved(g);
    if (curved.curvature) e.curvature.resize(3 * n);
    if (curved.stretch) e.uv_stretch.resize(n);
    for (size_t k = 0; k < n; ++k) {
        e.depth[k] = ch(k, "depth");
        e.uv[2 * k] = ch(k, "u");
        e.uv[2 * k + 1] = ch(k, "v");
        const char* const frame[] = {"Nx", "Ny", "Nz", "Tx", "Ty", "Tz", "Tw"};
        const char* const quat[] = {"Qx", "Qy", "Qz", "Qw"};
        if (quaternion) {
            for (int a = 0; a < 4; ++a) e.normal[4 * k + a] = ch(k, quat[a]);
        } else {
            for (int a = 0; a < 3; ++a) e.normal[4 * k + a] = ch(k, frame[a]);
            for (int a = 0; a < 4; ++a) e.tangent[4 * k + a] = ch(k, frame[3 + a]);
        }
        if (derivatives)
            for (int a = 0; a < 4; ++a) e.uv_derivatives[4 * k + a] = ch(k, derivative[a]);
        if (curved.curvature) {
            const cl_float4 c = curved.at(g, e.width, k, ch);
            std::copy_n(c.s, 3, &e.curvature[3 * k]);
            if (curved.stretch) e.uv_stretch[k] = c.s[3];
        }
    }
    return e;
}

}  // namespace

EngineScene load_engine_gbuffer(const std::string& path, size_t max_bytes) {
    GBufferFile g(path, max_bytes);
    return read_engine_form(g, max_bytes);
}

GBuffer load_gbuffer(const std::string& path, size_t max_bytes, std::shared_ptr<Runtime> runtime) {
    const std::string what = "G-buffer";
    GBufferFile g(path, max_bytes);
    if (g.engine_form()) {
        GBuffer gb =
            reconstruct(runtime ? runtime : Runtime::create(), read_engine_form(g, max_bytes));
        if (g.index.count("material")) {
            const int c = g.index["material"];
            const OIIO::TypeDesc t = g.in->spec().channelformat(c);
            if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT)
                throw Error(g.file + " stores channel 'material' as " + t.c_str() +
                            "; G-buffer channels must be half or float");
            const std::vector<float> m = read_float_pixels(*g.in, path, what, c, c + 1);
            gb.material = material_ids(g.file, gb, [&](size_t k) { return m[k]; });
        }
        return gb;
    }
    auto& in = g.in;
    const OIIO::ImageSpec& spec = in->spec();
    const std::string& file = g.file;
    std::map<std::string, int>& index = g.index;
    std::string present;
    for (const auto& n : spec.channelnames) present += (present.empty() ? "" : " ") + n;
    std::string missing;
    for (const char* n : {"u", "v", "Vx", "Vy", "Vz"})
        if (!index.count(n)) missing += std::string(missing.empty() ? "" : " ") + n;
    if (!missing.empty())
        throw Error(file + " lacks channel(s) " + missing +
                    " (needs u v Vx Vy Vz, optionally Lx Ly Lz lod material kuu kuv kvv "
                    "stretch, or the engine form: depth u v "
                    "Nx Ny Nz Tx Ty Tz Tw; it has: " +
                    present + ")");
    int nl = static_cast<int>(index.count("Lx") + index.count("Ly") + index.count("Lz"));
    if (nl != 0 && nl != 3)
        throw Error(file + " has only some of Lx Ly Lz (it has: " + present + ")");
    // Integer channels would be scaled to [0,1] on read: vectors and uv must be stored as numbers.
    for (const char* n : {"u", "v", "Vx", "Vy", "Vz", "Lx", "Ly", "Lz", "lod", "material"}) {
        if (!index.count(n)) continue;
        const OIIO::TypeDesc t = spec.channelformat(index[n]);
        if (t.basetype != OIIO::TypeDesc::HALF && t.basetype != OIIO::TypeDesc::FLOAT)
            throw Error(file + " stores channel '" + n + "' as " + t.c_str() +
                        "; G-buffer channels must be half or float");
    }
    check_gbuffer_size(spec.width, spec.height, file);
    // What is read (every channel as float) and what is kept (uv, view, light, curvature, lod).
    check_decode_size(spec, path, what,
                      spec.nchannels * sizeof(float) + sizeof(cl_float2) + 3 * sizeof(cl_float4) +
                          2 * sizeof(float),
                      max_bytes);
    std::vector<float> data = read_float_pixels(*in, path, what, 0, spec.nchannels);
    GBuffer gb;
    gb.resize(spec.width, spec.height, nl == 3, index.count("lod") != 0);
    const CurvatureChannels curved(g);
    if (curved.curvature) gb.curvature.resize(gb.pixels());
    const int nc = spec.nchannels;
    auto ch = [&](size_t k, const char* name) { return data[k * nc + index[name]]; };
    for (size_t k = 0; k < gb.pixels(); ++k) {
        gb.uv[k] = {{ch(k, "u"), ch(k, "v")}};
        gb.view[k] = {{ch(k, "Vx"), ch(k, "Vy"), ch(k, "Vz"), 0.0f}};
        if (gb.has_light()) gb.light[k] = {{ch(k, "Lx"), ch(k, "Ly"), ch(k, "Lz"), 0.0f}};
        if (gb.has_lod()) gb.lod[k] = ch(k, "lod");
        if (curved.curvature) gb.curvature[k] = curved.at(g, gb.width, k, ch);
    }
    if (index.count("material"))
        gb.material = material_ids(file, gb, [&](size_t k) { return ch(k, "material"); });
    return gb;
}

void save_gbuffer(const std::string& path, const GBuffer& gb) {
    std::vector<std::string> names = {"u", "v", "Vx", "Vy", "Vz"};
    if (gb.has_light()) names.insert(names.end(), {"Lx", "Ly", "Lz"});
    if (gb.has_lod()) names.push_back("lod");
    if (gb.has_material()) names.push_back("material");
    if (gb.has_curvature()) names.insert(names.end(), {"kuu", "kuv", "kvv", "stretch"});
    const int nc = static_cast<int>(names.size());
    std::vector<float> data(gb.pixels() * nc);
    for (size_t k = 0; k < gb.pixels(); ++k) {
        float* px = &data[k * nc];
        int c = 0;
        px[c++] = gb.uv[k].s[0];
        px[c++] = gb.uv[k].s[1];
        for (int a = 0; a < 3; ++a) px[c++] = gb.view[k].s[a];
        if (gb.has_light())
            for (int a = 0; a < 3; ++a) px[c++] = gb.light[k].s[a];
        if (gb.has_lod()) px[c++] = gb.lod[k];
        if (gb.has_material()) px[c++] = gb.material[k];
        if (gb.has_curvature())
            for (int a = 0; a < 4; ++a) px[c++] = gb.curvature[k].s[a];
    }
    write_float_exr(path, "G-buffer", gb.width, gb.height, names, data);
}

}  // namespace offsetmap
