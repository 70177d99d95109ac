// Conversion of one glTF mesh (all its primitives) into an lt::Mesh. Used by the
// glTF loader; the accessor reads are bounds-checked (gltf_accessors.h).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/material.h"
#include "scene/mesh.h"

namespace lt {

struct GltfMeshStats {
  size_t degenerate_triangles = 0;  // dropped
  bool uses_default_material = false;
  // Some primitive's texture coordinates are a set other than TEXCOORD_0 (the one
  // its material's base-colour texture names): loaded without materials, they differ.
  bool texcoords_not_set_0 = false;
  // Point and line primitives skipped (only triangles are rendered), in order:
  // the mode's name ("points", "lines", ...) and the primitive's index. The
  // loader warns about them once per mode for the whole file.
  std::vector<std::pair<std::string, size_t>> skipped_primitives;
};

// The pose of a skin (glTF 2.0 3.7.3): for each of its joints, the joint node's
// global transform times its inverse bind matrix. A skinned vertex is
// sum_i w_i * joint_matrices[j_i] * v (JOINTS_n / WEIGHTS_n), in the file's frame.
struct GltfSkinPose {
  std::vector<Eigen::Affine3d> joint_matrices;
  std::string pointer;  // "/skins/0", for messages
};

// The weights of a mesh's morph targets (glTF 2.0 3.7.2.2): the node's `weights`,
// else the mesh's; none (empty) means all 0.
struct GltfMorphWeights {
  std::vector<double> weights;
  std::string pointer;  // "/nodes/3/weights" or "/meshes/0/weights", for messages
};

// Converts mesh `index`. Triangle strips and fans become triangle lists, points
// and lines are skipped with a warning, primitives without NORMAL get flat normals
// (their vertices are unshared). Primitives without a material get
// `default_material`; `materials` are the file's converted materials (by glTF
// index): each primitive's texture coordinates are the TEXCOORD_n set its
// material's base-colour texture reads. Morph targets' POSITION and NORMAL are
// added with `morph` weights (the rest pose when null). With `skin`, the vertices
// and normals are then skinned into the skin's pose (triangles whose skinning
// mirrors are turned round, as a mirroring node's are by its determinant).
// Throws lt::InputError on malformed data.
Mesh ConvertGltfMesh(const GltfSource& src, int index, const std::vector<Material>& materials,
                     uint32_t default_material, GltfMeshStats* stats, std::vector<std::string>* warnings,
                     const GltfSkinPose* skin = nullptr, const GltfMorphWeights* morph = nullptr);

}  // namespace lt
