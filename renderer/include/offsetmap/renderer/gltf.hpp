// Scenes from glTF 2.0 files (.gltf, or .glb binary). glTF has no height-map slot, so a material
// table names each glTF material's height map: a primitive's material is the table entry whose
// "name" is the glTF material's name.
#pragma once
#include <string>
#include <vector>

#include "offsetmap/material_table.hpp"
#include "offsetmap/renderer/scene.hpp"

namespace offsetmap::renderer {

// Every triangle primitive (triangles, strips, fans) of the file's default scene, in world space
// (each node's matrix or translation, rotation and scale applied down the hierarchy; normals by
// the inverse transpose; winding reversed under a mirroring transform). Tangents and uv densities
// are derived from TEXCOORD_0 (derive_tangents), so the frame always follows the height map's uv;
// a TANGENT attribute is not read. The camera is the scene's first perspective camera node, else
// one that frames the scene's bounds; the light a point above the bounds.
// Throws Error, one line naming the file and the mesh or material: a file tinygltf cannot read, a
// primitive without POSITION, NORMAL (normals) or TEXCOORD_0 (uv), points or lines, a primitive
// without a material, a material no table entry names (no height map), an empty scene.
Scene load_gltf_scene(const std::string& path, const std::vector<MaterialSpec>& table,
                      const std::string& table_path);

// True for the names load_gltf_scene reads: *.gltf and *.glb (any case).
bool is_gltf_path(const std::string& path);

}  // namespace offsetmap::renderer
