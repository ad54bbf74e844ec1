// none: normal mapping (Blinn 78). The surface is taken to lie on the polygon: uv' = uv, t = 0.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    return 0.0f;
}
