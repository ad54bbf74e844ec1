// steep (McGuire & McGuire 05): n = `layers` equal depth layers from the top plane; the result is
// the first layer sample at or below the relief. The mip level `lod` is held fixed for the whole
// march (McGuire: it makes the reads cheaper; coarser levels also stop thin features being
// skipped). With LOD on, the level is the coarser of `lod` and the pixel's. McGuire steps t += E.xy
// * bumpScale / (n E.z) from the polygon at height 1: the same march with the top plane at the
// polygon (r = 1). Cost: at most n + 1 fetches.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmI n = om_step_count(r, (OmF)OM_PARAM(P, layers));
    OmField level = om_field(f->heights, P, max(f->level, (OmI)(int)OM_PARAM(P, lod)));
    OmSearchHit hit = om_linear_search(r, &level, n, active, fetches OM_IMG_ARG);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, hit.miss);  // left through the top
    return om_ray_t(r, OM_TO_FLOAT(hit.index) / OM_TO_FLOAT(n));
}
