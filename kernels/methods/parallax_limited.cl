// parallax-limited (Welsh 04, offset limiting): parallax without the division by V.z, so the
// offset never exceeds the depth s (r - H) however grazing the view: uv' = uv - s (r - H) V.xy.
// t is the ray parameter whose footprint is that uv'; the point p(t) is generally not on the
// relief.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmF h = om_height(f, r->u, r->v, active, fetches OM_IMG_ARG);
    return -r->scale * (h - r->ref);
}
