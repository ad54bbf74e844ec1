// The offset kernel entry for one-pixel methods (lane methods: offset_lanes.cl): G-buffer load,
// validation, LOD, one method's om_trace, store. Compiled once per method; the method file defining
// om_trace is pasted in before this file. aux is the method's precomputed data (NULL for most); lod
// is the per-pixel mip level (NULL unless the LOD system is on). Optional outputs (depth, fetches,
// flags) may be NULL buffers.
//
// LOD (Tatarchuk 2006): at mip level m the heights are read from level floor(m) of the pyramid,
// step counts are scaled by mix(1, min_detail, m / threshold) (more samples near the viewer), and
// the offset fades linearly to plain normal mapping over the `fade` levels below the threshold:
// uv' = uv + w (uv'_method - uv), w = clamp((threshold - m) / fade, 0, 1); w = 0 skips the trace.
// Footprint mode instead caps step counts at the texels (of level floor(m)) the ray's footprint
// crosses, plus one, and fades by that count over [fade_lo, fade_hi] texels: a ray that crosses
// less than a texel at the pixel's level cannot show parallax.
//
// Specialised at build time (the host sets these from the pass, one program each): OM_LOD when the
// LOD system is on, OM_OUT_DEPTH / OM_OUT_FETCHES / OM_OUT_FLAGS for the optional outputs bound.
// (Measured on PoCL: no faster than runtime checks, as uniform branches cost little on a CPU; it
// saves the GPU the checks and keeps unused outputs out of the kernel.)
#ifndef OM_LANE_METHOD  // lane methods use offset_lanes.cl
__kernel void om_offset(const OmOffsetParams P, __global const float2* gb_uv,
                        __global const float4* gb_view, __global const float* heights,
                        __global const float* aux, __global const float* lod,
                        __global float2* out_uv, __global float* out_depth,
                        __global uint* out_fetches, __global uint* out_flags) {
    int id = get_global_id(0);
    if (id >= P.pixel_count) return;
    float2 uv = gb_uv[id];
    OmRay ray;
    float2 base;
    uint flags = om_setup_ray(uv, gb_view[id], &P, &ray, &base);
    float blend = 1.0f;
    int level = 0;
#ifdef OM_LOD
    float m = lod[id];
    m = isfinite(m) ? m : 0.0f;
    level = (int)clamp(m, 0.0f, 16.0f);  // truncation is floor for m >= 0
    if (P.lod_footprint) {
        // Texels of this pixel's level the ray's footprint crosses through the whole slab.
        float texels = (ray.t_exit - ray.t_enter) * length(ray.v.xy) *
                       fmax((float)P.hf_width, (float)P.hf_height) / (float)(1 << level);
        ray.step_cap = (int)ceil(texels) + 1;
        blend = clamp((texels - P.lod_fade_lo) / (P.lod_fade_hi - P.lod_fade_lo), 0.0f, 1.0f);
    } else {
        blend = clamp((P.lod_threshold - m) / P.lod_fade, 0.0f, 1.0f);
        ray.detail = mix(1.0f, P.lod_min_detail, clamp(m / P.lod_threshold, 0.0f, 1.0f));
    }
#endif
    OmHeightField f = om_heightfield_level(heights, &P, level);
    f.aux = aux;
    bool rejected = (flags & (OM_FLAG_EMPTY | OM_FLAG_INVALID | OM_FLAG_BACKFACING)) != 0u;
    bool traced = !rejected && blend > 0.0f;
    float t = 0.0f;
    float2 hit = ray.uv;
    uint trace_flags = 0u;
    if (traced) hit = om_trace(&ray, &f, &P, &t, &trace_flags);
    // LOD fade toward normal mapping (blend = 1 without LOD).
    hit = ray.uv + blend * (hit - ray.uv);
    float2 out = hit + base;
    // On a non-tiling surface a ray that leaves the tile sees past the polygon's edge.
    bool outside = P.tile_mask && (out.x < 0.0f || out.x > 1.0f || out.y < 0.0f || out.y > 1.0f);
    flags |= traced ? trace_flags | (outside ? OM_FLAG_OUT_OF_TILE : 0u)
                    : (rejected ? 0u : OM_FLAG_LOD_FADED);
    out_uv[id] = traced ? out : uv;
#ifdef OM_OUT_DEPTH
    out_depth[id] = traced ? t * blend : 0.0f;
#endif
#ifdef OM_OUT_FETCHES
    out_fetches[id] = traced ? f.fetches : 0u;
#endif
#ifdef OM_OUT_FLAGS
    out_flags[id] = flags;
#endif
}
#endif
