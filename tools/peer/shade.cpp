// The shade kernel compiled as C++ at one lane (the peer the device check holds the shade pass
// to): the shade program's own files, as offsetmap_peer_gen lists them from the registry.
#include "clc_compat.hpp"
#include "cpu_peer.hpp"

namespace peer_shade {
using namespace ::clc;
#include "peer_shade_program.inc"
}  // namespace peer_shade

namespace offsetmap::cpu_peer {

void shade(const ShadeArgs& a, int begin, int end) {
    for (int id = begin; id < end; ++id) {
        ::clc::global_id = id;
        peer_shade::om_shade(a.params, reinterpret_cast<const ::clc::float2*>(a.uv), a.flags,
                             reinterpret_cast<const ::clc::float4*>(a.view),
                             reinterpret_cast<const ::clc::float4*>(a.light),
                             reinterpret_cast<const ::clc::float4*>(a.normals), a.heights,
                             reinterpret_cast<const ::clc::float4*>(a.albedo), a.shadow_mask,
                             reinterpret_cast<::clc::float4*>(a.out_rgba), a.out_visibility);
    }
}

}  // namespace offsetmap::cpu_peer
