// sphere (Donnelly 05; Premecz section 2.4): sphere tracing through a 3D distance map of the
// relief, precomputed by kernels/prep/distance.cl (p[0] = res voxels per side over the tile,
// p[1] = layers through the slab, p[2] = steps). From the top plane the ray advances by the
// distance to the relief, so it can never pass through it.
// Conservative sampling: each voxel stores the distance from its whole box to a proxy that
// contains the relief, so the value of the voxel holding p is a safe step from anywhere inside it
// (Donnelly samples distances at voxel centres trilinearly, which can overestimate and overshoot).
// The march ends when the step is 0, i.e. p's voxel touches the proxy: the error is then at most
// one voxel (1/res across, s/layers in height) plus the proxy's excess over the surface, both
// shrinking as res and layers grow; or when the steps run out (sphere tracing converges slowly at
// grazing views, where each step shrinks the gap by a factor of about 1 - V.z).
// Cost: one distance fetch per step, counted as one fetch.
inline float om_sphere_distance(const OmHeightField* f, const OmOffsetParams* P, int res,
                                int layers, float2 uv, float w) {
    float x = clamp(uv.x * res, -1.0e7f, 1.0e7f), y = clamp(uv.y * res, -1.0e7f, 1.0e7f);
    int i = (int)om_floor(x), j = (int)om_floor(y);
    int k = clamp((int)(w / P->scale * layers), 0, layers - 1);
    if (P->address_mode == OM_ADDRESS_WRAP) {
        i = om_wrap_index(i, res);
        j = om_wrap_index(j, res);
    } else {
        i = clamp(i, 0, res - 1);
        j = clamp(j, 0, res - 1);
    }
    return f->aux[(k * res + j) * res + i];
}

float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    int res = (int)P->p[0], layers = (int)P->p[1], steps = om_lod_count(r, P->p[2]);
    float span = r->t_exit - r->t_enter;
    float t = r->t_enter;
    for (int n = 0; n < steps; ++n) {
        float w = r->scale * (1.0f - (t - r->t_enter) / span);
        float d = om_sphere_distance(f, P, res, layers, om_ray_uv(r, t), w);
        f->fetches += 1u;
        if (d <= 0.0f) break;
        t = fmin(t + d, r->t_exit);
    }
    *t_hit = t;
    return om_ray_uv(r, t);
}
