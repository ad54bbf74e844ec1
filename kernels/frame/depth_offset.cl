// The rendered frame's pixel depth offset: the surface point P, from GL's window depth d and the
// inverse view-projection, moved along its eye ray by the offset pass's depth t times the uv
// density (world units per uv unit; t is in uv units along unit tangent-space V, and tangent
// space is in uv units on all three axes), away from the eye for t > 0, then projected back to
// window depth, which the host writes into GL's depth target. Sky (d >= 1) and pixels the pass
// left alone (t = 0, NaN or infinite) keep their depth. Rows bottom first, as GL reads them. A
// work-item takes OM_DEPTH_RUN pixels of a row: one pixel each made the launch's work-groups cost
// more than their arithmetic on a CPU (32,400 groups at 1080p).
__kernel void om_depth_offset(const OmDepthOffsetParams P, __global const float* depth,
                              __global const float* t_in, __global const float* density,
                              __global float* out) {
    const int x0 = (int)get_global_id(0) * OM_DEPTH_RUN, y = (int)get_global_id(1);
    if (x0 >= P.width || y >= P.height) return;
    const int x1 = min(x0 + OM_DEPTH_RUN, P.width);
    for (int x = x0; x < x1; ++x) {
        const int k = y * P.width + x;
        const float d = depth[k], t = t_in[k];
        // Branch-free (the kept depth selected at the end): the run's loop vectorises.
        const int keep = d >= 1.0f || !(fabs(t) > 0.0f) || isinf(t);
        // The pixel centre in NDC (GL: rows bottom first, z = 2d - 1), then P = (M ndc).xyz / w.
        const float nx = (float)(2 * x + 1) / (float)P.width - 1.0f;
        const float ny = (float)(2 * y + 1) / (float)P.height - 1.0f;
        const float nz = 2.0f * d - 1.0f;
        const float* m = P.inv_view_proj;
        const float w = m[3] * nx + m[7] * ny + m[11] * nz + m[15];
        const float px = (m[0] * nx + m[4] * ny + m[8] * nz + m[12]) / w;
        const float py = (m[1] * nx + m[5] * ny + m[9] * nz + m[13]) / w;
        const float pz = (m[2] * nx + m[6] * ny + m[10] * nz + m[14]) / w;
        const float ex = P.eye[0] - P.eye_w * px, ey = P.eye[1] - P.eye_w * py,
                    ez = P.eye[2] - P.eye_w * pz;
        // Along the unit eye ray, away from the eye for t > 0 (orthographic: along -eye).
        const float step = (keep ? 0.0f : t * density[k]) / sqrt(ex * ex + ey * ey + ez * ez);
        const float qx = px - step * ex, qy = py - step * ey, qz = pz - step * ez;
        const float* c = P.view_proj;
        const float cz = c[2] * qx + c[6] * qy + c[10] * qz + c[14];
        const float cw = c[3] * qx + c[7] * qy + c[11] * qz + c[15];
        out[k] = keep ? d : clamp(0.5f * cz / cw + 0.5f, 0.0f, 1.0f);
    }
}
