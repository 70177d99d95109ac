#include "scene/gltf_nodes.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "core/error.h"
#include "core/json_reader.h"
#include "core/text_fields.h"

namespace lt {

namespace {


// The affine transform of a column-major 4x4 matrix (node matrices, inverse bind
// matrices); nullopt when it is not finite or its last row is not 0 0 0 1.
// Exporters write float matrices: the last row may be off by float noise,
// relative to the matrix's scale, and is then made exact.
template <typename T>
std::optional<Eigen::Affine3d> AffineFromColumnMajor(const T* values) {
  Eigen::Matrix4d m;
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) m(r, c) = double(values[4 * c + r]);
  }
  if (!m.allFinite()) return std::nullopt;
  const double tol = 1e-5 * std::max(1.0, m.topRows<3>().cwiseAbs().maxCoeff());
  if (m.row(3).head<3>().cwiseAbs().maxCoeff() > tol || std::abs(m(3, 3) - 1) > 1e-5) return std::nullopt;
  m.row(3) << 0, 0, 0, 1;
  Eigen::Affine3d t;
  t.matrix() = m;
  return t;
}

Eigen::Affine3d LocalTransform(const tinygltf::Node& node, const std::string& where) {
  auto finite = [&](const std::vector<double>& v, const char* key) {
    for (double x : v) {
      if (!std::isfinite(x)) throw InputError(where + "/" + key, "must be finite, got " + FormatNumber(x));
    }
  };
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) throw InputError(where + "/matrix", "must have 16 elements");
    finite(node.matrix, "matrix");
    std::optional<Eigen::Affine3d> m = AffineFromColumnMajor(node.matrix.data());
    if (!m) throw InputError(where + "/matrix", "must be affine (last row 0 0 0 1)");
    return *m;
  }
  if (!node.translation.empty()) {
    if (node.translation.size() != 3) throw InputError(where + "/translation", "must have 3 elements");
    finite(node.translation, "translation");
    t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
  }
  if (!node.rotation.empty()) {
    if (node.rotation.size() != 4) throw InputError(where + "/rotation", "must have 4 elements");
    finite(node.rotation, "rotation");
    Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF: x y z w
    if (q.norm() < 1e-6) throw InputError(where + "/rotation", "must be a unit quaternion, got norm " + FormatNumber(q.norm()));
    t.rotate(q.normalized());
  }
  if (!node.scale.empty()) {
    if (node.scale.size() != 3) throw InputError(where + "/scale", "must have 3 elements");
    finite(node.scale, "scale");
    t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
  }
  return t;
}


// The global transform of node `index`, from the root of its hierarchy (which
// need not be in the default scene: a skin's joints may lie anywhere).
Eigen::Affine3d NodeGlobal(const GltfSource& src, const std::vector<int>& parent, int index) {
  std::vector<int> chain;
  for (int n = index; n >= 0; n = parent[size_t(n)]) {
    if (chain.size() > parent.size()) {
      throw InputError(GltfWhere(src, "nodes", index), "node is its own ancestor (the node hierarchy has a cycle)");
    }
    chain.push_back(n);
  }
  Eigen::Affine3d global = Eigen::Affine3d::Identity();
  for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
    global = global * LocalTransform(src.model.nodes[size_t(*it)], GltfWhere(src, "nodes", *it));
  }
  return global;
}

}  // namespace

GltfSkinPose GltfSkinPoseOf(const GltfSource& src, int index) {
  const auto& m = src.model;
  const tinygltf::Skin& skin = m.skins[size_t(index)];
  GltfSkinPose pose;
  pose.pointer = "/skins/" + std::to_string(index);
  const std::string where = GltfWhere(src, "skins", index);
  if (skin.joints.empty()) throw InputError(where + "/joints", "a skin needs at least one joint");
  std::vector<int> parent(m.nodes.size(), -1);
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    for (int c : m.nodes[i].children) {
      if (c >= 0 && size_t(c) < m.nodes.size() && parent[size_t(c)] < 0) parent[size_t(c)] = int(i);
    }
  }
  std::vector<float> ibm;
  if (skin.inverseBindMatrices >= 0) {
    if (size_t(skin.inverseBindMatrices) >= m.accessors.size()) {
      throw InputError(where + "/inverseBindMatrices", "accessor " + std::to_string(skin.inverseBindMatrices) +
                                                                " does not exist (" +
                                                                std::to_string(m.accessors.size()) + " accessors)");
    }
    ibm = ReadFloatAccessor(src, skin.inverseBindMatrices, 16);
    if (ibm.size() / 16 < skin.joints.size()) {
      throw InputError(GltfWhere(src, "accessors", skin.inverseBindMatrices),
                       std::to_string(ibm.size() / 16) + " inverse bind matrices for " +
                           std::to_string(skin.joints.size()) + " joints");
    }
  }
  for (size_t k = 0; k < skin.joints.size(); ++k) {
    const int joint = skin.joints[k];
    if (joint < 0 || size_t(joint) >= m.nodes.size()) {
      throw InputError(where + "/joints/" + std::to_string(k), "node " + std::to_string(joint) +
                                                                        " does not exist (" +
                                                                        std::to_string(m.nodes.size()) + " nodes)");
    }
    Eigen::Affine3d inverse_bind = Eigen::Affine3d::Identity();
    if (!ibm.empty()) {
      for (int e = 0; e < 16; ++e) {
        if (!std::isfinite(ibm[16 * k + size_t(e)])) {
          throw InputError(GltfWhere(src, "accessors", skin.inverseBindMatrices),
                           "inverse bind matrix " + std::to_string(k) + " is not finite (" +
                               FormatNumber(ibm[16 * k + size_t(e)]) + " at column " + std::to_string(e / 4) +
                               ", row " + std::to_string(e % 4) + ")");
        }
      }
      std::optional<Eigen::Affine3d> b = AffineFromColumnMajor(ibm.data() + 16 * k);
      if (!b) {
        throw InputError(GltfWhere(src, "accessors", skin.inverseBindMatrices),
                         "inverse bind matrix " + std::to_string(k) + " must be affine (last row 0 0 0 1)");
      }
      inverse_bind = *b;
    }
    pose.joint_matrices.push_back(NodeGlobal(src, parent, joint) * inverse_bind);
  }
  return pose;
}

namespace {

// The instance transforms of a node's EXT_mesh_gpu_instancing: T * R * S from
// its TRANSLATION, ROTATION (unit quaternion x, y, z, w) and SCALE accessors.
std::vector<Eigen::Affine3d> GpuInstances(const GltfSource& src, const tinygltf::Value& ext, const std::string& where) {
  const tinygltf::Value& attributes = ext.IsObject() ? ext.Get("attributes") : ext;
  if (!attributes.IsObject()) throw InputError(where + "/attributes", "must be an object");
  const char* kNames[3] = {"TRANSLATION", "ROTATION", "SCALE"};
  std::vector<float> values[3];
  size_t count = 0;
  const char* first = nullptr;
  for (int a = 0; a < 3; ++a) {
    if (!attributes.Has(kNames[a])) continue;
    const std::string at = where + "/attributes/" + kNames[a];
    const tinygltf::Value& index = attributes.Get(kNames[a]);
    if (!index.IsInt() || index.GetNumberAsInt() < 0 || size_t(index.GetNumberAsInt()) >= src.model.accessors.size()) {
      throw InputError(at, "must name one of the " + std::to_string(src.model.accessors.size()) + " accessors");
    }
    const int components = a == 1 ? 4 : 3;
    values[a] = ReadFloatAccessor(src, index.GetNumberAsInt(), components);
    const size_t n = values[a].size() / size_t(components);
    if (first == nullptr) {
      first = kNames[a];
      count = n;
    } else if (n != count) {
      throw InputError(at, std::to_string(n) + " elements, " + first + " has " + std::to_string(count));
    }
    for (size_t i = 0; i < values[a].size(); ++i) {
      if (!std::isfinite(values[a][i])) {
        throw InputError(GltfWhere(src, "accessors", index.GetNumberAsInt()),
                         "instance " + std::to_string(i / size_t(components)) + " is not finite (" +
                             FormatNumber(values[a][i]) + ")");
      }
    }
  }
  if (first == nullptr) throw InputError(where + "/attributes", "needs TRANSLATION, ROTATION or SCALE");
  std::vector<Eigen::Affine3d> out(count, Eigen::Affine3d::Identity());
  for (size_t i = 0; i < count; ++i) {
    if (!values[0].empty()) out[i].translate(Eigen::Vector3d(values[0][3 * i], values[0][3 * i + 1], values[0][3 * i + 2]));
    if (!values[1].empty()) {
      const float* q = values[1].data() + 4 * i;
      const Eigen::Quaterniond r(q[3], q[0], q[1], q[2]);  // x y z w
      if (r.norm() < 1e-6) {
        throw InputError(where + "/attributes/ROTATION", "instance " + std::to_string(i) +
                                                             " is not a unit quaternion (norm " +
                                                             FormatNumber(r.norm()) + ")");
      }
      out[i].rotate(r.normalized());
    }
    if (!values[2].empty()) out[i].scale(Eigen::Vector3d(values[2][3 * i], values[2][3 * i + 1], values[2][3 * i + 2]));
  }
  return out;
}

}  // namespace

std::vector<GltfNodeUse> WalkGltfScene(const GltfSource& src, std::vector<std::string>* warnings) {
  const auto& m = src.model;
  std::vector<int> roots;
  std::string roots_where;  // "/scenes/0/nodes", or empty for the parentless nodes
  if (m.defaultScene >= 0 || !m.scenes.empty()) {
    int scene = m.defaultScene >= 0 ? m.defaultScene : 0;
    if (size_t(scene) >= m.scenes.size()) {
      throw InputError(src.file + ": /scene", "scene " + std::to_string(scene) + " does not exist (" +
                                                  std::to_string(m.scenes.size()) + " scenes)");
    }
    if (m.defaultScene < 0 && m.scenes.size() > 1) {
      warnings->push_back(src.file + ": no default scene (\"scene\"); scene 0 of " + std::to_string(m.scenes.size()) +
                          " is loaded");
    }
    roots = m.scenes[size_t(scene)].nodes;
    roots_where = "/scenes/" + std::to_string(scene) + "/nodes";
    for (size_t i = 0; i < roots.size(); ++i) {
      if (roots[i] < 0 || size_t(roots[i]) >= m.nodes.size()) {
        throw InputError(src.file + ": " + roots_where + "/" + std::to_string(i),
                         "node " + std::to_string(roots[i]) + " does not exist (" + std::to_string(m.nodes.size()) +
                             " nodes)");
      }
    }
  } else {
    std::vector<char> is_child(m.nodes.size(), 0);
    for (const auto& n : m.nodes) {
      for (int c : n.children) {
        if (c >= 0 && size_t(c) < m.nodes.size()) is_child[size_t(c)] = 1;
      }
    }
    for (size_t i = 0; i < m.nodes.size(); ++i) {
      if (!is_child[i]) roots.push_back(int(i));
    }
    if (!m.meshes.empty()) warnings->push_back(src.file + ": no scene defined; all root nodes are loaded");
  }
  auto node_name = [&](int index) {
    const std::string& name = m.nodes[size_t(index)].name;
    return name.empty() ? "node " + std::to_string(index) : name;
  };
  // A list (scene roots or a node's children) without repeats: a repeat would be
  // a second, coincident copy of the same subtree.
  auto unique = [&](const std::vector<int>& list, const std::string& list_where) {
    std::vector<int> out;
    std::set<int> seen;
    for (size_t i = 0; i < list.size(); ++i) {
      if (seen.insert(list[i]).second) {
        out.push_back(list[i]);
      } else {
        warnings->push_back(src.file + ": " + list_where + "/" + std::to_string(i) + ": node " +
                            std::to_string(list[i]) + " is listed twice; placed once");
      }
    }
    return out;
  };
  // Parents of each node (distinct), for the warning about shared nodes.
  std::vector<int> parents(m.nodes.size(), 0);
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    std::set<int> children(m.nodes[i].children.begin(), m.nodes[i].children.end());
    for (int c : children) {
      if (c >= 0 && size_t(c) < m.nodes.size()) ++parents[size_t(c)];
    }
  }

  struct Entry {
    int index;
    Eigen::Affine3d parent;
    size_t depth;  // length of the path above the node
  };
  std::vector<GltfNodeUse> uses;
  std::vector<std::string> hidden;     // the nodes KHR_node_visibility hides
  std::vector<int> path;               // the nodes from the root down to the current one
  std::vector<char> on_path(m.nodes.size(), 0), warned(m.nodes.size(), 0);
  // Shared nodes multiply: a bound on the placements keeps a malicious file from
  // expanding exponentially.
  const size_t max_visits = std::max<size_t>(1000000, 16 * m.nodes.size());
  size_t visits = 0;
  std::vector<Entry> stack;
  roots = unique(roots, roots_where.empty() ? "/nodes (parentless)" : roots_where);
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, Eigen::Affine3d::Identity(), 0});
  while (!stack.empty()) {
    Entry e = stack.back();
    stack.pop_back();
    while (path.size() > e.depth) {
      on_path[size_t(path.back())] = 0;
      path.pop_back();
    }
    const int index = e.index;
    const std::string where = GltfWhere(src, "nodes", index);
    if (on_path[size_t(index)]) throw InputError(where, "node is its own ancestor (the node hierarchy has a cycle)");
    if (++visits > max_visits) {
      throw InputError(src.file, "the node hierarchy places more than " + std::to_string(max_visits) +
                                     " nodes (nodes shared by several parents multiply)");
    }
    on_path[size_t(index)] = 1;
    path.push_back(index);
    if (parents[size_t(index)] > 1 && !warned[size_t(index)]) {
      warned[size_t(index)] = 1;
      warnings->push_back(src.file + ": node \"" + node_name(index) + "\" has " +
                          std::to_string(parents[size_t(index)]) +
                          " parents (glTF asks for a tree); it is placed under each");
    }
    const tinygltf::Node& node = m.nodes[size_t(index)];
    // KHR_node_visibility (Godot 4.5+): a node written invisible hides itself and
    // all its descendants, as viewers show the file.
    if (auto vis = node.extensions.find("KHR_node_visibility"); vis != node.extensions.end() && vis->second.Has("visible")) {
      const tinygltf::Value& visible = vis->second.Get("visible");
      if (!visible.IsBool()) {
        throw InputError(where + "/extensions/KHR_node_visibility/visible", "must be true or false");
      }
      if (!visible.Get<bool>()) {
        hidden.push_back("\"" + node_name(index) + "\"");
        continue;
      }
    }
    Eigen::Affine3d global = e.parent * LocalTransform(node, where);
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= m.meshes.size()) {
        throw InputError(where + "/mesh", "mesh " + std::to_string(node.mesh) + " does not exist (" +
                                              std::to_string(m.meshes.size()) + " meshes)");
      }
      const std::string name = node_name(index);
      GltfMorphWeights morph;
      if (!node.weights.empty()) {
        morph = {node.weights, "/nodes/" + std::to_string(index) + "/weights"};
      } else if (!m.meshes[size_t(node.mesh)].weights.empty()) {
        morph = {m.meshes[size_t(node.mesh)].weights, "/meshes/" + std::to_string(node.mesh) + "/weights"};
      }
      auto instancing = node.extensions.find("EXT_mesh_gpu_instancing");
      if (node.skin >= 0) {
        if (size_t(node.skin) >= m.skins.size()) {
          throw InputError(where + "/skin", "skin " + std::to_string(node.skin) + " does not exist (" +
                                                std::to_string(m.skins.size()) + " skins)");
        }
        if (instancing != node.extensions.end()) {
          warnings->push_back(src.file + ": node \"" + name + "\": EXT_mesh_gpu_instancing of a skinned mesh "
                              "ignored (the skin places the mesh once)");
        }
        // glTF 2.0 3.7.3.3: the joints place a skinned mesh; its node's transform is ignored.
        uses.push_back({node.mesh, Eigen::Affine3d::Identity(), name, node.skin, morph});
      } else {
        std::vector<std::pair<Eigen::Affine3d, std::string>> placements;
        if (instancing != node.extensions.end()) {
          const std::vector<Eigen::Affine3d> instances =
              GpuInstances(src, instancing->second, where + "/extensions/EXT_mesh_gpu_instancing");
          for (size_t k = 0; k < instances.size(); ++k) {
            placements.emplace_back(global * instances[k], name + "/instance " + std::to_string(k));
          }
        } else {
          placements.emplace_back(global, name);
        }
        size_t singular = 0;
        for (auto& [transform, placed_name] : placements) {
          const double det = transform.linear().determinant();
          if (!(std::abs(det) > 1e-30) || !transform.matrix().allFinite()) {
            ++singular;
          } else {
            uses.push_back({node.mesh, transform, placed_name, -1, morph});
          }
        }
        if (singular == 1 && placements.size() == 1) {
          warnings->push_back(src.file + ": node \"" + name + "\" has a singular transform; its mesh is skipped");
        } else if (singular > 0) {
          warnings->push_back(src.file + ": node \"" + name + "\": " + std::to_string(singular) + " of its " +
                              std::to_string(placements.size()) +
                              " EXT_mesh_gpu_instancing instances have a singular transform; they are skipped");
        }
      }
    } else if (node.mesh < -1) {
      throw InputError(where + "/mesh", "must be >= 0, got " + std::to_string(node.mesh));
    }
    for (size_t c = 0; c < node.children.size(); ++c) {
      int child = node.children[c];
      if (child < 0 || size_t(child) >= m.nodes.size()) {
        throw InputError(where + "/children/" + std::to_string(c),
                         "node " + std::to_string(child) + " does not exist (" + std::to_string(m.nodes.size()) +
                             " nodes)");
      }
    }
    const std::vector<int> children = unique(node.children, "/nodes/" + std::to_string(index) + "/children");
    for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back({*it, global, path.size()});
  }
  if (!hidden.empty()) {
    warnings->push_back(src.file + ": " + std::to_string(hidden.size()) +
                        (hidden.size() == 1 ? " node" : " nodes") +
                        " hidden by KHR_node_visibility (\"visible\": false) not loaded, with their descendants: " +
                        ListFirst(hidden, 3));
  }
  return uses;
}

}  // namespace lt
