// Roofline microkernels for bench/: the floors every offset kernel is measured against.

// G-buffer pass-through: the offset pass's memory traffic (uv 8 B + view 16 B in, uv' 8 B out)
// with no work. Multiplying by 0 keeps the view load without changing the output.
__kernel void om_bench_passthrough(__global const float2* uv, __global const float4* view,
                                   __global float2* out, int n) {
    int i = get_global_id(0);
    if (i >= n) return;
    out[i] = uv[i] + view[i].xy * 0.0f;
}

// `chain` dependent bilinear height fetches per pixel through the methods' sampling layer, OM_LANES
// pixels per work-item (lanes.h; 1 unless defined): each fetch's position depends on the previous
// height, as in a march, so none can be skipped or hoisted. Time per fetch = (this - pass-through)
// / chain.
__kernel void om_bench_fetch_chain(const OmOffsetParams P, __global const float* heights,
                                   __global const float* uv, __global float* out, int n,
                                   int chain) {
    OmI id = min((int)get_global_id(0) * OM_LANES + OM_LANE_IDS, n - 1);
    OmField f = om_field(heights, &P, (OmI)0);
    OmF u = OM_GATHER(uv, 2 * id), v = OM_GATHER(uv, 2 * id + 1);
    OmI fetches = 0;
    for (int k = 0; k < chain; ++k) {
        OmF h = om_height(&f, u, v, (OmI)1, &fetches OM_IMG_ARG);
        u += 0.37f * h / f.fw;
        v += 0.11f * h / f.fh;
    }
    OmF r = u + v + OM_TO_FLOAT(fetches) * 0.0f;
    for (int k = 0; k < OM_LANES; ++k) {
        int i = (int)get_global_id(0) * OM_LANES + k;
        if (i < n) out[i] = ((float*)&r)[k];
    }
}

// `count` independent bilinear fetches per pixel along a line, as a linear search makes them: the
// positions do not depend on earlier heights, so fetches can overlap. The fastest fetch rate
// measured is the roof methods are measured against.
__kernel void om_bench_fetch_line(const OmOffsetParams P, __global const float* heights,
                                  __global const float* uv, __global float* out, int n, int count) {
    OmI id = min((int)get_global_id(0) * OM_LANES + OM_LANE_IDS, n - 1);
    OmField f = om_field(heights, &P, (OmI)0);
    OmF u = OM_GATHER(uv, 2 * id), v = OM_GATHER(uv, 2 * id + 1);
    OmF du = 0.61f / f.fw, dv = 0.29f / f.fh, sum = 0.0f;
    OmI fetches = 0;
    for (int k = 0; k < count; ++k)
        sum +=
            om_height(&f, u + (float)k * du, v + (float)k * dv, (OmI)1, &fetches OM_IMG_ARG);
    OmF r = u + v + sum * 0.0f + OM_TO_FLOAT(fetches) * 0.0f;
    for (int k = 0; k < OM_LANES; ++k) {
        int i = (int)get_global_id(0) * OM_LANES + k;
        if (i < n) out[i] = ((float*)&r)[k];
    }
}
