// offsetmap's evaluation tools (target offsetmap::evaluation): the exact hit in double precision,
// G-buffer sources, error statistics, the sweep, failure maps and temporal stability, and image
// and G-buffer files (OpenImageIO). Includes the library itself.
#pragma once
#include "offsetmap/auto_method.hpp"
#include "offsetmap/evaluate.hpp"
#include "offsetmap/failure_map.hpp"
#include "offsetmap/image_io.hpp"
#include "offsetmap/material_eval.hpp"
#include "offsetmap/material_table.hpp"
#include "offsetmap/offsetmap.hpp"
#include "offsetmap/oracle.hpp"
#include "offsetmap/scenes.hpp"
#include "offsetmap/sweep.hpp"
#include "offsetmap/temporal.hpp"
