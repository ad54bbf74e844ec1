// offsetmap: per-pixel displacement mapping as OpenCL compute passes over a deferred G-buffer.
#pragma once
#include "offsetmap/error.hpp"
#include "offsetmap/evaluate.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/image_io.hpp"
#include "offsetmap/oracle.hpp"
#include "offsetmap/passes.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/runtime.hpp"
#include "offsetmap/scenes.hpp"
#include "offsetmap/sweep.hpp"
#include "offsetmap/failure_map.hpp"
