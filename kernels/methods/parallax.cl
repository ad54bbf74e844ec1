// parallax (Kaneko 01): assume the relief is flat at the height H(uv) read at the entry point and
// intersect the ray with that plane: t = s (r - H) / V.z, uv' = uv - (r - H) P with P = s V.xy /
// V.z. Premecz writes uv + h V.xy / V.z with h = SCALE H + BIAS; in this convention h = s (H - r),
// which is the same expression. The textbook "uv - (1 - H) P" is the r = 1 case.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmF h = om_height(f, r->u, r->v, active, fetches OM_IMG_ARG);
    return -r->scale * (h - r->ref) / r->vz;
}
