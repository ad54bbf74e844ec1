// The lane layer's paths for PoCL's CPU targets (x86: AVX-512, AVX2): clang builtins and
// instructions that only PoCL, compiling for its own CPU, is sure to take. Every other driver
// (rusticl and, through SPIR-V, most GPU stacks) gets lanes.h's plain OpenCL C 1.2 instead: a
// macro left undefined here falls back to it there. The runtime puts this file before lanes.h.
// What each path gained is measured in docs/throughput.md.
#ifdef OM_POCL

// PoCL's floor() (scalar and vector) and any() are library routines with branches; clang's
// builtins are one rounding instruction and an OR reduction; results are the same. A driver that
// goes through SPIR-V gets LLVM intrinsics its translator rejects (llvm.vector.reduce.or).
#define om_floor(x) __builtin_floorf(x)
#define OM_LIKELY(c) __builtin_expect((c), 1)
#if defined(__has_builtin)
#if __has_builtin(__builtin_elementwise_floor) && __has_builtin(__builtin_reduce_or)
#define OM_CLANG_LANE_BUILTINS 1
#endif
#endif
#ifdef OM_CLANG_LANE_BUILTINS
#define OM_VANY_REDUCE(m) (__builtin_reduce_or(m) < 0)
#define OM_VFLOOR(x) __builtin_elementwise_floor(x)
#endif

// Any lane's sign bit, for 16 lanes: one mask instruction (AVX-512's vpmovd2m, AVX's vmovmskps
// on each half) where the reduction takes an OR and shuffle tree. OM_ANY_RARE keeps the reduction
// for a branch almost never taken (the patch solve's bisection): with the mask instruction there,
// PoCL laid `exact` out slower.
#if defined(OM_CLANG_LANE_BUILTINS) && OM_LANES == 16 && defined(__AVX512DQ__)
#define OM_VANY(m) (__builtin_ia32_cvtd2mask512(m) != 0)
#elif defined(OM_CLANG_LANE_BUILTINS) && OM_LANES == 16 && defined(__AVX__)
#define OM_VANY(m)                                            \
    ((__builtin_ia32_movmskps256(as_float8((m).lo)) |         \
      __builtin_ia32_movmskps256(as_float8((m).hi))) != 0)
#endif
// Whether any lane has a != b or c != d (ints), for a branch almost never taken. Under AVX2 the
// lanes' differences ORed and tested at once (vptest), where 16 compares' mask was packed to bytes
// first (about 20 instructions a patch read). AVX-512 keeps the compares, whose masks are free
// there.
#if defined(OM_CLANG_LANE_BUILTINS) && defined(__AVX__) && !defined(__AVX512F__)
#define OM_VANY_NE2(a, b, c, d) (__builtin_reduce_or(((a) ^ (b)) | ((c) ^ (d))) != 0)
#endif

// Pairs of neighbouring floats (p[i], p[i + 1]) for 8 lanes as one float16 (first, second
// interleaved): a bilinear patch's row is such a pair. AVX-512 gathers cost per element, so two
// 64-bit gathers of 8 pairs replace two gathers of 16 floats (clang's gather builtin: PoCL's CPU
// target has one flat address space). Without AVX-512 the compiler builds a gather from one scalar
// load and one insert per float (it emits no AVX2 gathers, which are slow on many CPUs); a pair is
// then one 64-bit load: half the loads and inserts. With AVX-512 such loads are slower than its
// gathers. Float buffers only; every lane's p[i + 1] must lie in the buffer.
#if !defined(OM_IMAGES) && (OM_LANES == 8 || OM_LANES == 16)
#if defined(__AVX512F__) && defined(__has_builtin) && defined(OM_CLANG_LANE_BUILTINS)
#if __has_builtin(__builtin_ia32_gathersiv8di)
#define OM_PAIRS8(p, i)                                                                      \
    as_float16(                                                                              \
        __builtin_ia32_gathersiv8di((long8)0, (const void*)(size_t)(p), (i), (unsigned char)0xff, 4))
#endif
#endif
#ifndef OM_PAIRS8
#define OM_PAIR(p, k) as_long(vload2(0, (p) + (k)))
#define OM_PAIRS8(p, i)                                                                        \
    as_float16((long8)(OM_PAIR(p, (i).s0), OM_PAIR(p, (i).s1), OM_PAIR(p, (i).s2),             \
                       OM_PAIR(p, (i).s3), OM_PAIR(p, (i).s4), OM_PAIR(p, (i).s5),             \
                       OM_PAIR(p, (i).s6), OM_PAIR(p, (i).s7)))
#endif
#define OM_PAIR_GATHER 1
#endif

#endif  // OM_POCL
