// Relief normals at texel centres: normalize(-s dH/du, -s dH/dv, 1) with central differences in
// uv units (one texel is 1/W of u), honouring the address mode at the borders.
__kernel void om_normals(const OmOffsetParams P, __global const float* heights,
                         __global float4* normals) {
    int i = get_global_id(0), j = get_global_id(1);
    if (i >= P.hf_width || j >= P.hf_height) return;
    OmField f = om_field(heights, &P, 0);
    float dhdu = 0.5f * (om_texel(&f, i + 1, j) - om_texel(&f, i - 1, j)) * f.fw;
    float dhdv = 0.5f * (om_texel(&f, i, j + 1) - om_texel(&f, i, j - 1)) * f.fh;
    if (!f.wrap) {
        // One-sided at clamped borders: the clamped neighbour repeats the edge texel.
        if (i == 0 || i == f.width - 1) dhdu *= f.width > 1 ? 2.0f : 0.0f;
        if (j == 0 || j == f.height - 1) dhdv *= f.height > 1 ? 2.0f : 0.0f;
    }
    float3 n = normalize((float3)(-P.scale * dhdu, -P.scale * dhdv, 1.0f));
    normals[j * f.width + i] = (float4)(n, 0.0f);
}
