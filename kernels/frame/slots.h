// The material frame's id rule, for its classification (frame/classify.cl) and the shade pass's
// per-material shading (shade.cl): a G-buffer's material value names a slot of the frame's table
// only when it is an integer id the table holds.
// The slot of material value m (id -> slot table of id_limit entries), or -1.
static inline int om_slot_of(float m, int id_limit, __global const int* slot_of_id) {
    const int id = m >= 1.0f && m < (float)id_limit ? (int)m : 0;
    return id > 0 && (float)id == m ? slot_of_id[id] : -1;
}
