// The engine-shaped G-buffer turned into the explicit one the offset and shade passes read. Per
// pixel: the surface point P from the depth and the inverse view-projection, V = (eye - P) / |eye -
// P| and L (toward a directional light, or a point light's position) expressed in the pixel's
// tangent frame, orthonormalised (Gram-Schmidt of the tangent against the normal; B = h N x T,
// h = -1 where the handedness is negative); uv as stored.
// Sky (depth at or past the far plane) writes a NaN uv: an empty pixel. A depth that is not
// finite, a degenerate frame (zero or non-finite normal or quaternion, a tangent along the normal)
// or a point the matrix cannot place writes a NaN V: the offset pass flags it INVALID and passes
// its uv through.
// Each input is a buffer, its storage in the parameters, or an image where the host defines
// OM_IMAGE_<INPUT> (one program per combination).

// Two steps, so the OM_IMAGE_* argument expands to 0 or 1 before it is pasted.
#define OM_INPUT_ARG(name, image) OM_INPUT_ARG_(name, image)
#define OM_INPUT_ARG_(name, image) OM_INPUT_ARG_##image(name)
#define OM_INPUT_ARG_1(name) __read_only image2d_t name
#define OM_INPUT_ARG_0(name) __global const uchar* name
#define OM_READ(name, image, storage, n) OM_READ_(name, image, storage, n)
#define OM_READ_(name, image, storage, n) OM_READ_##image(name, storage, n)
#define OM_READ_1(name, storage, n) read_imagef(name, om_texel_sampler, (int2)(x, y))
#define OM_READ_0(name, storage, n) om_stored_n(name, storage, k, n)

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

// The columns of a rotation by the unit quaternion q = (x, y, z, w): tangent, bitangent, normal.
OM_INLINE void om_quaternion_frame(float4 q, float3* t, float3* b, float3* n) {
    float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
    float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
    float wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
    *t = (float3)(1.0f - 2.0f * (yy + zz), 2.0f * (xy + wz), 2.0f * (xz - wy));
    *b = (float3)(2.0f * (xy - wz), 1.0f - 2.0f * (xx + zz), 2.0f * (yz + wx));
    *n = (float3)(2.0f * (xz + wy), 2.0f * (yz - wx), 1.0f - 2.0f * (xx + yy));
}

OM_INLINE float4 om_in_frame(float3 v, float3 t, float3 b, float3 n) {
    return (float4)(dot(v, t), dot(v, b), dot(v, n), 0.0f);
}

__kernel void om_reconstruct(const OmReconstructParams P, OM_INPUT_ARG(depth_in, OM_IMAGE_DEPTH),
                             OM_INPUT_ARG(frame_in, OM_IMAGE_FRAME),
                             OM_INPUT_ARG(tangent_in, OM_IMAGE_TANGENT),
                             OM_INPUT_ARG(uv_in, OM_IMAGE_UV), __global float2* out_uv,
                             __global float4* out_view, __global float4* out_light) {
    const int x = get_global_id(0), y = get_global_id(1);
    if (x >= P.width || y >= P.height) return;
    const size_t k = (size_t)y * P.width + x;
    float2 uv = OM_READ(uv_in, OM_IMAGE_UV, P.uv_storage, 2).xy;
    const float d = OM_READ(depth_in, OM_IMAGE_DEPTH, P.depth_storage, 1).x;
    const float4 fa = OM_READ(frame_in, OM_IMAGE_FRAME, P.frame_storage, 4);

    // The pixel centre in NDC, then P = (M ndc).xyz / (M ndc).w.
    const float nx = (float)(2 * x + 1) / (float)P.width - 1.0f;
    const float ny = P.row0_ndc_y * (1.0f - (float)(2 * y + 1) / (float)P.height);
    const float nz = P.depth_convention == OM_DEPTH_GL ? 2.0f * d - 1.0f : d;
    const float* m = P.inv_view_proj;
    float4 c = (float4)(m[0], m[1], m[2], m[3]) * nx + (float4)(m[4], m[5], m[6], m[7]) * ny +
               (float4)(m[8], m[9], m[10], m[11]) * nz + (float4)(m[12], m[13], m[14], m[15]);
    const float3 p = c.xyz / c.w;
    const float3 to_eye = (float3)(P.eye[0], P.eye[1], P.eye[2]) - p;
    const float3 v = to_eye * rsqrt(dot(to_eye, to_eye));

    float3 t, b, n;
    int ok;
    if (P.frame == OM_FRAME_QUATERNION) {
        // Quaternions q and -q are the same rotation: the sign of w carries the handedness.
        const float q2 = dot(fa, fa);
        ok = isfinite(q2) && q2 > 1.0e-12f;
        om_quaternion_frame(fa * rsqrt(q2), &t, &b, &n);
        if (fa.w < 0.0f) b = -b;
    } else {
        const float4 ta = OM_READ(tangent_in, OM_IMAGE_TANGENT, P.tangent_storage, 4);
        const float n2 = dot(fa.xyz, fa.xyz);
        n = fa.xyz * rsqrt(n2);
        const float3 tp = ta.xyz - n * dot(n, ta.xyz);
        const float tp2 = dot(tp, tp);
        // A tangent within about 0.06 degrees of the normal spans no plane.
        ok = isfinite(n2) && n2 > 1.0e-12f && isfinite(tp2) && tp2 > 1.0e-6f * dot(ta.xyz, ta.xyz);
        t = tp * rsqrt(tp2);
        b = cross(n, t);
        if (ta.w < 0.0f) b = -b;
    }
    ok = ok && isfinite(d) && all(isfinite(v));

    const int sky = P.depth_convention == OM_DEPTH_REVERSED ? d <= 0.0f : d >= 1.0f;
    if (sky) uv = (float2)(NAN, NAN);
    out_uv[k] = uv;
    out_view[k] = sky ? (float4)(0.0f, 0.0f, 1.0f, 0.0f)
                      : ok ? om_in_frame(v, t, b, n) : (float4)(NAN);
    if (P.light == OM_LIGHT_NONE) return;
    float3 l = (float3)(P.light_vec[0], P.light_vec[1], P.light_vec[2]);
    if (P.light == OM_LIGHT_POINT) {
        l -= p;
        l *= rsqrt(dot(l, l));
    }
    out_light[k] = ok && all(isfinite(l)) ? om_in_frame(l, t, b, n) : (float4)(0.0f, 0.0f, 1.0f, 0.0f);
}
