// Conversion of one glTF mesh (all its primitives) into an lt::Mesh. Used by the
// glTF loader; the accessor reads are bounds-checked (gltf_accessors.h).
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/mesh.h"

namespace lt {

struct GltfMeshStats {
  size_t degenerate_triangles = 0;  // dropped
  bool uses_default_material = false;
};

// The pose of a skin (glTF 2.0 3.7.3): for each of its joints, the joint node's
// global transform times its inverse bind matrix. A skinned vertex is
// sum_i w_i * joint_matrices[j_i] * v (JOINTS_n / WEIGHTS_n), in the file's frame.
struct GltfSkinPose {
  std::vector<Eigen::Affine3d> joint_matrices;
  std::string pointer;  // "/skins/0", for messages
};

// Converts mesh `index`. Triangle strips and fans become triangle lists, points
// and lines are skipped with a warning, primitives without NORMAL get flat normals
// (their vertices are unshared). Primitives without a material get
// `default_material`. With `skin`, the vertices and normals are skinned into the
// skin's pose (triangles whose skinning mirrors are turned round, as a mirroring
// node's are by its determinant). Throws lt::InputError on malformed data.
Mesh ConvertGltfMesh(const GltfSource& src, int index, uint32_t default_material, GltfMeshStats* stats,
                     std::vector<std::string>* warnings, const GltfSkinPose* skin = nullptr);

}  // namespace lt
