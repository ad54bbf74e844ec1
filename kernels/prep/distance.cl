// Distance map for `sphere`: a res x res x layers grid over the tile and the relief slab. Voxel
// (i, j, k) is the box uv [i/res, (i+1)/res] x [j/res, (j+1)/res] x w [k s/layers, (k+1) s/layers]
// (w = s H, uv units). It stores the Euclidean distance from that *box* to a *column proxy* of
// the relief: column (i, j) is the box over the same uv square from w = 0 up to s times the
// largest height of the bilinear relief over that square. The proxy contains the relief, so no
// point of the voxel is closer to the relief than the stored value (conservative by construction).
// Wrap: columns tile. Clamp: columns beyond the edges repeat the edge columns (the extruded
// relief).

// The largest height of the bilinear relief over column (i, j)'s uv square. A bilinear patch
// restricted to a rectangle peaks at one of its corners, so the maximum over the square is reached
// on the grid of its edges and the patch lines (texel centres) inside it: exact, and tight as res
// grows past the map's resolution.
__kernel void om_column_max(const OmOffsetParams P, __global const float* heights, int res,
                            __global float* colmax) {
    int i = get_global_id(0), j = get_global_id(1);
    if (i >= res || j >= res) return;
    OmField f = om_field(heights, &P, 0);
    float x0 = (float)i / res, x1 = (float)(i + 1) / res;
    float y0 = (float)j / res, y1 = (float)(j + 1) / res;
    // Patch lines in uv: u = (n + 0.5) / W.
    int nx0 = (int)floor(OM_CELL(x0, f.fw)) + 1, nx1 = (int)ceil(OM_CELL(x1, f.fw)) - 1;
    int ny0 = (int)floor(OM_CELL(y0, f.fh)) + 1, ny1 = (int)ceil(OM_CELL(y1, f.fh)) - 1;
    float m = 0.0f;
    for (int gy = ny0 - 1; gy <= ny1 + 1; ++gy) {
        float v = gy < ny0 ? y0 : (gy > ny1 ? y1 : ((float)gy + 0.5f) / f.fh);
        for (int gx = nx0 - 1; gx <= nx1 + 1; ++gx) {
            float u = gx < nx0 ? x0 : (gx > nx1 ? x1 : ((float)gx + 0.5f) / f.fw);
            m = fmax(m, om_height_at(&f, u, v));
        }
    }
    colmax[j * res + i] = m;
}

__kernel void om_distance_map(const OmOffsetParams P, __global const float* colmax, int res,
                              int layers, __global float* dist) {
    int i = get_global_id(0), j = get_global_id(1), k = get_global_id(2);
    if (i >= res || j >= res || k >= layers) return;
    float s = P.scale, cell = 1.0f / res;
    float w_low = s * (float)k / layers;  // the voxel's lowest height
    float d = w_low;                      // the floor w = 0 belongs to every column
    int reach = (int)ceil(d * res) + 1;
    for (int dj = -reach; dj <= reach; ++dj) {
        float ey = fmax(fabs((float)dj) - 1.0f, 0.0f) * cell;  // gap between the two squares
        if (ey >= d) continue;
        for (int di = -reach; di <= reach; ++di) {
            float ex = fmax(fabs((float)di) - 1.0f, 0.0f) * cell;
            if (ex >= d) continue;
            int ci = i + di, cj = j + dj;
            ci = om_address(ci, res, P.address_mode == OM_ADDRESS_WRAP);
            cj = om_address(cj, res, P.address_mode == OM_ADDRESS_WRAP);
            float ez = fmax(w_low - s * colmax[cj * res + ci], 0.0f);
            d = fmin(d, sqrt(ex * ex + ey * ey + ez * ez));
        }
    }
    dist[(k * res + j) * res + i] = d;
}
