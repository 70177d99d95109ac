// Skinning and morph targets of a glTF primitive's vertices, and the accessor checks
// they share with ConvertGltfMesh (gltf_mesh.h). Internal to gltf_mesh.cpp (which
// defines the checks) and gltf_skin_morph.cpp (which defines ApplySkin and
// ApplyMorphTargets).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "scene/gltf_mesh.h"

namespace tinygltf {
struct Primitive;
}

namespace lt::gltf_mesh_detail {

// Fails when accessor `index`, referenced at `where`, does not exist.
void CheckAccessorRef(const GltfSource& src, int index, const std::string& where);

// The accessor of an attribute, or -1 when the primitive has none.
int FindAttribute(const GltfSource& src, const tinygltf::Primitive& p, const char* name, const std::string& where);

// Fails when any value is not finite; with `used`, only the values of the used
// elements are checked (a vertex no triangle uses cannot reach the render).
void CheckFinite(const GltfSource& src, int accessor, const std::vector<float>& v, int components,
                 const char* what, const std::vector<char>* used = nullptr);

Eigen::Vector3f Vec3At(const std::vector<float>& v, size_t i);

// Skins a primitive's positions and normals into `skin`'s pose (linear blend
// skinning); marks the vertices whose blended matrix mirrors (determinant < 0).
void ApplySkin(const GltfSource& src, const tinygltf::Primitive& prim, const std::string& where,
               const GltfSkinPose& skin, std::vector<float>* pos, std::vector<float>* nrm, std::vector<char>* mirrored);

// Adds the morph targets of a primitive, weighted, to its positions and normals
// (glTF 2.0 3.7.2.2). Targets' other attributes (TANGENT, TEXCOORD_n, COLOR_n) are not used.
void ApplyMorphTargets(const GltfSource& src, const tinygltf::Primitive& prim, const std::string& where,
                       const GltfMorphWeights* morph, std::vector<float>* pos, std::vector<float>* nrm);

}  // namespace lt::gltf_mesh_detail
