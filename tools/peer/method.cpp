// One method's offset kernel compiled as C++ (built once per method file by CMake with
// OM_PROGRAM_INC, OM_NS and OM_ENTRY defined): the kernel's own source, run over a pixel range.
// OM_PROGRAM_INC is the method's program as offsetmap_peer_gen writes it from the registry row:
// its parameter slots and the same files in the same order as the OpenCL build.
#include "clc_compat.hpp"
#include "cpu_peer.hpp"

// The peer writes every output (its test compares flags and fetches); the benchmark's kernel runs
// write uv' and depth only, 8 bytes a pixel less, which is noise beside either's ns per pixel.
#define OM_OUT_DEPTH
#define OM_OUT_FETCHES
#define OM_OUT_FLAGS
namespace OM_NS {
using namespace ::clc;
#include OM_PROGRAM_INC
}  // namespace OM_NS

namespace offsetmap::cpu_peer {

void OM_ENTRY(const Args& a, int begin, int end) {
    static_assert(sizeof(::clc::float2) == 8 && sizeof(::clc::float4) == 16, "vector layout");
    for (int id = begin; id < end; ++id) {
        ::clc::global_id = id;
        OM_NS::om_offset(a.params, reinterpret_cast<const ::clc::float2*>(a.uv),
                         reinterpret_cast<const ::clc::float4*>(a.view), a.heights, a.aux, a.lod,
                         reinterpret_cast<::clc::float2*>(a.out_uv), a.out_depth, a.out_fetches,
                         a.out_flags, reinterpret_cast<const ::clc::float4*>(a.curvature), nullptr);
    }
}

}  // namespace offsetmap::cpu_peer
