// parallax (Kaneko 01): assume the relief is flat at the height H(uv) read at the entry point and
// intersect the ray with that plane: t = s (r - H) / V.z, uv' = uv - (r - H) P with P = s V.xy /
// V.z. Premecz writes uv + h V.xy / V.z with h = SCALE H + BIAS; in this convention h = s (H - r),
// which is the same expression. The textbook "uv - (1 - H) P" is the r = 1 case.
// Over a curved base the level d = s (H - r) is the circle h = d (om_ray_curve's quadratic, its
// root past the pixel's side); a convex base that turns the ray away before that level is a miss.
// A ray that stays below the level over a concave base (it cannot reach an inner circle) takes
// its highest point, t = V.z / kn, within the slab.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmF h = om_height(f, r->u, r->v, active, fetches OM_IMG_ARG);
    OmF t = -r->scale * (h - r->ref) / r->vz;
#ifdef OM_CURVED
    if (r->any_curved) {
        const OmF d = r->scale * (h - r->ref), c = d * (2.0f + r->kn * d);
        const OmF disc = r->vz * r->vz + r->kn * c;
        const OmI short_of = r->curved & (disc < 0.0f);
        const OmI away = short_of & (r->kn > 0.0f);
        t = OM_SEL(t, -c / (r->vz + sqrt(fmax(disc, 0.0f))), r->curved);
        t = OM_SEL(t, r->t_exit, away);
        t = OM_SEL(t, clamp(r->vz / r->kn, r->t_enter, r->t_exit), short_of & !away);
        *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_SILHOUETTE, away);
    }
#endif
    return t;
}
