// Just enough of OpenCL C for the offset kernels' sources to compile as C++ (g++ or clang):
// vector types with the swizzles the kernels use, the builtins they call, and address-space
// qualifiers as nothing. The methods then run as plain C++ loops: the same algorithm, line for
// line, as the threaded CPU peer of the bench and as a cross-check in the tests.
#pragma once
#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "offsetmap/shared.h"

#define __global
#define __kernel
#define OM_F2(a, b) (::clc::float2{{{static_cast<float>(a), static_cast<float>(b)}}})
#define OM_F3(a, b, c) \
    (::clc::float3{{{static_cast<float>(a), static_cast<float>(b), static_cast<float>(c)}}})
#define OM_F4(a, b, c, d)                                                                   \
    (::clc::float4{{{static_cast<float>(a), static_cast<float>(b), static_cast<float>(c), \
                     static_cast<float>(d)}}})
#define get_global_id(dim) (::clc::global_id)

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"  // anonymous structs in unions: the swizzles

namespace clc {

typedef unsigned int uint;
inline thread_local int global_id = 0;

struct float2 {
    union {
        struct {
            float x, y;
        };
        float s[2];
    };
};
struct float3 {
    union {
        struct {
            float x, y, z;
        };
        float2 xy;
    };
};
struct float4 {
    union {
        struct {
            float x, y, z, w;
        };
        float3 xyz;
        float2 xy;
    };
};

#define OM_CLC_OPS(T, N)                                                                 \
    inline T operator+(T a, T b) { for (int k = 0; k < N; ++k) (&a.x)[k] += (&b.x)[k]; return a; } \
    inline T operator-(T a, T b) { for (int k = 0; k < N; ++k) (&a.x)[k] -= (&b.x)[k]; return a; } \
    inline T operator*(T a, T b) { for (int k = 0; k < N; ++k) (&a.x)[k] *= (&b.x)[k]; return a; } \
    inline T operator/(T a, T b) { for (int k = 0; k < N; ++k) (&a.x)[k] /= (&b.x)[k]; return a; } \
    inline T operator*(T a, float b) { for (int k = 0; k < N; ++k) (&a.x)[k] *= b; return a; }      \
    inline T operator*(float b, T a) { return a * b; }                                               \
    inline T operator/(T a, float b) { for (int k = 0; k < N; ++k) (&a.x)[k] /= b; return a; }      \
    inline T operator-(T a) { for (int k = 0; k < N; ++k) (&a.x)[k] = -(&a.x)[k]; return a; }        \
    inline T& operator+=(T& a, T b) { return a = a + b; }                                            \
    inline T& operator-=(T& a, T b) { return a = a - b; }                                            \
    inline T& operator*=(T& a, float b) { return a = a * b; }                                        \
    inline T& operator/=(T& a, float b) { return a = a / b; }                                        \
    inline float dot(T a, T b) { float s = 0; for (int k = 0; k < N; ++k) s += (&a.x)[k] * (&b.x)[k]; return s; } \
    inline float length(T a) { return std::sqrt(dot(a, a)); }                                        \
    inline T clamp(T v, T lo, T hi) { for (int k = 0; k < N; ++k) (&v.x)[k] = std::fmin(std::fmax((&v.x)[k], (&lo.x)[k]), (&hi.x)[k]); return v; } \
    inline T mix(T a, T b, float t) { return a + (b - a) * t; }

OM_CLC_OPS(float2, 2)
OM_CLC_OPS(float3, 3)
OM_CLC_OPS(float4, 4)
#undef OM_CLC_OPS

inline float floor(float x) { return std::floor(x); }
inline float sqrt(float x) { return std::sqrt(x); }
inline float rsqrt(float x) { return 1.0f / std::sqrt(x); }
inline float fabs(float x) { return std::fabs(x); }
inline float fmin(float a, float b) { return std::fmin(a, b); }
inline float fmax(float a, float b) { return std::fmax(a, b); }
inline float copysign(float a, float b) { return std::copysign(a, b); }
inline float atan2(float y, float x) { return std::atan2(y, x); }
inline float log2(float x) { return std::log2(x); }
inline float mix(float a, float b, float t) { return a + (b - a) * t; }
inline float fma(float a, float b, float c) { return std::fma(a, b, c); }
inline bool isnan(float x) { return std::isnan(x); }
inline int as_int(float x) {
    int i;
    std::memcpy(&i, &x, sizeof i);
    return i;
}
inline bool isfinite(float x) { return std::isfinite(x); }
inline int min(int a, int b) { return std::min(a, b); }
inline int max(int a, int b) { return std::max(a, b); }
inline int clz(int x) { return x == 0 ? 32 : __builtin_clz(static_cast<unsigned>(x)); }
inline int clamp(int v, int lo, int hi) { return std::min(std::max(v, lo), hi); }
inline float clamp(float v, float lo, float hi) { return std::fmin(std::fmax(v, lo), hi); }

}  // namespace clc

#pragma GCC diagnostic pop
