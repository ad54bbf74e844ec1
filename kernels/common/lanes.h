// Lanes: every method (methods/*.cl, each defining om_trace) is written
// once over OmF / OmI, which are float / int when OM_LANES is 1 (one pixel per work-item: GPUs,
// the C++ peer) and float8 / float16 (8 or 16 consecutive pixels per work-item) on a CPU, where
// the compiler then keeps every pixel of a work-item in one SIMD register (docs/design.md, "Why":
// PoCL does not vectorise data-dependent loops across work-items by itself).
// Masks (comparison results) are OmI: 1 / 0 as scalars, -1 / 0 as vectors; use the macros below,
// which work with either. Integer min, max and clamp take OmI arguments only, never a scalar
// beside a lane vector (write `max(w, (OmI)1)`): Oclgrind 21.10's (gentype, sgentype) forms
// return garbage past the first element, and its walks then ran differently from run to run.
// This file is plain OpenCL C 1.2 for any driver; PoCL's instruction-set paths (clang builtins,
// x86 mask instructions, pair gathers) are lanes_pocl.h's, which comes first in every program.
#ifndef OM_LANES
#define OM_LANES 1
#endif

#ifdef OM_OPENCL_C
// Vector literals, spelled so the kernel sources also compile as C++ (tools/peer).
#define OM_F2(a, b) ((float2)((a), (b)))
#define OM_F3(a, b, c) ((float3)((a), (b), (c)))
#define OM_F4(a, b, c, d) ((float4)((a), (b), (c), (d)))
#endif

// Every helper is forced inline: PoCL kept the larger ones (patch corners, ray set-up, linear
// search) as calls that pass 16-lane vectors through memory, which made even `none` far slower.
// Static as well: a plain `inline` function is C99's inline definition, which emits no body, so a
// compiler that does not inline it (clang with the LLVM passes off, as SPIR-V front ends may run)
// links against a function that does not exist. OM_PLAIN_CALLS (the Oclgrind check,
// tests/portability) keeps them as calls: inlined, clang marks their struct results with
// llvm.experimental.noalias.scope.decl, which Oclgrind 21.10 cannot run.
#ifdef OM_PLAIN_CALLS
#define OM_INLINE static inline
#else
#define OM_INLINE static inline __attribute__((always_inline))
#endif

// a * b + c, fused where the device has the instruction. Where it has none (CL_FP_FMA unset, the
// runtime's OM_SOFT_FMA: Mesa's llvmpipe), fma is a correctly rounded routine per component that
// made the 16-lane programs take minutes to build there; mad lets the driver round as it does
// best (its result within the rounding of the product and the sum).
#ifdef OM_SOFT_FMA
#define OM_FMA(a, b, c) mad(a, b, c)
#else
#define OM_FMA(a, b, c) fma(a, b, c)
#endif

// Plain OpenCL C 1.2 for every helper lanes_pocl.h does not define (every driver but PoCL).
#ifndef om_floor
#define om_floor(x) floor(x)
#define OM_LIKELY(c) (c)
#endif
#ifndef OM_VANY_REDUCE
#define OM_VANY_REDUCE(m) any(m)
#define OM_VFLOOR(x) floor(x)
#endif
#ifndef OM_VANY
#define OM_VANY(m) OM_VANY_REDUCE(m)
#endif
#ifndef OM_VANY_NE2
#define OM_VANY_NE2(a, b, c, d) OM_VANY(((a) != (b)) | ((c) != (d)))
#endif

#if OM_LANES == 1
typedef float OmF;
typedef int OmI;
#define OM_ANY(m) ((m) != 0)
#define OM_ANY_RARE(m) ((m) != 0)
#define OM_ANY_NE2(a, b, c, d) ((a) != (b) || (c) != (d))
#define OM_SEL(a, b, m) ((m) ? (b) : (a))  // b where m, else a
#define OM_TO_INT(x) ((int)(x))
#define OM_TO_FLOAT(x) ((float)(x))
#define OM_LFLOOR(x) om_floor(x)
#define OM_GATHER(p, i) ((p)[i])
#define OM_AS_INT(x) as_int(x)
#define OM_LANE_IDS 0
#define OM_VLOAD(p) ((p)[0])
#define OM_VSTORE(v, p) ((p)[0] = (v))
#elif OM_LANES == 8
typedef float8 OmF;
typedef int8 OmI;
#define OM_ANY(m) OM_VANY(m)
#define OM_ANY_RARE(m) OM_VANY_REDUCE(m)
#define OM_ANY_NE2(a, b, c, d) OM_VANY_NE2(a, b, c, d)
#define OM_SEL(a, b, m) select((a), (b), (m))
#define OM_TO_INT(x) convert_int8(x)
#define OM_TO_FLOAT(x) convert_float8(x)
#define OM_LFLOOR(x) OM_VFLOOR(x)
#define OM_GATHER(p, i)                                                                     \
    ((float8)((p)[(i).s0], (p)[(i).s1], (p)[(i).s2], (p)[(i).s3], (p)[(i).s4], (p)[(i).s5], \
              (p)[(i).s6], (p)[(i).s7]))
#define OM_LANE_IDS ((int8)(0, 1, 2, 3, 4, 5, 6, 7))
#define OM_AS_INT(x) as_int8(x)
#define OM_VLOAD(p) vload8(0, p)
#define OM_VSTORE(v, p) vstore8(v, 0, p)
#elif OM_LANES == 16
typedef float16 OmF;
typedef int16 OmI;
#define OM_ANY(m) OM_VANY(m)
#define OM_ANY_RARE(m) OM_VANY_REDUCE(m)
#define OM_ANY_NE2(a, b, c, d) OM_VANY_NE2(a, b, c, d)
#define OM_SEL(a, b, m) select((a), (b), (m))
#define OM_TO_INT(x) convert_int16(x)
#define OM_TO_FLOAT(x) convert_float16(x)
#define OM_LFLOOR(x) OM_VFLOOR(x)
#define OM_GATHER(p, i)                                                                      \
    ((float16)((p)[(i).s0], (p)[(i).s1], (p)[(i).s2], (p)[(i).s3], (p)[(i).s4], (p)[(i).s5], \
               (p)[(i).s6], (p)[(i).s7], (p)[(i).s8], (p)[(i).s9], (p)[(i).sa], (p)[(i).sb], \
               (p)[(i).sc], (p)[(i).sd], (p)[(i).se], (p)[(i).sf]))
#define OM_LANE_IDS ((int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15))
#define OM_AS_INT(x) as_int16(x)  // a float's bits, as OmI
#define OM_VLOAD(p) vload16(0, p)  // an OmF from OM_LANES floats in private memory
#define OM_VSTORE(v, p) vstore16(v, 0, p)
#else
#error "OM_LANES must be 1, 8 or 16"
#endif
#define OM_ANY_NE(a, b) OM_ANY_NE2(a, b, a, b)

// The smallest of an OmI's lanes, as an int.
#if OM_LANES == 1
#define OM_LANE_MIN(x) (x)
#else
OM_INLINE int om_lane_min4(int4 v) {
    const int2 m = min(v.lo, v.hi);
    return min(m.x, m.y);
}
#if OM_LANES == 8
#define OM_LANE_MIN(x) om_lane_min4(min((x).lo, (x).hi))
#else
#define OM_LANE_MIN(x) om_lane_min4(min(min((x).lo.lo, (x).lo.hi), min((x).hi.lo, (x).hi.hi)))
#endif
#endif

// The smallest and largest of an OmF's lanes, as a float.
#if OM_LANES == 1
#define OM_LANE_FMIN(x) (x)
#define OM_LANE_FMAX(x) (x)
#else
OM_INLINE float om_lane_fmin4(float4 v) {
    const float2 m = fmin(v.lo, v.hi);
    return fmin(m.x, m.y);
}
OM_INLINE float om_lane_fmax4(float4 v) {
    const float2 m = fmax(v.lo, v.hi);
    return fmax(m.x, m.y);
}
#if OM_LANES == 8
#define OM_LANE_FMIN(x) om_lane_fmin4(fmin((x).lo, (x).hi))
#define OM_LANE_FMAX(x) om_lane_fmax4(fmax((x).lo, (x).hi))
#else
#define OM_LANE_FMIN(x) \
    om_lane_fmin4(fmin(fmin((x).lo.lo, (x).lo.hi), fmin((x).hi.lo, (x).hi.hi)))
#define OM_LANE_FMAX(x) \
    om_lane_fmax4(fmax(fmax((x).lo.lo, (x).lo.hi), fmax((x).hi.lo, (x).hi.hi)))
#endif
#endif

// Heights come from a float buffer (the CPU path), or with OM_IMAGES through an image1d_buffer_t
// view of the same buffer (a GPU's texture path; the same floats, so the same frame). OpenCL C
// allows images only as function parameters, so the sampling calls carry it as a last parameter.
#ifdef OM_IMAGES
#define OM_IMG_PARAM , __read_only image1d_buffer_t om_img
#define OM_IMG_ARG , om_img
#define OM_TEXEL1(i) read_imagef(om_img, (i)).x
#if OM_LANES == 1
#define OM_HEIGHTS(p, i) OM_TEXEL1(i)
#elif OM_LANES == 8
#define OM_HEIGHTS(p, i)                                                                  \
    ((float8)(OM_TEXEL1((i).s0), OM_TEXEL1((i).s1), OM_TEXEL1((i).s2), OM_TEXEL1((i).s3), \
              OM_TEXEL1((i).s4), OM_TEXEL1((i).s5), OM_TEXEL1((i).s6), OM_TEXEL1((i).s7)))
#else
#define OM_HEIGHTS(p, i)                                                                   \
    ((float16)(OM_TEXEL1((i).s0), OM_TEXEL1((i).s1), OM_TEXEL1((i).s2), OM_TEXEL1((i).s3), \
               OM_TEXEL1((i).s4), OM_TEXEL1((i).s5), OM_TEXEL1((i).s6), OM_TEXEL1((i).s7), \
               OM_TEXEL1((i).s8), OM_TEXEL1((i).s9), OM_TEXEL1((i).sa), OM_TEXEL1((i).sb), \
               OM_TEXEL1((i).sc), OM_TEXEL1((i).sd), OM_TEXEL1((i).se), OM_TEXEL1((i).sf)))
#endif
#else
#define OM_IMG_PARAM
#define OM_IMG_ARG
#define OM_HEIGHTS(p, i) OM_GATHER(p, i)
#endif

// Four float4 as one float16, built as two float8 halves: Oclgrind 21.10 assembles the four-way
// literal (float16)(a, b, c, d) wrongly at -O0 (lanes from other memory, different from run to run).
#define OM_CAT4(a, b, c, d) ((float16)((float8)((a), (b)), (float8)((c), (d))))

// 1 where the mask is set, else 0 (for counting), with either mask convention.
#define OM_ONE(m) ((m)&1)

// A method's om_trace_pair loop: two groups of lanes advanced by turns, for at most `rounds`
// rounds, each group while `more_a` / `more_b` (its lanes not done) holds, until neither does.
// Each group takes the steps its own om_trace would, so the frame does not change.
#define OM_PAIR_LOOP(rounds, more_a, step_a, more_b, step_b) \
    for (int round_ = 0; round_ < (rounds); ++round_) {      \
        const int a_ = (more_a), b_ = (more_b);              \
        if (!a_ && !b_) break;                               \
        if (a_) step_a;                                      \
        if (b_) step_b;                                      \
    }

// Pairs of neighbouring floats per lane, where lanes_pocl.h has a way to read them at once.
#ifdef OM_PAIR_GATHER
// Eight pairs from indices i (floats from p): (first, second) of each pair.
OM_INLINE float8 om_gather8_pairs(__global const float* p, int8 i, float8* second) {
    float16 q = OM_PAIRS8(p, i);
    *second = q.odd;
    return q.even;
}

OM_INLINE void om_gather_pairs(__global const float* p, OmI i, OmF* first, OmF* second) {
#if OM_LANES == 8
    *first = om_gather8_pairs(p, i, second);
#else
    float8 s0, s1;
    float8 f0 = om_gather8_pairs(p, i.lo, &s0);
    float8 f1 = om_gather8_pairs(p, i.hi, &s1);
    *first = (float16)(f0, f1);
    *second = (float16)(s0, s1);
#endif
}
#endif
