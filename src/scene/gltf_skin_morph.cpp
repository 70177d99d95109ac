// ApplySkin and ApplyMorphTargets (gltf_skin_morph.h): a glTF primitive's vertices and
// normals deformed by a skin's joints and by weighted morph targets, for ConvertGltfMesh
// (gltf_mesh.cpp).
#include "scene/gltf_skin_morph.h"

#include <tiny_gltf.h>

#include <cmath>
#include <utility>

#include "core/error.h"

namespace lt::gltf_mesh_detail {

// Skins a primitive's positions and normals into `skin`'s pose (linear blend
// skinning); marks the vertices whose blended matrix mirrors (determinant < 0).
void ApplySkin(const GltfSource& src, const tinygltf::Primitive& prim, const std::string& where,
               const GltfSkinPose& skin, std::vector<float>* pos, std::vector<float>* nrm, std::vector<char>* mirrored) {
  const size_t nverts = pos->size() / 3;
  std::vector<Eigen::Matrix<double, 3, 4>> blend(nverts, Eigen::Matrix<double, 3, 4>::Zero());
  std::vector<double> weight_sum(nverts, 0.0);
  for (int set = 0;; ++set) {
    const std::string joints_name = "JOINTS_" + std::to_string(set), weights_name = "WEIGHTS_" + std::to_string(set);
    const int joints_acc = FindAttribute(src, prim, joints_name.c_str(), where);
    const int weights_acc = FindAttribute(src, prim, weights_name.c_str(), where);
    if (joints_acc < 0 && weights_acc < 0 && set > 0) break;
    if (joints_acc < 0 || weights_acc < 0) {
      throw InputError(where + "/attributes", "the mesh is skinned (" + skin.pointer + ") but the primitive has no " +
                                                  (joints_acc < 0 ? joints_name : weights_name));
    }
    const tinygltf::Accessor& ja = src.model.accessors[size_t(joints_acc)];
    if ((ja.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
         ja.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) ||
        ja.normalized) {
      throw InputError(GltfWhere(src, "accessors", joints_acc),
                       joints_name + " must be unsigned bytes or shorts (componentType 5121 or 5123) without "
                       "\"normalized\" (glTF 3.7.3.1), got componentType " + std::to_string(ja.componentType) +
                           (ja.normalized ? " normalized" : ""));
    }
    const std::vector<float> joints = ReadFloatAccessor(src, joints_acc, 4);
    const std::vector<float> weights = ReadFloatAccessor(src, weights_acc, 4);
    for (auto [acc, n] : {std::pair{joints_acc, joints.size()}, std::pair{weights_acc, weights.size()}}) {
      if (n / 4 != nverts) {
        throw InputError(GltfWhere(src, "accessors", acc), std::to_string(n / 4) + " elements, POSITION " +
                                                               std::to_string(nverts));
      }
    }
    CheckFinite(src, weights_acc, weights, 4, "weight");
    for (size_t v = 0; v < nverts; ++v) {
      for (int k = 0; k < 4; ++k) {
        const double w = weights[4 * v + size_t(k)];
        if (w == 0) continue;
        const size_t j = size_t(joints[4 * v + size_t(k)]);
        if (w < 0) {
          throw InputError(GltfWhere(src, "accessors", weights_acc),
                           "weight " + FormatNumber(w) + " of vertex " + std::to_string(v) + " is negative");
        }
        if (j >= skin.joint_matrices.size()) {
          throw InputError(GltfWhere(src, "accessors", joints_acc),
                           "joint " + std::to_string(j) + " of vertex " + std::to_string(v) + " is past the " +
                               std::to_string(skin.joint_matrices.size()) + " joints of " + skin.pointer);
        }
        blend[v] += w * skin.joint_matrices[j].matrix().topRows<3>();
        weight_sum[v] += w;
      }
    }
  }
  mirrored->assign(nverts, 0);
  for (size_t v = 0; v < nverts; ++v) {
    if (!(weight_sum[v] > 0)) {
      throw InputError(where + "/attributes/WEIGHTS_0",
                       "vertex " + std::to_string(v) + " has no joint weight (its weights sum to 0)");
    }
    const Eigen::Matrix<double, 3, 4> m = blend[v] / weight_sum[v];  // glTF asks for a sum of 1; quantized ones are close
    const Eigen::Matrix3d linear = m.leftCols<3>();
    const Eigen::Vector3d p = linear * Vec3At(*pos, v).cast<double>() + m.col(3);
    for (int c = 0; c < 3; ++c) (*pos)[3 * v + size_t(c)] = float(p[c]);
    const double det = linear.determinant();
    (*mirrored)[v] = det < 0;
    if (!nrm->empty()) {
      // Normals by the inverse transpose; a singular blend leaves a zero normal,
      // which is replaced by the face normals below.
      const Eigen::Vector3d n = std::abs(det) > 1e-30 ? Eigen::Vector3d(linear.inverse().transpose() *
                                                                        Vec3At(*nrm, v).cast<double>())
                                                      : Eigen::Vector3d::Zero();
      for (int c = 0; c < 3; ++c) (*nrm)[3 * v + size_t(c)] = float(n[c]);
    }
  }
}

// Adds the morph targets of a primitive, weighted, to its positions and normals
// (glTF 2.0 3.7.2.2). Targets' other attributes (TANGENT, TEXCOORD_n, COLOR_n) are not used.
void ApplyMorphTargets(const GltfSource& src, const tinygltf::Primitive& prim, const std::string& where,
                       const GltfMorphWeights* morph, std::vector<float>* pos, std::vector<float>* nrm) {
  if (prim.targets.empty() || morph == nullptr || morph->weights.empty()) return;
  if (morph->weights.size() != prim.targets.size()) {
    const size_t at = where.find(": ");
    throw InputError(src.file + ": " + morph->pointer,
                     std::to_string(morph->weights.size()) + " weights for the " + std::to_string(prim.targets.size()) +
                         " morph targets of " + (at == std::string::npos ? where : where.substr(at + 2)));
  }
  for (size_t k = 0; k < prim.targets.size(); ++k) {
    const double w = morph->weights[k];
    if (!std::isfinite(w)) {
      throw InputError(src.file + ": " + morph->pointer + "/" + std::to_string(k), "must be finite, got " + FormatNumber(w));
    }
    if (w == 0) continue;
    const std::string target_where = where + "/targets/" + std::to_string(k);
    for (auto [name, values] : {std::pair{"POSITION", pos}, std::pair{"NORMAL", nrm}}) {
      auto it = prim.targets[k].find(name);
      if (it == prim.targets[k].end() || values->empty()) continue;
      CheckAccessorRef(src, it->second, target_where + "/" + name);
      const std::vector<float> delta = ReadFloatAccessor(src, it->second, 3);
      CheckFinite(src, it->second, delta, 3, "morph target displacement");
      if (delta.size() != values->size()) {
        throw InputError(GltfWhere(src, "accessors", it->second),
                         std::to_string(delta.size() / 3) + " elements, POSITION " + std::to_string(pos->size() / 3));
      }
      for (size_t i = 0; i < delta.size(); ++i) (*values)[i] = float(double((*values)[i]) + w * double(delta[i]));
    }
  }
}

}  // namespace lt::gltf_mesh_detail
