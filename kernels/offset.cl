// The one offset kernel entry: G-buffer load, validation, one method's om_trace, store.
// Compiled once per method; the method file defining om_trace is pasted in before this file.
// aux is the method's precomputed data (NULL for most). Optional outputs (depth, fetches, flags)
// may be NULL buffers.
__kernel void om_offset(const OmOffsetParams P, __global const float2* gb_uv,
                        __global const float4* gb_view, __global const float* heights,
                        __global const float* aux,
                        __global float2* out_uv, __global float* out_depth,
                        __global uint* out_fetches, __global uint* out_flags) {
    int id = get_global_id(0);
    if (id >= P.pixel_count) return;
    float2 uv = gb_uv[id];
    OmRay ray;
    float2 base;
    uint flags = om_setup_ray(uv, gb_view[id], &P, &ray, &base);
    OmHeightField f = om_heightfield(heights, &P);
    f.aux = aux;
    float t = 0.0f;
    float2 out = uv;
    if ((flags & (OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING)) == 0u) {
        out = om_trace(&ray, &f, &P, &t, &flags) + base;
    }
    out_uv[id] = out;
    if (out_depth) out_depth[id] = t;
    if (out_fetches) out_fetches[id] = f.fetches;
    if (out_flags) out_flags[id] = flags;
}
