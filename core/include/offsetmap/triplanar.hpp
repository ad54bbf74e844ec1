// Triplanar relief (docs/design.md, "Triplanar relief"): a material without uv takes its relief
// from three axis-aligned projections of the world, weighted by the normal. The reconstruct pass
// gives each triplanar pixel its dominant projection in the G-buffer and the other two, where they
// weigh, in the planes below; the material frame traces each projection with the material's method
// and shades the blend.
#pragma once
#include <array>
#include <string>

#include "offsetmap/cl.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/offset_pass.hpp"

namespace offsetmap {

class Runtime;

// A material's projection. Weights: |n_a|^sharpness for each axis a of the G-buffer's normal n,
// normalised, each lowered by `cutoff` and normalised again (a projection below the cutoff weighs
// 0 and is not traced).
struct Triplanar {
    bool enabled = false;
    float world_scale = 1.0f;  // texture tiles per world unit, in (0, 1e6]
    float sharpness = 4.0f;    // the blend exponent, in [1, 64]
    float cutoff = 0.05f;      // in [0, 0.3]
};

// Throws Error naming `what` (the material) and the parameter out of range.
void validate(const Triplanar& t, const std::string& what);

// The definitions the kernels follow, on the host in double: projection p's frame (T, B, N; p =
// 2 axis + 1 where the normal's component on the axis is negative), the projection of axis a for
// normal n, and the three weights for a unit normal n.
struct TriplanarFrame {
    std::array<double, 3> t, b, n;
};
TriplanarFrame triplanar_frame(int p);
int triplanar_projection(const std::array<double, 3>& n, int axis);
std::array<double, 3> triplanar_weights(const std::array<double, 3>& n, double sharpness,
                                        double cutoff);

// A triplanar frame's planes besides the G-buffer, all width x height.
struct TriplanarPlanes {
    // The second and third projections (uv, view and material: the pixel's id where the
    // projection weighs, else 0), as the reconstruct pass writes them, and their traces (every
    // output). No light: the shade turns the G-buffer's into each projection's frame.
    DeviceGBuffer second, third;
    OffsetTargets second_targets, third_targets;
    // float4 a pixel: its weights, projections and normal, packed (kernels/common/triplanar.cl;
    // x < 0: not triplanar).
    cl::Buffer blend;
    // float a pixel: the first projection's ray scale (the trace's t along its unit ray over the
    // surface, times this, is t along the world ray; 1 on an axis-aligned face), 0 where not
    // triplanar. The second's and third's are their view planes' w.
    cl::Buffer ray_scale;
};

TriplanarPlanes allocate_triplanar(Runtime& runtime, int width, int height);

// The table the reconstruct pass reads: per material id a float4 (world_scale, sharpness,
// cutoff, 1 for a triplanar material; 0 otherwise). MaterialFrame::triplanar_table().
struct TriplanarTable {
    cl::Buffer of_id;
    int id_limit = 0;
    bool any = false;  // the table has a triplanar material
    std::string name;  // the first triplanar material, for messages
};

}  // namespace offsetmap
