// exact: the first hit of the eye ray with the bilinearly interpolated height field, the ground
// truth. A DDA walks the bilinear patches (cells between texel centres) the ray's footprint
// crosses from the top plane to the bottom plane, solving each (om_patch_hit,
// common/patch.cl). Cost: one patch (4 texels, counted as one fetch) per cell crossed, at most
// ~ (s / V.z)(W + H). Each lane walks its own cells; the loop ends when every lane has its
// answer.
OM_INLINE OmF om_trace(const OmRay* r, const OmField* f, const OmOffsetParams* P, OmI active,
                       OmI* fetches, OmI* flags OM_IMG_PARAM) {
    OmWalk w = om_walk(r, f);
    OmF t = r->t_enter;
    OmI i, j;
    om_walk_cell(&w, t, &i, &j);
    OmF hit_t = r->t_exit;
    OmI done = !active;
    for (int n = 0; n < P->max_cells && OM_ANY(!done); ++n) {
        OmI live = !done;
        OmF tx, ty, th;
        OmF t_out = om_walk_exit(&w, i, j, (OmI)1, r->t_exit, &tx, &ty);
        OmI hit = om_patch_hit(r, f, &w, i, j, t, t_out, live, fetches, &th OM_IMG_ARG);
        hit_t = OM_SEL(hit_t, th, hit);
        // No hit at the bottom plane: reached through rounding, where the gap is exactly 0 when
        // H = 0 (the root at the segment's end can round away); the answer is then t_exit.
        OmI end = live & !hit & (t_out >= r->t_exit);
        done |= hit | end;
        om_walk_step(&w, live & !hit & !end, tx, ty, t_out, &t, &i, &j);
    }
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !done);  // ran out of cells
    return hit_t;
}
