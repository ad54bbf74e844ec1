// The truth's shadows: the displaced meshes' own shadow map from the light, and the truth frame's
// points tested against it (renderer/truth.hpp).
#include <cmath>

#include "offsetmap/error.hpp"
#include "offsetmap/renderer/truth.hpp"
#include "offsetmap/shadow_mask_pass.hpp"
#include "offsetmap/timing.hpp"

namespace offsetmap::renderer {

ShadowTruth shadow_truth(const std::shared_ptr<Runtime>& rt, FrameRenderer& camera,
                         const Scene& scene, const std::vector<LoadedMaterial>& table,
                         const std::vector<MethodParams>& methods, int width, int height,
                         int map_size, int pcf_radius, float texels_per_quad) {
    const Stopwatch clock;
    if (scene.light.kind != LightKind::Directional)
        throw Error("the shadow truth needs the scene's light to be directional");
    if (camera.gbuffer().width != width || camera.gbuffer().height != height)
        throw Error("the shadow truth needs a rendered " + std::to_string(width) + "x" +
                    std::to_string(height) + " frame of the camera");
    const size_t n = static_cast<size_t>(width) * height;
    TessellationOptions options;
    options.texels_per_quad = texels_per_quad;
    options.width = width;
    options.height = height;
    GeometryFrame truth;
    {
        const Tessellation seen = displace_scene(scene, table, options);
        truth = camera.render_geometry(seen.scene, 0);
    }
    Scene lit = scene;
    const std::array<float, 3>& l = scene.light.vector;
    lit.camera = light_camera(scene, {l[0], l[1], l[2]});
    options.width = options.height = map_size;
    options.keep_back_faces = true;
    const Tessellation tess = displace_scene(lit, table, options);
    FrameRenderer light(rt, lit, table, methods, map_size, map_size, ShadeSettings());
    const GeometryFrame map = light.render_geometry(tess.scene, 0);

    auto upload = [&](const std::vector<float>& v) {
        return cl::Buffer(rt->context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                          v.size() * sizeof(float), const_cast<float*>(v.data()));
    };
    const std::vector<float> depth_rows = flip_row_order(truth.depth, width, height);
    const std::vector<float> map_rows = flip_row_order(map.depth, map_size, map_size);
    const cl::Buffer depth = upload(depth_rows), shadow_map = upload(map_rows);
    const cl::Buffer mask(rt->context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
    ShadowMaskInputs in;
    in.width = width;
    in.height = height;
    in.camera = camera.pass_camera();
    in.depth = depth;
    in.map = light.shadow_map_view(shadow_map);
    in.pcf_radius = pcf_radius;
    ShadowMaskPass(rt).enqueue(in, {mask}).wait();
    ShadowTruth out;
    out.lit.resize(n);
    rt->queue().enqueueReadBuffer(mask, CL_TRUE, 0, n * sizeof(float), out.lit.data());
    out.lit = flip_row_order(out.lit, width, height);
    out.normal = truth.normal;
    for (size_t k = 0; k < n; ++k)
        if (!(truth.depth[k] < 1.0f)) out.lit[k] = std::nanf("");
    out.triangles = tess.triangles;
    out.ms = clock.total();
    return out;
}

ShadowMismatch shadow_mismatch(const ShadowTruth& truth, const std::vector<float>& visibility,
                               const std::vector<float>& depth, const std::array<float, 3>& toward,
                               std::vector<std::uint8_t>* mismatched) {
    const size_t n = truth.lit.size();
    const std::vector<float>& normal = truth.normal;
    if (visibility.size() != n || depth.size() != n || normal.size() != 3 * n)
        throw Error("shadow_mismatch: the frame's planes and the truth's differ in size");
    if (mismatched) mismatched->assign(n, 0);
    ShadowMismatch m;
    for (size_t k = 0; k < n; ++k) {
        const float* nk = &normal[3 * k];
        const float facing = nk[0] * toward[0] + nk[1] * toward[1] + nk[2] * toward[2];
        if (std::isnan(truth.lit[k]) || !(depth[k] < 1.0f) || !(facing > 0.0f)) continue;
        ++m.compared;
        const bool differ = std::abs(truth.lit[k] - visibility[k]) >= 0.5f;
        m.mismatch += differ;
        if (mismatched) (*mismatched)[k] = differ;
    }
    return m;
}

}  // namespace offsetmap::renderer
