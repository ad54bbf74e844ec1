// The per-ray bound of the exact methods against the double oracle, from the reference library
// (offsetmap/oracle_bound.hpp): the suite and the device check hold the kernels to the same one.
#pragma once
#include "offsetmap/oracle_bound.hpp"
#include "support.hpp"
