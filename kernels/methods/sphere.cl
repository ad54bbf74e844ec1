// sphere (Donnelly 05; Premecz section 2.4): sphere tracing through a 3D distance map of the
// relief, precomputed by kernels/prep/distance.cl (`res` voxels per side over the tile,
// `layers` through the slab; `steps` at most). From the top plane the ray advances by the
// distance to the relief, so it can never pass through it.
// Conservative sampling: each voxel stores the distance from its whole box to a proxy that
// contains the relief, so the value of the voxel holding p is a safe step from anywhere inside it
// (Donnelly samples distances at voxel centres trilinearly, which can overestimate and overshoot).
// The march ends when the step is 0, i.e. p's voxel touches the proxy: the error is then at most
// one voxel (1/res across, s/layers in height) plus the proxy's excess over the surface, both
// shrinking as res and layers grow; or when the steps run out (sphere tracing converges slowly at
// grazing views, where each step shrinks the gap by a factor of about 1 - V.z).
// Cost: one distance fetch per step, counted as one fetch.
// Lanes that stop early wait for the others (a fixed step budget).
OM_INLINE OmF om_sphere_distance(const OmField* f, const OmOffsetParams* P, int res, int layers,
                                 OmF u, OmF v, OmF z) {
    OmF x = clamp(u * (float)res, -1.0e7f, 1.0e7f), y = clamp(v * (float)res, -1.0e7f, 1.0e7f);
    OmI i = OM_TO_INT(OM_LFLOOR(x)), j = OM_TO_INT(OM_LFLOOR(y));
    OmI k = clamp(OM_TO_INT(z), 0, layers - 1);
    const int wrap = P->address_mode == OM_ADDRESS_WRAP;
    i = om_address(i, (OmI)res, wrap);
    j = om_address(j, (OmI)res, wrap);
    return OM_GATHER(f->aux, (k * res + j) * res + i);
}

OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    int res = (int)OM_PARAM(P, res), layers = (int)OM_PARAM(P, layers);
    OmI steps = om_step_count(r, (OmF)OM_PARAM(P, steps));
    // The layer coordinate z = w layers / s of the ray at t, w = s (t_exit - t) / (t_exit -
    // t_enter): one multiply per step, where two divisions lay on the step's dependent chain
    // (a point on a voxel face may fall in either voxel: both boxes hold it, so both are safe).
    OmF z_per_t = (float)layers / (r->t_exit - r->t_enter);
    OmF t = r->t_enter;
    OmI marching = active;
    for (int n = 0; OM_ANY(marching); ++n) {
        marching &= (OmI)n < steps;
        OmF z = (r->t_exit - t) * z_per_t;
        OmF d = om_sphere_distance(f, P, res, layers, r->u - t * r->vx, r->v - t * r->vy, z);
        *fetches += OM_ONE(marching);
        marching &= d > 0.0f;
        t = OM_SEL(t, fmin(t + d, r->t_exit), marching);
    }
    return t;
}
