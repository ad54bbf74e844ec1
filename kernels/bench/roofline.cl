// Roofline microkernels for bench/: the floors every offset kernel is measured against.

// G-buffer pass-through: the offset pass's memory traffic (uv 8 B + view 16 B in, uv' 8 B out)
// with no work. Multiplying by 0 keeps the view load without changing the output.
__kernel void om_bench_passthrough(__global const float2* uv, __global const float4* view,
                                   __global float2* out, int n) {
    int i = get_global_id(0);
    if (i >= n) return;
    out[i] = uv[i] + view[i].xy * 0.0f;
}

// `chain` dependent bilinear height fetches per pixel through the project's sampling layer: each
// fetch's position depends on the previous height, as in a march, so none can be skipped or
// hoisted. Time per fetch = (this - pass-through) / chain.
__kernel void om_bench_fetch_chain(const OmOffsetParams P, __global const float* heights,
                                   __global const float2* uv, __global float2* out, int n,
                                   int chain) {
    int i = get_global_id(0);
    if (i >= n) return;
    OmHeightField f = om_heightfield(heights, &P);
    float2 p = uv[i];
    for (int k = 0; k < chain; ++k) {
        float h = om_height(&f, p);
        p += (float2)(0.37f * h, 0.11f * h) / f.fw;
    }
    out[i] = p;
}

// `count` independent bilinear fetches per pixel along a line, as a linear search makes them: the
// positions do not depend on earlier heights, so fetches can overlap. The faster of the two fetch
// rates is the roof methods are measured against.
__kernel void om_bench_fetch_line(const OmOffsetParams P, __global const float* heights,
                                  __global const float2* uv, __global float2* out, int n,
                                  int count) {
    int i = get_global_id(0);
    if (i >= n) return;
    OmHeightField f = om_heightfield(heights, &P);
    float2 p = uv[i], d = (float2)(0.61f, 0.29f) / f.fw;
    float sum = 0.0f;
    for (int k = 0; k < count; ++k) sum += om_height(&f, p + (float)k * d);
    out[i] = p + sum * 0.0f;
}
