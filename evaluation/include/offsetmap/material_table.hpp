// A frame's material table as a file (JSON: a list of objects, one per material), read, loaded and
// put on the device as a MaterialFrame's materials.
#pragma once
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "offsetmap/gbuffer.hpp"
#include "offsetmap/image_io.hpp"
#include "offsetmap/material_frame.hpp"

namespace offsetmap {

// The accuracy a material asks of method "auto": the p95 or the mean of its uv error against the
// exact hit, in texels of its height map.
struct ErrorBudget {
    enum class Statistic { P95, Mean } statistic = Statistic::P95;
    double texels = 0.0;  // (0, 64]
};

// One entry of the table, as the file gives it. Keys: id, name, height_map, depth_map, channel,
// scale, reference_plane, address (wrap, clamp), grazing (clamp, limit, cap), grazing_min_deg,
// max_offset, tile_mask, tile_bounds ([u_min, v_min, u_max, v_max], null: open), method (a
// method's name or "auto"), params (name: value), error_budget
// ({"p95_texels": x} or {"mean_texels": x}; method auto only), normal_map, flip_green, albedo,
// projection ("uv", the default, or "triplanar": the world projected along three axes, for meshes
// without uv; wrap addressing) with world_scale, sharpness and blend_cutoff (offsetmap/triplanar.hpp).
// Paths are relative to the JSON file's folder; settings not given keep `defaults`.
struct MaterialSpec {
    int id = 0;
    std::string name;        // "name", else the height map's file name
    std::string height_map;  // resolved path
    HeightLoadOptions load;
    PassSettings settings;
    std::string method = "pom";
    std::map<std::string, std::string> params;
    ErrorBudget budget;  // method "auto"
    std::string normal_map, albedo;
    bool flip_green = false;
    Triplanar triplanar;
};

// Reads and checks the table: JSON syntax, unknown keys, value types and ranges, ids in
// [1, kMaxMaterialId] and not repeated, known methods and parameters, budgets in range (and only
// with "auto"). Reads no image. Throws Error naming the file and the entry's id (or position).
std::vector<MaterialSpec> read_material_table(const std::string& path,
                                              const PassSettings& defaults = {});

// A table entry with its images read (before any device work).
struct LoadedMaterial {
    MaterialSpec spec;
    HeightMap map;
    Image4 normals;  // 0 x 0: derived from the heights
    Image4 albedo;   // 0 x 0: the neutral checker
};
// Throws Error naming the material and the file that cannot be read.
std::vector<LoadedMaterial> load_materials(const std::vector<MaterialSpec>& specs);

// The loaded table on the device, each material with the method given in `methods` (one per
// material, same order: its own for a named method, the choice for "auto").
std::vector<FrameMaterial> upload_materials(Runtime& runtime,
                                            const std::vector<LoadedMaterial>& materials,
                                            const std::vector<MethodParams>& methods);

// Material ids laid over a G-buffer without any (the built-in scenes): each uv tile
// (floor u, floor v) takes one of `ids`, picked by a hash of the tile; empty pixels take 0.
void lay_out_materials(GBuffer& gbuffer, const std::vector<int>& ids);

}  // namespace offsetmap
