// The rendered frame's pixel depth offset: the surface point P, from the window depth d and the
// inverse view-projection (common/unproject.cl, in the camera's conventions), moved along its eye
// ray by the offset pass's depth t times the uv density (world units per uv unit; t is in uv units
// along unit tangent-space V, and tangent space is in uv units on all three axes), away from the
// eye for t > 0, then projected back to window depth. Sky (d at or past the far plane) and pixels
// the pass left alone (t = 0, NaN or infinite) keep their depth. A work-item takes OM_DEPTH_RUN
// pixels of a row: one pixel each made the launch's work-groups cost more than their arithmetic on
// a CPU (32,400 groups at 1080p).
__kernel void om_depth_offset(const OmDepthOffsetParams P, __global const float* depth,
                              __global const float* t_in, __global const float* density,
                              __global float* out) {
    const int x0 = (int)get_global_id(0) * OM_DEPTH_RUN, y = (int)get_global_id(1);
    if (x0 >= P.grid.width || y >= P.grid.height) return;
    const int x1 = min(x0 + OM_DEPTH_RUN, P.grid.width);
    const float ny = OM_PIXEL_NDC_Y(P.grid.row0_ndc_y, y, P.grid.height);
    for (int x = x0; x < x1; ++x) {
        const int k = y * P.grid.width + x;
        const float d = depth[k], t = t_in[k];
        // Branch-free (the kept depth selected at the end): the run's loop vectorises.
        const int keep =
            P.grid.far_sign * (d - P.grid.far_depth) >= 0.0f || !(fabs(t) > 0.0f) || isinf(t);
        const float nx = OM_PIXEL_NDC_X((float)(2 * x + 1), P.grid.width);
        const float nz = OM_PIXEL_NDC_Z(P.grid, d);
        OM_UNPROJECT(float, P.inv_view_proj, nx, ny, nz, px, py, pz);
        const float ex = P.eye[0] - P.eye_w * px, ey = P.eye[1] - P.eye_w * py,
                    ez = P.eye[2] - P.eye_w * pz;
        // Along the unit eye ray, away from the eye for t > 0 (orthographic: along -eye).
        const float step = (keep ? 0.0f : t * density[k]) / sqrt(ex * ex + ey * ey + ez * ez);
        const float qx = px - step * ex, qy = py - step * ey, qz = pz - step * ez;
        const float* c = P.view_proj;
        const float cz = c[2] * qx + c[6] * qy + c[10] * qz + c[14];
        const float cw = c[3] * qx + c[7] * qy + c[11] * qz + c[15];
        const float after = P.grid.ndc_depth_scale * cz / cw + P.grid.ndc_depth_offset;
        out[k] = keep ? d : clamp(after, 0.0f, 1.0f);
    }
}
