// A pixel and its window depth to the world, and a world point to a frame's pixels and depth: the
// one place every kernel that reads a depth buffer turns it into points (the reconstruct, the depth
// offset and the shadow test). Macros over a type T, so that a lane-form kernel (OmF) and a
// scalar one (float) share each expression, operation for operation.

// NDC of pixel (x, y)'s centre in a grid of width x height pixels (fx = 2 x + 1 as T), rows from
// row0_ndc_y's edge (GL's bottom-first rows: -1; top first: +1), at window depth d.
#define OM_PIXEL_NDC_X(fx, width) ((fx) / (float)(width)-1.0f)
#define OM_PIXEL_NDC_Y(row0_ndc_y, y, height) \
    ((row0_ndc_y) * (1.0f - (float)(2 * (y) + 1) / (float)(height)))
#define OM_PIXEL_NDC_Z(G, d) ((G).depth_scale * (d) + (G).depth_offset)

// Declares T px, py, pz: the world point (M ndc).xyz / (M ndc).w of NDC (nx, ny, nz), M the
// inverse view-projection (column-major float[16]).
#define OM_UNPROJECT(T, m, nx, ny, nz, px, py, pz)                                    \
    const T px##_w_ = (m)[3] * (nx) + (m)[7] * (ny) + (m)[11] * (nz) + (m)[15];       \
    const T px = ((m)[0] * (nx) + (m)[4] * (ny) + (m)[8] * (nz) + (m)[12]) / px##_w_; \
    const T py = ((m)[1] * (nx) + (m)[5] * (ny) + (m)[9] * (nz) + (m)[13]) / px##_w_; \
    const T pz = ((m)[2] * (nx) + (m)[6] * (ny) + (m)[10] * (nz) + (m)[14]) / px##_w_

// A grid's pixel drawn (not sky): d before the far plane, in the grid's depth direction.
#define OM_PIXEL_DRAWN(G, d) ((G).far_sign * ((d) - (G).far_depth) < 0.0f)
