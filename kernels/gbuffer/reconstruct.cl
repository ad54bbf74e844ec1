// The engine-shaped G-buffer turned into the explicit one the offset and shade passes read. Per
// pixel: the surface point P from the depth and the inverse view-projection, V = (eye - P) / |eye -
// P| and L (toward a directional light, or a point light's position) expressed in the pixel's
// tangent frame, orthonormalised (Gram-Schmidt of the tangent against the normal; B = h N x T,
// h = -1 where the handedness is negative); uv as stored.
// Sky (depth at or past the far plane) writes a NaN uv: an empty pixel. A depth that is not
// finite, a degenerate frame (zero or non-finite normal or quaternion, a tangent along the normal)
// or a point the matrix cannot place writes a NaN V: the offset pass flags it INVALID and passes
// its uv through.
// Each input is a buffer, its storage fixed at build time (OM_STORAGE_<INPUT>, one of
// OM_STORAGE_*, so the decoding is straight-line code), or an image where the host defines
// OM_IMAGE_<INPUT>. One program per combination.

// Two steps, so the OM_IMAGE_* argument expands to 0 or 1 before it is pasted.
#define OM_INPUT_ARG(name, image) OM_INPUT_ARG_(name, image)
#define OM_INPUT_ARG_(name, image) OM_INPUT_ARG_##image(name)
#define OM_INPUT_ARG_1(name) __read_only image2d_t name
#define OM_INPUT_ARG_0(name) __global const uchar* name
// Declares v0 .. v3, the first n values of pixel (x, y) (the rest 0), as scalars.
#define OM_FETCH(name, image, storage, n, v) OM_FETCH_(name, image, storage, n, v)
#define OM_FETCH_(name, image, storage, n, v) OM_FETCH_##image(name, storage, n, v)
#define OM_FETCH_1(name, storage, n, v)                                        \
    const float4 v##_ = read_imagef(name, om_texel_sampler, (int2)(x, y));     \
    const float v##0 = v##_.x, v##1 = v##_.y, v##2 = v##_.z, v##3 = v##_.w
#define OM_FETCH_0(name, storage, n, v)                                        \
    const float v##0 = OM_STORED(name, storage, k * n),                        \
                v##1 = n > 1 ? OM_STORED(name, storage, k * n + 1) : 0.0f,     \
                v##2 = n > 2 ? OM_STORED(name, storage, k * n + 2) : 0.0f,     \
                v##3 = n > 3 ? OM_STORED(name, storage, k * n + 3) : 0.0f

// The frame's form and the light are fixed at build time too (OM_QUATERNION_FRAME; OM_LIT, with
// OM_POINT_LIGHT for a point light).
#ifndef OM_STORAGE_DEPTH
#define OM_STORAGE_DEPTH 0  // OM_STORAGE_FLOAT, as a literal for OM_STORED
#endif
#ifndef OM_STORAGE_FRAME
#define OM_STORAGE_FRAME 0  // OM_STORAGE_FLOAT, as a literal for OM_STORED
#endif
#ifndef OM_STORAGE_TANGENT
#define OM_STORAGE_TANGENT 0  // OM_STORAGE_FLOAT, as a literal for OM_STORED
#endif
#ifndef OM_STORAGE_UV
#define OM_STORAGE_UV 0  // OM_STORAGE_FLOAT, as a literal for OM_STORED
#endif
#ifndef OM_IMAGE_DEPTH
#define OM_IMAGE_DEPTH 0
#endif
#ifndef OM_IMAGE_FRAME
#define OM_IMAGE_FRAME 0
#endif
#ifndef OM_IMAGE_TANGENT
#define OM_IMAGE_TANGENT 0
#endif
#ifndef OM_IMAGE_UV
#define OM_IMAGE_UV 0
#endif

// Written for PoCL's loop vectoriser, which widens a work-group's pixels only in straight-line
// scalar code: no float3 or float4 values (images aside), no switch, no run-time branch on the
// frame's form or the light. It still declines the loop (it names an instruction it cannot
// widen), so on a CPU this pass costs about 14 ns/pixel against 5 for its loads and stores
// alone (720p, AVX-512, PoCL 3.1; the bench's "reconstruct" entry); explicit lanes as in
// offset.cl are the way to close that.
#define OM_DOT3(a, b) (a##x * b##x + a##y * b##y + a##z * b##z)

__kernel void om_reconstruct(const OmReconstructParams P, OM_INPUT_ARG(depth_in, OM_IMAGE_DEPTH),
                             OM_INPUT_ARG(frame_in, OM_IMAGE_FRAME),
                             OM_INPUT_ARG(tangent_in, OM_IMAGE_TANGENT),
                             OM_INPUT_ARG(uv_in, OM_IMAGE_UV), __global float2* out_uv,
                             __global float4* out_view, __global float4* out_light) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= P.width || y >= P.height) return;
    const size_t k = (size_t)y * P.width + x;
    OM_FETCH(uv_in, OM_IMAGE_UV, OM_STORAGE_UV, 2, uv);
    OM_FETCH(depth_in, OM_IMAGE_DEPTH, OM_STORAGE_DEPTH, 1, depth);
    OM_FETCH(frame_in, OM_IMAGE_FRAME, OM_STORAGE_FRAME, 4, f);
    const float d = depth0;

    // The pixel centre in NDC, then p = (M ndc).xyz / (M ndc).w and V = (eye - p) / |eye - p|.
    const float nx = (float)(2 * x + 1) / (float)P.width - 1.0f;
    const float ny = P.row0_ndc_y * (1.0f - (float)(2 * y + 1) / (float)P.height);
    const float nz = P.depth_scale * d + P.depth_offset;  // 2d - 1 (GL) or d
    const float* m = P.inv_view_proj;
    const float cw = m[3] * nx + m[7] * ny + m[11] * nz + m[15];
    const float px = (m[0] * nx + m[4] * ny + m[8] * nz + m[12]) / cw;
    const float py = (m[1] * nx + m[5] * ny + m[9] * nz + m[13]) / cw;
    const float pz = (m[2] * nx + m[6] * ny + m[10] * nz + m[14]) / cw;
    float vx = P.eye[0] - px, vy = P.eye[1] - py, vz = P.eye[2] - pz;
    const float iv = rsqrt(OM_DOT3(v, v));
    vx *= iv;
    vy *= iv;
    vz *= iv;

    float tx, ty, tz, bx, by, bz, nx_, ny_, nz_;
    int ok;
#ifdef OM_QUATERNION_FRAME
    {
        // The columns of the rotation by the unit quaternion: tangent, bitangent, normal. q and -q
        // are the same rotation, so the sign of w carries the handedness.
        const float q2 = f0 * f0 + f1 * f1 + f2 * f2 + f3 * f3;
        ok = isfinite(q2) && q2 > 1.0e-12f;
        const float iq = rsqrt(q2);
        const float qx = f0 * iq, qy = f1 * iq, qz = f2 * iq, qw = f3 * iq;
        const float xx = qx * qx, yy = qy * qy, zz = qz * qz;
        const float xy = qx * qy, xz = qx * qz, yz = qy * qz;
        const float wx = qw * qx, wy = qw * qy, wz = qw * qz;
        const float h = f3 < 0.0f ? -1.0f : 1.0f;
        tx = 1.0f - 2.0f * (yy + zz);
        ty = 2.0f * (xy + wz);
        tz = 2.0f * (xz - wy);
        bx = h * (2.0f * (xy - wz));
        by = h * (1.0f - 2.0f * (xx + zz));
        bz = h * (2.0f * (yz + wx));
        nx_ = 2.0f * (xz + wy);
        ny_ = 2.0f * (yz - wx);
        nz_ = 1.0f - 2.0f * (xx + yy);
    }
#else
    {
        OM_FETCH(tangent_in, OM_IMAGE_TANGENT, OM_STORAGE_TANGENT, 4, t);
        const float n2 = f0 * f0 + f1 * f1 + f2 * f2;
        const float in_ = rsqrt(n2);
        nx_ = f0 * in_;
        ny_ = f1 * in_;
        nz_ = f2 * in_;
        const float nt = nx_ * t0 + ny_ * t1 + nz_ * t2;
        tx = t0 - nx_ * nt;
        ty = t1 - ny_ * nt;
        tz = t2 - nz_ * nt;
        const float tp2 = OM_DOT3(t, t);
        // A tangent within about 0.06 degrees of the normal spans no plane.
        ok = isfinite(n2) && n2 > 1.0e-12f && isfinite(tp2) &&
             tp2 > 1.0e-6f * (t0 * t0 + t1 * t1 + t2 * t2);
        const float it = rsqrt(tp2);
        tx *= it;
        ty *= it;
        tz *= it;
        const float h = t3 < 0.0f ? -1.0f : 1.0f;  // B = h N x T
        bx = h * (ny_ * tz - nz_ * ty);
        by = h * (nz_ * tx - nx_ * tz);
        bz = h * (nx_ * ty - ny_ * tx);
    }
#endif
    const float vt = OM_DOT3(v, t), vb = OM_DOT3(v, b), vn = vx * nx_ + vy * ny_ + vz * nz_;
    ok = ok && isfinite(d) && isfinite(vt) && isfinite(vb) && isfinite(vn);

    const int sky = P.far_sign * (d - P.far_depth) >= 0.0f;  // d >= 1, or d <= 0 when reversed
    // Stored as scalars too.
    __global float* ouv = (__global float*)out_uv + 2 * k;
    __global float* ov = (__global float*)out_view + 4 * k;
    ouv[0] = sky ? NAN : uv0;
    ouv[1] = sky ? NAN : uv1;
    ov[0] = sky ? 0.0f : ok ? vt : NAN;
    ov[1] = sky ? 0.0f : ok ? vb : NAN;
    ov[2] = sky ? 1.0f : ok ? vn : NAN;
    ov[3] = sky ? 0.0f : ok ? 0.0f : NAN;
#ifdef OM_LIT
    float lx = P.light_vec[0], ly = P.light_vec[1], lz = P.light_vec[2];
#ifdef OM_POINT_LIGHT
    {
        lx -= px;
        ly -= py;
        lz -= pz;
        const float il = rsqrt(OM_DOT3(l, l));
        lx *= il;
        ly *= il;
        lz *= il;
    }
#endif
    const float lt = OM_DOT3(l, t), lb = OM_DOT3(l, b), ln = lx * nx_ + ly * ny_ + lz * nz_;
    const int lit = ok && isfinite(lt) && isfinite(lb) && isfinite(ln);
    __global float* ol = (__global float*)out_light + 4 * k;
    ol[0] = lit ? lt : 0.0f;
    ol[1] = lit ? lb : 0.0f;
    ol[2] = lit ? ln : 1.0f;
    ol[3] = 0.0f;
#endif
}
