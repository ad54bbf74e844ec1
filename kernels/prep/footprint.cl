// Per-pixel mip level from the uv footprint, as a GPU derives it from screen-space derivatives:
// the uv differences to the right and lower neighbours (left or upper at the border, or where the
// neighbour is empty) in texels of level 0; level = log2 of the longer one. Pixels with no usable
// neighbour get level 0. Meaningful for camera G-buffers, where neighbours are neighbours.
__kernel void om_footprint_lod(__global const float2* uv, int width, int height, float tex_w,
                               float tex_h, __global float* lod) {
    int x = get_global_id(0), y = get_global_id(1);
    if (x >= width || y >= height) return;
    float2 c = uv[y * width + x];
    float rho = 0.0f;
    if (isfinite(c.x) && isfinite(c.y)) {
        int xs[2] = {min(x + 1, width - 1), max(x - 1, 0)};
        int ys[2] = {min(y + 1, height - 1), max(y - 1, 0)};
        for (int axis = 0; axis < 2; ++axis) {
            for (int side = 0; side < 2; ++side) {
                int nx = axis == 0 ? xs[side] : x, ny = axis == 1 ? ys[side] : y;
                if (nx == x && ny == y) continue;
                float2 d = uv[ny * width + nx] - c;
                if (!isfinite(d.x) || !isfinite(d.y)) continue;
                rho = fmax(rho, length((float2)(d.x * tex_w, d.y * tex_h)));
                break;
            }
        }
    }
    lod[y * width + x] = rho > 0.0f ? log2(rho) : 0.0f;
}
