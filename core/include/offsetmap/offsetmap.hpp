// offsetmap: per-pixel displacement mapping as OpenCL compute passes over a deferred G-buffer.
// The library an engine links (target offsetmap::offsetmap): the runtime on the caller's context
// and queue, the method registry, the passes and their settings. No file IO, no OpenImageIO; the
// evaluation tools are offsetmap/evaluation.hpp (target offsetmap::evaluation).
#pragma once
#include "offsetmap/engine_gbuffer.hpp"
#include "offsetmap/error.hpp"
#include "offsetmap/gbuffer.hpp"
#include "offsetmap/heightmap.hpp"
#include "offsetmap/passes.hpp"
#include "offsetmap/registry.hpp"
#include "offsetmap/runtime.hpp"
