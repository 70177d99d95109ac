// Loading glTF 2.0 files (.gltf with external or embedded base64 buffers, and .glb)
// into CPU meshes, materials and instances.
//
// What is read: the default scene's node hierarchy (TRS and matrix transforms),
// meshes with several primitives, triangles / triangle strips / triangle fans,
// indexed (u8/u16/u32) or not, normalized and sparse accessors (and accessors
// without data: zeros), POSITION, NORMAL (flat normals computed where missing, as
// glTF 2.0 specifies), the TEXCOORD_n set each material's base-colour texture
// reads, metallic-roughness factors, base-colour textures with their samplers and
// KHR_texture_transform, emissive factor (with KHR_materials_emissive_strength),
// KHR_materials_pbrSpecularGlossiness (converted), morph targets posed by their
// default weights, skinned meshes posed by their joints (JOINTS_n / WEIGHTS_n,
// inverse bind matrices; the skinned node's transform ignored, as glTF specifies),
// EXT_mesh_gpu_instancing, the uncompressed fallback of Draco / meshopt
// compression that is not required.
// COLOR_0 vertex colours multiply the base colour (Mesh::colors).
// Materials, textures and images that no triangle uses are not read or warned about
// (their references are checked; scene/gltf_used.h); such a material keeps its index.
// Points and lines are skipped with a warning naming the mesh; so are other unrendered
// features (material extensions, animations). Degenerate
// triangles are counted and dropped. See docs/scene-format.md.
// A mesh used by several nodes is loaded once and instanced.
//
// Every error in the file (truncated, out-of-range buffer view, index past the
// vertex count, NaN position, missing buffer or texture) is an lt::InputError
// naming the file and, where it can, the JSON pointer of the offending element.
#pragma once

#include <Eigen/Geometry>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/material.h"
#include "scene/mesh.h"

namespace lt {

// One use of a mesh by a node of the default scene.
struct GltfInstance {
  size_t mesh = 0;                   // index into GltfAsset::meshes
  Eigen::Affine3d file_from_mesh;    // the node's global transform (may scale); identity
                                     // for a skinned mesh, whose vertices are posed in the file frame
  std::string node_name;             // glTF node name, or "node <index>"
};

struct GltfAsset {
  std::filesystem::path path;
  std::vector<Mesh> meshes;          // triangle_material indexes `materials`
  std::vector<Material> materials;   // the file's materials in order, then "default" if used
  std::vector<GltfInstance> instances;
  size_t degenerate_triangles = 0;   // dropped while loading
  bool uses_default_material = false;  // some primitive has no material ("default" is last in materials)
  // The materials some triangle uses whose metallic is glTF's default 1 for want of a
  // metallicFactor (ConvertGltfMaterials), for a warning: `material "a"`, `materials
  // "a", "b", "c" and 2 more`, empty if none. They are metal, meant or
  // not; the scene warns about them unless the object sets its material.
  std::string metallic_by_default;
  // Some triangles' texture coordinates are a set other than TEXCOORD_0, named by
  // their material's base-colour texture: loaded without materials (each primitive
  // reading TEXCOORD_0) the meshes' texcoords would differ.
  bool texcoords_not_set_0 = false;
  std::vector<std::string> warnings; // each prefixed with the file name
};

struct GltfLoadOptions {
  // false when the caller gives every primitive a material of its own (a scene
  // object's "material"): the file's materials, textures, images and samplers are
  // then neither read nor checked (nor the required extensions that concern only
  // them: KHR_materials_*, KHR_texture_basisu, ...), so a file whose look cannot be
  // read still loads; nothing is said about them. The geometry is read as with
  // materials (the same triangles, instances and positions), except that each
  // primitive reads TEXCOORD_0 (not the set its material's texture named).
  // GltfAsset::materials then holds one placeholder, glTF's default material, that
  // every triangle indexes; uses_default_material is false and metallic_by_default
  // empty.
  bool materials = true;
};

// Loads a .gltf or .glb (detected from the content, not the extension). Errors
// name the file as `display_name` (default: the path as given).
GltfAsset LoadGltf(const std::filesystem::path& path, const std::string& display_name = "",
                   const GltfLoadOptions& options = {});

}  // namespace lt
