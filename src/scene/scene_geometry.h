// The geometry of a scene file loaded into memory: the meshes of all its glTF
// files (each loaded once, however many objects and nodes use it), one global
// material table and the instances that place meshes in the world.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/material.h"
#include "scene/mesh.h"

namespace lt {

struct SceneFile;

// One placed mesh: a glTF node of one scene object.
struct SceneInstance {
  size_t mesh = 0;                   // index into SceneGeometry::meshes
  size_t object = 0;                 // index into SceneFile::objects
  Eigen::Affine3d world_from_mesh;   // object pose times the node's glTF transform
  int32_t material_override = -1;    // material id used for all its triangles, or -1
  std::string name;                  // "object/node"
};

struct SceneGeometry {
  std::vector<Mesh> meshes;          // Mesh::triangle_material holds global material ids
  // The scene file's named materials first (in SceneFile::materials order), then
  // the materials of each glTF file in the order the files were loaded.
  std::vector<Material> materials;
  std::vector<SceneInstance> instances;
  std::vector<std::string> object_names;  // SceneFile::objects order, then "print" when the scene prints
  // The meshes of the printed part's chunks (scene/printed_part.h), in chunk
  // order; empty until PrintedPart::UpdateTo fills them. Empty without "print".
  std::vector<size_t> print_meshes;
  size_t degenerate_triangles = 0;   // dropped while loading
  std::vector<std::string> warnings;

  // Material id of a triangle as seen through an instance (the override, if any).
  uint32_t MaterialOf(const SceneInstance& instance, uint32_t triangle) const {
    return instance.material_override >= 0 ? uint32_t(instance.material_override)
                                           : meshes[instance.mesh].triangle_material[triangle];
  }
  // By material id, whether some placed triangle takes the material: an instance's
  // material_override (the printed part's too, before it grows), else its mesh's
  // triangle_material. A glTF material no triangle of the loaded scene names
  // (exporters' material libraries, a mesh no node places, points and lines) or a
  // scene material no object takes is false: changing it changes nothing.
  std::vector<bool> UsedMaterials() const;
  size_t UniqueTriangleCount() const;     // sum over meshes
  size_t InstancedTriangleCount() const;  // sum over instances
  // Exact world bounds of every instanced vertex (computed in double).
  Eigen::AlignedBox3d WorldBounds() const;
};

// Loads every glTF the scene references. Errors are lt::InputError naming the
// glTF file (and the JSON pointer inside it).
SceneGeometry LoadSceneGeometry(const SceneFile& scene);

}  // namespace lt
