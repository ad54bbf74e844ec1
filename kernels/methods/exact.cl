// exact: the first hit of the eye ray with the bilinearly interpolated height field, the ground
// truth. A DDA walks the bilinear patches (cells between texel centres) the ray's footprint
// crosses from the top plane to the bottom plane, solving each (om_lane_patch_hit,
// common/lane_patch.cl). Cost: one patch (4 texels, counted as one fetch) per cell crossed, at most
// ~ (s / V.z)(W + H). A lane method: each lane walks its own cells; the loop ends when every lane
// has its answer.
void om_trace_lanes(const OmLaneRay* r, const OmLaneField* f, const OmOffsetParams* P, OmI active,
                    OmF* t_hit, OmF* u_hit, OmF* v_hit, OmI* fetches, OmI* flags OM_IMG_PARAM) {
    // Ray in cell coordinates: c(t) = c0 - t * d, where integer c is a texel centre.
    OmF cx = clamp(r->u * f->fw - 0.5f, -1.0e8f, 1.0e8f);
    OmF cy = clamp(r->v * f->fh - 0.5f, -1.0e8f, 1.0e8f);
    OmF dx = r->vx * f->fw, dy = r->vy * f->fh;
    OmF t = r->t_enter;
    OmI i = OM_TO_INT(OM_LFLOOR(cx - t * dx)), j = OM_TO_INT(OM_LFLOOR(cy - t * dy));
    OmI si = OM_SEL((OmI)1, (OmI)-1, dx > 0.0f), sj = OM_SEL((OmI)1, (OmI)-1, dy > 0.0f);
    OmF hit_t = r->t_exit;
    OmI done = !active;
    for (int n = 0; n < P->max_cells && OM_ANY(!done); ++n) {
        OmI live = !done;
        OmI bi = OM_SEL(i + 1, i, si < 0), bj = OM_SEL(j + 1, j, sj < 0);
        OmF tx = OM_SEL((OmF)INFINITY, (cx - OM_TO_FLOAT(bi)) / dx, dx != 0.0f);
        OmF ty = OM_SEL((OmF)INFINITY, (cy - OM_TO_FLOAT(bj)) / dy, dy != 0.0f);
        OmF t_out = fmin(fmin(tx, ty), r->t_exit);
        OmF th;
        OmI hit =
            om_lane_patch_hit(r, f, i, j, cx, cy, dx, dy, t, t_out, live, fetches, &th OM_IMG_ARG);
        hit_t = OM_SEL(hit_t, th, hit);
        // No hit at the bottom plane: reached through rounding, where the gap is exactly 0 when
        // H = 0 (the root at the segment's end can round away); the answer is then t_exit.
        OmI end = live & !hit & (t_out >= r->t_exit);
        done |= hit | end;
        OmI step = live & !hit & !end;
        t = OM_SEL(t, t_out, step);
        i = OM_SEL(i, i + si, step & (tx <= ty));
        j = OM_SEL(j, j + sj, step & !(tx <= ty));
    }
    *flags |= OM_SEL((OmI)0, (OmI)OM_FLAG_CAPPED, !done);  // ran out of cells
    *t_hit = hit_t;
    *u_hit = r->u - hit_t * r->vx;
    *v_hit = r->v - hit_t * r->vy;
}
