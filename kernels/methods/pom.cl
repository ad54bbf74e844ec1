// pom (Tatarchuk 05/06): a linear search whose step count is lerp(n_max, n_min, V.z) (more samples
// at grazing views: Tatarchuk's dynamic sampling rate; n_min = `min_samples`, n_max =
// `max_samples`), then the ray intersected with the straight segment joining the last two height
// samples. Tatarchuk's V.N is V.z here. With `spacing` > 0 the count follows the texels the ray
// crosses through the slab instead, one sample per `spacing` texels, clamped to [n_min, n_max]:
// V.z alone ignores the map's size and the depth scale, and the texels crossed grow as tan of the
// view's angle from the normal, much faster than 1 - V.z near grazing. Cost: at most n_max + 1
// fetches.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    const float n_min = OM_PARAM(P, min_samples), n_max = OM_PARAM(P, max_samples);
    const float spacing = OM_PARAM(P, spacing);
    OmF want;
    if (spacing > 0.0f) {
        // At the lane's mip level: f's size is that level's.
        const OmF across = (r->t_exit - r->t_enter) *
                           sqrt(r->vx * r->vx * f->fw * f->fw + r->vy * r->vy * f->fh * f->fh);
        want = clamp(ceil(across / spacing), (OmF)n_min, (OmF)n_max);
    } else {
        want = mix((OmF)n_max, (OmF)n_min, r->vz);
    }
    OmI n = om_step_count(r, want);
    OmSearchHit hit = om_linear_search(r, f, n, active, fetches OM_IMG_ARG);
    // Along the segment, height minus ray height goes from d0 < 0 (above) to d1 >= 0.
    OmF fn = OM_TO_FLOAT(n);
    OmF l0 = OM_TO_FLOAT(hit.index - 1) / fn, l1 = OM_TO_FLOAT(hit.index) / fn;
    OmF eta0, eta1;
    om_search_etas(r, &hit, l0, l1, &eta0, &eta1);
    OmF d0 = hit.h_prev - eta0;
    OmF d1 = hit.h_cur - eta1;
    OmF lambda = OM_SEL((OmF)0.0f, om_segment_cut(l0, l1, d0, d1), hit.index > 0);
    // Over a curved base: no hit before the ray left through the top (a silhouette).
    lambda = OM_SEL(lambda, (OmF)1.0f, hit.miss);
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, hit.miss);
    return om_ray_t(r, lambda);
}
