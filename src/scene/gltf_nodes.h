// The node hierarchy of a glTF file: node transforms (matrix or TRS), the walk of
// the default scene that says which node places which mesh where (with
// EXT_mesh_gpu_instancing and morph weights), and the pose of a skin. Used by the
// glTF loader; errors are lt::InputError naming the file and the JSON pointer.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/gltf_mesh.h"

namespace lt {

// One placement of a mesh by a node (or by one EXT_mesh_gpu_instancing instance).
struct GltfNodeUse {
  int gltf_mesh;
  Eigen::Affine3d transform;  // file_from_mesh; identity for a skinned mesh (its joints place it)
  std::string node_name;      // the node's name or "node <index>", "/instance <k>" appended
  int skin = -1;
  GltfMorphWeights morph;     // the node's weights, else the mesh's
};

// Walks the default scene (scene 0 without one; every parentless node, with a
// warning, without scenes), iteratively so deep hierarchies cannot overflow the
// stack. glTF asks for a tree: a node listed under several parents is placed under
// each (with a warning), a node listed twice in one list is placed once, and a node
// that is its own ancestor is an error. Nodes with a singular transform are skipped
// with a warning.
std::vector<GltfNodeUse> WalkGltfScene(const GltfSource& src, std::vector<std::string>* warnings);

// The pose of skin `index`: each joint's global transform times its inverse bind matrix.
GltfSkinPose GltfSkinPoseOf(const GltfSource& src, int index);

}  // namespace lt
