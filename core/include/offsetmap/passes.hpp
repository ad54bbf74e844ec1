// The passes an engine runs, and their settings (one header each, gathered here).
#pragma once
#include "offsetmap/depth_offset_pass.hpp"
#include "offsetmap/height_field.hpp"
#include "offsetmap/material_frame.hpp"
#include "offsetmap/offset_pass.hpp"
#include "offsetmap/settings.hpp"
#include "offsetmap/shade_pass.hpp"
#include "offsetmap/shadow_mask_pass.hpp"
