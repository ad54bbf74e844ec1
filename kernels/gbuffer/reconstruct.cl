// The engine-shaped G-buffer turned into the explicit one the offset and shade passes read. Per
// pixel: the surface point P from the depth and the inverse view-projection, V = (eye - P) / |eye -
// P| and L (toward a directional light, or a point light's position) expressed in the pixel's
// tangent frame, orthonormalised (Gram-Schmidt of the tangent against the normal; B = h N x T,
// h = -1 where the handedness is negative); uv as stored.
// Sky (depth at or past the far plane) writes a NaN uv: an empty pixel. A depth that is not
// finite, a degenerate frame (zero or non-finite normal or quaternion, a tangent along the normal)
// or a point the matrix cannot place writes a NaN V: the offset pass flags it INVALID and passes
// its uv through.
// Each work-item takes OM_LANES consecutive pixels of one row (lanes.h: one SIMD register per
// value on a CPU, one pixel on a GPU); the host launches ceil(width / OM_LANES) x height. Fixed at
// build time, one program per combination: each input's form, an image where the host defines
// OM_IMAGE_<INPUT>, else a buffer of OM_STORAGE_<INPUT> (a literal OM_STORAGE_* value); the frame's
// form (OM_QUATERNION_FRAME) and the light (OM_LIT, with OM_POINT_LIGHT for a point light).
// OM_TRIPLANAR (common/triplanar.cl): the pixels whose material id is triplanar in `tri_of_id`
// (world_scale, sharpness, cutoff, 1) take their frame, uv, V and L from their largest
// projection; their second and third projections' uv and V go to the extra planes where their
// weight is not zero (with the id; 0 where it is, so the material frame traces only those; the
// shade turns L itself), and every pixel gets its weights, projections and normal packed in
// `out_blend`. Without uv (OM_NO_UV) or a tangent (OM_NO_TANGENT) the other pixels get an empty uv
// or an invalid frame.

#define OM_INPUT_ARG(name, image) OM_INPUT_ARG_(name, image)
#define OM_INPUT_ARG_(name, image) OM_INPUT_ARG_##image(name)
#define OM_INPUT_ARG_1(name) __read_only image2d_t name
#define OM_INPUT_ARG_0(name) __global const uchar* name

// Declares OmF v0 .. v3: the first n values of the work-item's pixels (the rest 0). Lanes past the
// row's end repeat its last pixel.
#define OM_FETCH(name, image, storage, n, v) OM_FETCH_(name, image, storage, n, v)
#define OM_FETCH_(name, image, storage, n, v) OM_FETCH_##image(name, storage, n, v)
// A full work-item of float or half values: vector loads and shuffles (as offset.cl loads its
// G-buffer), where a lane-by-lane load cost several times as much (the bench's reconstruct entry).
#if OM_LANES == 16
// The i-th 16 values from element b on (vloadn needs only the element's alignment).
#define OM_VL16_0(q, b, i) vload16(i, (__global const float*)(q) + (b))
#define OM_VL16_1(q, b, i) vload_half16(i, (__global const half*)(q) + (b))
#define OM_VL16_2(q, b, i) ((float16)0.0f)  // never taken (OM_HAS_FULL_LOAD)
#define OM_VL16_3(q, b, i) ((float16)0.0f)
#define OM_VL16_4(q, b, i) ((float16)0.0f)
#define OM_VL16(q, storage, b, i) OM_VL16_(q, storage, b, i)
#define OM_VL16_(q, storage, b, i) OM_VL16_##storage(q, b, i)
#define OM_FULL_LOAD(p, storage, n, v)                                                      \
    do {                                                                                    \
        const size_t e_ = (row + x0) * (n);                                                 \
        if ((n) == 1) {                                                                     \
            v##0 = OM_VL16(p, storage, e_, 0);                                              \
        } else if ((n) == 2) {                                                              \
            const float16 a_ = OM_VL16(p, storage, e_, 0), b_ = OM_VL16(p, storage, e_, 1); \
            v##0 = (float16)(a_.even, b_.even);                                             \
            v##1 = (float16)(a_.odd, b_.odd);                                               \
        } else {                                                                            \
            const float16 a_ = OM_VL16(p, storage, e_, 0), b_ = OM_VL16(p, storage, e_, 1), \
                          c_ = OM_VL16(p, storage, e_, 2), d_ = OM_VL16(p, storage, e_, 3); \
            v##0 = OM_CAT4(a_.s048c, b_.s048c, c_.s048c, d_.s048c);                         \
            v##1 = OM_CAT4(a_.s159d, b_.s159d, c_.s159d, d_.s159d);                         \
            v##2 = OM_CAT4(a_.s26ae, b_.s26ae, c_.s26ae, d_.s26ae);                         \
            v##3 = OM_CAT4(a_.s37bf, b_.s37bf, c_.s37bf, d_.s37bf);                         \
        }                                                                                   \
    } while (0)
#define OM_HAS_FULL_LOAD(storage) ((storage) <= 1)
#else
#define OM_FULL_LOAD(p, storage, n, v)
#define OM_HAS_FULL_LOAD(storage) 0
#endif
#define OM_FETCH_0(name, storage, n, v)                                                 \
    OmF v##0 = 0.0f, v##1 = 0.0f, v##2 = 0.0f, v##3 = 0.0f;                             \
    if (OM_HAS_FULL_LOAD(storage) && x0 + OM_LANES <= P.width) {                        \
        OM_FULL_LOAD(name, storage, n, v);                                              \
    } else {                                                                            \
        float t_[4][OM_LANES];                                                          \
        for (int l_ = 0; l_ < OM_LANES; ++l_) {                                         \
            const size_t k_ = row + min(x0 + l_, P.width - 1);                          \
            for (int c_ = 0; c_ < 4; ++c_)                                              \
                t_[c_][l_] = c_ < (n) ? OM_STORED(name, storage, k_ * (n) + c_) : 0.0f; \
        }                                                                               \
        v##0 = OM_VLOAD(t_[0]);                                                         \
        v##1 = OM_VLOAD(t_[1]);                                                         \
        v##2 = OM_VLOAD(t_[2]);                                                         \
        v##3 = OM_VLOAD(t_[3]);                                                         \
    }
#define OM_FETCH_1(name, storage, n, v)                                                    \
    OmF v##0, v##1, v##2, v##3;                                                            \
    {                                                                                      \
        float t_[4][OM_LANES];                                                             \
        for (int l_ = 0; l_ < OM_LANES; ++l_) {                                            \
            const float4 r_ =                                                              \
                read_imagef(name, om_texel_sampler, (int2)(min(x0 + l_, P.width - 1), y)); \
            t_[0][l_] = r_.x;                                                              \
            t_[1][l_] = r_.y;                                                              \
            t_[2][l_] = r_.z;                                                              \
            t_[3][l_] = r_.w;                                                              \
        }                                                                                  \
        v##0 = OM_VLOAD(t_[0]);                                                            \
        v##1 = OM_VLOAD(t_[1]);                                                            \
        v##2 = OM_VLOAD(t_[2]);                                                            \
        v##3 = OM_VLOAD(t_[3]);                                                            \
    }

// Writes n values per pixel (OmF a, b, ...) for the work-item's pixels inside the row: a full
// work-item of 16 lanes with shuffles and vector stores, any other with a loop.
#if OM_LANES == 16
#define OM_I2_LO (uint16)(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23)
#define OM_I2_HI (uint16)(8, 24, 9, 25, 10, 26, 11, 27, 12, 28, 13, 29, 14, 30, 15, 31)
#define OM_I4_LO (uint16)(0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23)
#define OM_I4_HI (uint16)(8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31)
#define OM_PUT_FULL(o, n, a, b, c, d)                                                         \
    if (x0 + OM_LANES <= P.width) {                                                           \
        const float16 ab_lo = shuffle2(a, b, OM_I2_LO), ab_hi = shuffle2(a, b, OM_I2_HI);     \
        if ((n) == 2) {                                                                       \
            vstore16(ab_lo, 0, o);                                                            \
            vstore16(ab_hi, 1, o);                                                            \
        } else {                                                                              \
            const float16 cd_lo = shuffle2(c, d, OM_I2_LO), cd_hi = shuffle2(c, d, OM_I2_HI); \
            vstore16(shuffle2(ab_lo, cd_lo, OM_I4_LO), 0, o);                                 \
            vstore16(shuffle2(ab_lo, cd_lo, OM_I4_HI), 1, o);                                 \
            vstore16(shuffle2(ab_hi, cd_hi, OM_I4_LO), 2, o);                                 \
            vstore16(shuffle2(ab_hi, cd_hi, OM_I4_HI), 3, o);                                 \
        }                                                                                     \
        break;                                                                                \
    }
#else
#define OM_PUT_FULL(o, n, a, b, c, d)
#endif
#define OM_PUT(out, n, a, b, c, d)                                           \
    do {                                                                     \
        __global float* o_ = (__global float*)(out) + (row + x0) * (n);      \
        OM_PUT_FULL(o_, n, a, b, c, d)                                       \
        float s_[4][OM_LANES];                                               \
        OM_VSTORE(a, s_[0]);                                                 \
        OM_VSTORE(b, s_[1]);                                                 \
        OM_VSTORE(c, s_[2]);                                                 \
        OM_VSTORE(d, s_[3]);                                                 \
        for (int l_ = 0; l_ < OM_LANES && x0 + l_ < P.width; ++l_)           \
            for (int c_ = 0; c_ < (n); ++c_) o_[l_ * (n) + c_] = s_[c_][l_]; \
    } while (0)

#ifndef OM_STORAGE_DEPTH
#define OM_STORAGE_DEPTH 0  // OM_STORAGE_FLOAT, as a literal for OM_STORED
#endif
#ifndef OM_STORAGE_FRAME
#define OM_STORAGE_FRAME 0
#endif
#ifndef OM_STORAGE_TANGENT
#define OM_STORAGE_TANGENT 0
#endif
#ifndef OM_STORAGE_UV
#define OM_STORAGE_UV 0
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

#define OM_DOT3(a, b) (a##x * b##x + a##y * b##y + a##z * b##z)

#ifdef OM_TRIPLANAR
// One float a pixel of the work-item's row (lanes past its end repeat its last pixel).
OM_INLINE OmF om_load_row_f(__global const float* q, size_t row, int x0, int width) {
#if OM_LANES > 1
    if (x0 + OM_LANES <= width) return OM_VLOAD(q + row + x0);
#endif
    float t[OM_LANES];
    for (int l = 0; l < OM_LANES; ++l) t[l] = q[row + min(x0 + l, width - 1)];
    return OM_VLOAD(t);
}

// A projection's planes for the lanes of `need` (its id elsewhere 0): uv, and V in its frame over
// the surface of normal n, with its ray's t scale in w (om_tri_over_surface).
OM_INLINE void om_reconstruct_projection(OmI p, OmI need, OmF ws, OmF px, OmF py, OmF pz, OmF vx,
                                         OmF vy, OmF vz, OmF nx, OmF ny, OmF nz, OmF id,
                                         size_t row, int x0, int width, __global float2* uv,
                                         __global float4* view, __global float* ids) {
    const OmF kept = OM_SEL((OmF)0.0f, id, need);
#if OM_LANES > 1
    if (x0 + OM_LANES <= width) {
        OM_VSTORE(kept, ids + row + x0);
    } else
#endif
    {
        float s[OM_LANES];
        OM_VSTORE(kept, s);
        for (int l = 0; l < OM_LANES && x0 + l < width; ++l) ids[row + x0 + l] = s[l];
    }
    if (!OM_ANY(need)) return;
    OmF a, b, c;
    om_tri_into(p, px, py, pz, &a, &b, &c);
    const struct {
        int width;
    } P = {width};  // OM_PUT's row length
    OM_PUT(uv, 2, ws * a, ws * b, (OmF)0.0f, (OmF)0.0f);
    om_tri_into(p, vx, vy, vz, &a, &b, &c);
    OmF nt, nb, nn;
    om_tri_into(p, nx, ny, nz, &nt, &nb, &nn);
    OmF scale;
    om_tri_over_surface(&a, &b, &c, OM_DOT3(v, n), nt, nb, &scale);
    OM_PUT(view, 4, a, b, c, scale);
}
#endif

__kernel void om_reconstruct(const OmReconstructParams P, OM_INPUT_ARG(depth_in, OM_IMAGE_DEPTH),
                             OM_INPUT_ARG(frame_in, OM_IMAGE_FRAME),
                             OM_INPUT_ARG(tangent_in, OM_IMAGE_TANGENT),
                             OM_INPUT_ARG(uv_in, OM_IMAGE_UV), __global float2* out_uv,
                             __global float4* out_view, __global float4* out_light
#ifdef OM_TRIPLANAR
                             ,
                             __global const float* material, __global const float4* tri_of_id,
                             const int id_limit, __global float2* second_uv,
                             __global float4* second_view, __global float* second_ids,
                             __global float2* third_uv, __global float4* third_view,
                             __global float* third_ids, __global float4* out_blend,
                             __global float* out_ray_scale
#endif
) {
    const int x0 = get_global_id(0) * OM_LANES, y = get_global_id(1);
    if (x0 >= P.width || y >= P.height) return;
    const size_t row = (size_t)y * P.width;
#ifdef OM_NO_UV
    const OmF uv0 = NAN, uv1 = NAN;
#else
    OM_FETCH(uv_in, OM_IMAGE_UV, OM_STORAGE_UV, 2, uv);
#endif
    OM_FETCH(depth_in, OM_IMAGE_DEPTH, OM_STORAGE_DEPTH, 1, depth);
    OM_FETCH(frame_in, OM_IMAGE_FRAME, OM_STORAGE_FRAME, 4, f);
    const OmF d = depth0;

    // The pixel centre in NDC, then p = (M ndc).xyz / (M ndc).w and V = (eye - p) / |eye - p|
    // (an orthographic view: eye / |eye|, with eye_w 0).
    const OmF nx = OM_PIXEL_NDC_X(OM_TO_FLOAT(2 * (x0 + OM_LANE_IDS) + 1), P.width);
    const float ny = OM_PIXEL_NDC_Y(P.row0_ndc_y, y, P.height);
    const OmF nz = OM_PIXEL_NDC_Z(P, d);  // 2d - 1 (GL) or d
    OM_UNPROJECT(OmF, P.inv_view_proj, nx, ny, nz, px, py, pz);
    OmF vx = P.eye[0] - P.eye_w * px, vy = P.eye[1] - P.eye_w * py, vz = P.eye[2] - P.eye_w * pz;
    const OmF iv = rsqrt(OM_DOT3(v, v));
    vx *= iv;
    vy *= iv;
    vz *= iv;

    OmF tx, ty, tz, bx, by, bz, qnx, qny, qnz;  // the frame: tangent, bitangent, normal
    OmI ok, n_ok;  // the frame, and its normal alone
#ifdef OM_QUATERNION_FRAME
    {
        // The columns of the rotation by the unit quaternion: tangent, bitangent, normal. q and -q
        // are the same rotation, so the sign of w carries the handedness.
        const OmF q2 = f0 * f0 + f1 * f1 + f2 * f2 + f3 * f3;
        ok = isfinite(q2) & (q2 > 1.0e-12f);
        n_ok = ok;
        const OmF iq = rsqrt(q2);
        const OmF qx = f0 * iq, qy = f1 * iq, qz = f2 * iq, qw = f3 * iq;
        const OmF xx = qx * qx, yy = qy * qy, zz = qz * qz;
        const OmF xy = qx * qy, xz = qx * qz, yz = qy * qz;
        const OmF wx = qw * qx, wy = qw * qy, wz = qw * qz;
        const OmF h = OM_SEL((OmF)1.0f, (OmF)-1.0f, f3 < 0.0f);
        tx = 1.0f - 2.0f * (yy + zz);
        ty = 2.0f * (xy + wz);
        tz = 2.0f * (xz - wy);
        bx = h * (2.0f * (xy - wz));
        by = h * (1.0f - 2.0f * (xx + zz));
        bz = h * (2.0f * (yz + wx));
        qnx = 2.0f * (xz + wy);
        qny = 2.0f * (yz - wx);
        qnz = 1.0f - 2.0f * (xx + yy);
    }
#else
    {
#ifdef OM_NO_TANGENT
        const OmF t0 = 0.0f, t1 = 0.0f, t2 = 0.0f, t3 = 0.0f;
#else
        OM_FETCH(tangent_in, OM_IMAGE_TANGENT, OM_STORAGE_TANGENT, 4, t);
#endif
        const OmF n2 = f0 * f0 + f1 * f1 + f2 * f2;
        const OmF in = rsqrt(n2);
        qnx = f0 * in;
        qny = f1 * in;
        qnz = f2 * in;
        const OmF nt = qnx * t0 + qny * t1 + qnz * t2;
        tx = t0 - qnx * nt;
        ty = t1 - qny * nt;
        tz = t2 - qnz * nt;
        const OmF tp2 = OM_DOT3(t, t);
        // A tangent within about 0.06 degrees of the normal spans no plane.
        n_ok = isfinite(n2) & (n2 > 1.0e-12f);
        ok = n_ok & isfinite(tp2) &
             (tp2 > 1.0e-6f * (t0 * t0 + t1 * t1 + t2 * t2));
        const OmF it = rsqrt(tp2);
        tx *= it;
        ty *= it;
        tz *= it;
        const OmF h = OM_SEL((OmF)1.0f, (OmF)-1.0f, t3 < 0.0f);  // B = h N x T
        bx = h * (qny * tz - qnz * ty);
        by = h * (qnz * tx - qnx * tz);
        bz = h * (qnx * ty - qny * tx);
    }
#endif
    // Sky: d >= 1, or d <= 0 when reversed.
    const OmI sky = P.far_sign * (d - P.far_depth) >= 0.0f;
    const OmF nan = (OmF)NAN;
    OmF fnx = qnx, fny = qny, fnz = qnz;  // the frame's normal
    OmF u_out = uv0, v_out = uv1;
#ifdef OM_TRIPLANAR
    // Each lane's material: triplanar where its table entry says so (one lookup where the lanes
    // share one id, as most do).
    const OmF ids = om_load_row_f(material, row, x0, P.width);
    float id_[OM_LANES], ws_[OM_LANES], sharp_[OM_LANES], cut_[OM_LANES];
    int on_[OM_LANES];
    OM_VSTORE(ids, id_);
    const int one_id = !OM_ANY(ids != id_[0]);
    for (int l_ = 0; l_ < OM_LANES; ++l_) {
        const float id = id_[l_];
        const int i = (int)id;
        float4 e = (float4)(0.0f);
        if (l_ > 0 && one_id) {
            e = (float4)(ws_[0], sharp_[0], cut_[0], on_[0] ? 1.0f : 0.0f);
        } else if (id == (float)i && i > 0 && i < id_limit) {
            e = tri_of_id[i];
        }
        ws_[l_] = e.x;
        sharp_[l_] = e.y;
        cut_[l_] = e.z;
        on_[l_] = e.w > 0.0f ? -1 : 0;
    }
    const OmI tri = (OM_VLOAD(on_) != 0) & n_ok & !sky & isfinite(d);
    OmI p0 = 4, p1 = 2, p2 = 0;
    OmF w0 = 1.0f, w1 = 0.0f, w2 = 0.0f;
    const OmF ws = OM_VLOAD(ws_);
    if (OM_ANY(tri)) {
        OmF wx, wy, wz;
        om_tri_weights(qnx, qny, qnz, OM_VLOAD(sharp_), OM_VLOAD(cut_), &wx, &wy, &wz);
        om_tri_order(qnx, qny, qnz, wx, wy, wz, &p0, &p1, &p2, &w0, &w1, &w2);
        OmF at, bt, ct;  // P in the dominant projection's frame (ct unused)
        om_tri_into(p0, px, py, pz, &at, &bt, &ct);
        u_out = OM_SEL(u_out, ws * at, tri);
        v_out = OM_SEL(v_out, ws * bt, tri);
        OmF ftx, ftz, fby, fbz, fx_, fy_, fz_;
        om_tri_frame(p0, &ftx, &ftz, &fby, &fbz, &fx_, &fy_, &fz_);
        tx = OM_SEL(tx, ftx, tri);
        ty = OM_SEL(ty, (OmF)0.0f, tri);
        tz = OM_SEL(tz, ftz, tri);
        bx = OM_SEL(bx, (OmF)0.0f, tri);
        by = OM_SEL(by, fby, tri);
        bz = OM_SEL(bz, fbz, tri);
        fnx = OM_SEL(fnx, fx_, tri);
        fny = OM_SEL(fny, fy_, tri);
        fnz = OM_SEL(fnz, fz_, tri);
        ok = OM_SEL(ok, n_ok, tri);
    }
#endif
    OmF vt = OM_DOT3(v, t), vb = OM_DOT3(v, b), vn = OM_DOT3(v, fn);
#ifdef OM_TRIPLANAR
    OmF scale0 = 0.0f;  // the first projection's ray's t scale; 0 where not triplanar
    if (OM_ANY(tri)) {  // V over the surface, in the first projection's frame
        OmF a = vt, b_ = vb, c = vn, s;
        om_tri_over_surface(&a, &b_, &c, OM_DOT3(v, qn), OM_DOT3(qn, t), OM_DOT3(qn, b), &s);
        vt = OM_SEL(vt, a, tri);
        vb = OM_SEL(vb, b_, tri);
        vn = OM_SEL(vn, c, tri);
        scale0 = OM_SEL((OmF)0.0f, s, tri);
    }
#endif
    ok = ok & isfinite(d) & isfinite(vt) & isfinite(vb) & isfinite(vn);

    OM_PUT(out_uv, 2, OM_SEL(u_out, nan, sky), OM_SEL(v_out, nan, sky), nan, nan);
    OM_PUT(out_view, 4, OM_SEL(OM_SEL(nan, vt, ok), (OmF)0.0f, sky),
           OM_SEL(OM_SEL(nan, vb, ok), (OmF)0.0f, sky), OM_SEL(OM_SEL(nan, vn, ok), (OmF)1.0f, sky),
           OM_SEL(nan, (OmF)0.0f, ok | sky));
#ifdef OM_LIT
    OmF lx = P.light_vec[0], ly = P.light_vec[1], lz = P.light_vec[2];
#ifdef OM_POINT_LIGHT
    lx -= px;
    ly -= py;
    lz -= pz;
    const OmF il = rsqrt(OM_DOT3(l, l));
    lx *= il;
    ly *= il;
    lz *= il;
#endif
    const OmF lt = OM_DOT3(l, t), lb = OM_DOT3(l, b), ln = OM_DOT3(l, fn);
    const OmI lit = ok & isfinite(lt) & isfinite(lb) & isfinite(ln);
#ifdef OM_SPOT_LIGHT
    // The cone: the angle between the axis and the ray from the light to the point, its cosine
    // smoothstepped from the outer half-angle (none) to the inner (whole); w is what it takes.
    const OmF along = -(lx * P.light_axis[0] + ly * P.light_axis[1] + lz * P.light_axis[2]);
    const OmF span = fmax(P.cone_cos_inner - P.cone_cos_outer, 1.0e-6f);
    const OmF s = clamp((along - P.cone_cos_outer) / span, 0.0f, 1.0f);
    const OmF dark = 1.0f - s * s * (3.0f - 2.0f * s);
    OM_PUT(out_light, 4, OM_SEL((OmF)0.0f, lt, lit), OM_SEL((OmF)0.0f, lb, lit),
           OM_SEL((OmF)1.0f, ln, lit), OM_SEL((OmF)0.0f, dark, lit));
#else
    OM_PUT(out_light, 4, OM_SEL((OmF)0.0f, lt, lit), OM_SEL((OmF)0.0f, lb, lit),
           OM_SEL((OmF)1.0f, ln, lit), (OmF)0.0f);
#endif
#endif
#ifdef OM_TRIPLANAR
    // The second and third projections: uv and V in their frames where their weight is not 0.
    const OmF id_here = OM_SEL((OmF)0.0f, ids, tri);
    om_reconstruct_projection(p1, tri & (w1 > 0.0f), ws, px, py, pz, vx, vy, vz, qnx, qny, qnz,
                              id_here, row, x0, P.width, second_uv, second_view, second_ids);
    om_reconstruct_projection(p2, tri & (w2 > 0.0f), ws, px, py, pz, vx, vy, vz, qnx, qny, qnz,
                              id_here, row, x0, P.width, third_uv, third_view, third_ids);
    OmF ndx, ndy, ndz;  // the normal in the first projection's frame
    om_tri_into(p0, qnx, qny, qnz, &ndx, &ndy, &ndz);
    OM_PUT(out_blend, 4, OM_SEL((OmF)-1.0f, om_tri_pack_x(p0, p1, w1), tri),
           OM_SEL((OmF)0.0f, w2, tri), OM_SEL((OmF)0.0f, ndx, tri), OM_SEL((OmF)0.0f, ndy, tri));
#if OM_LANES > 1
    if (x0 + OM_LANES <= P.width) {
        OM_VSTORE(scale0, out_ray_scale + row + x0);
    } else
#endif
    {
        float s_[OM_LANES];
        OM_VSTORE(scale0, s_);
        for (int l = 0; l < OM_LANES && x0 + l < P.width; ++l) out_ray_scale[row + x0 + l] = s_[l];
    }
#endif
}
