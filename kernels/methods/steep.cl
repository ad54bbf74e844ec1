// steep (McGuire & McGuire 05): n = p[0] equal depth layers from the top plane; the result is the
// first layer sample at or below the relief. The mip level p[1] is held fixed for the whole march
// (McGuire: it makes the reads cheaper; coarser levels also stop thin features being skipped).
// With LOD on, the level is the coarser of p[1] and the pixel's.
// McGuire steps t += E.xy * bumpScale / (n E.z) from the polygon at height 1: the same march with
// the top plane at the polygon (r = 1). Cost: at most n + 1 fetches.
float2 om_trace(const OmRay* r, OmHeightField* f, const OmOffsetParams* P, float* t_hit,
                uint* flags) {
    int n = om_lod_count(r, P->p[0]);
    OmHeightField level = om_heightfield_level(f->base, P, max(f->level, (int)P->p[1]));
    OmLinearHit hit = om_linear_search(r, &level, n);
    f->fetches += level.fetches;
    float t = om_ray_t(r, (float)hit.index / (float)n);
    *t_hit = t;
    return om_ray_uv(r, t);
}
