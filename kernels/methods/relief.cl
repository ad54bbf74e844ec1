// relief (Policarpo et al. 05; Premecz section 2.3): linear search of n = `linear` steps, then
// binary search of m = `binary` steps between the last sample above and the first below the relief.
// Returns the bracket's lower end (a point at or below the surface, as Policarpo's best depth).
// Cost: at most n + 1 + m fetches.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmI n = om_step_count(r, (OmF)OM_PARAM(P, linear));
    int m = (int)OM_PARAM(P, binary);
    OmSearchHit hit = om_linear_search(r, f, n, active, fetches OM_IMG_ARG);
    OmF fn = OM_TO_FLOAT(n);
    OmF hi = OM_TO_FLOAT(hit.index) / fn;
    OmF lo = OM_SEL((OmF)0.0f, OM_TO_FLOAT(hit.index - 1) / fn, hit.index > 0);
    OmI refine = active & (hit.index > 0) & !hit.miss;
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, hit.miss);  // left through the top
    for (int k = 0; k < m && OM_ANY(refine); ++k) {
        OmF mid = 0.5f * (lo + hi);
        OmF x, y, eta;
        om_ray_sample(r, mid, &x, &y, &eta);
        OmF h = om_height(f, x, y, refine, fetches OM_IMG_ARG);
        OmI below = h >= eta;
        hi = OM_SEL(hi, mid, refine & below);
        lo = OM_SEL(lo, mid, refine & !below);
    }
    return om_ray_t(r, hi);
}
