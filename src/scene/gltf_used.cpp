// FindGltfUse (gltf_used.h): the materials and images a glTF's triangles use.
#include "scene/gltf_used.h"

#include <string>

namespace lt {

namespace {

using nlohmann::json;

// The non-negative integer `o[key]`, or -1.
long long IndexAt(const json& o, const char* key) {
  if (!o.is_object()) return -1;
  auto it = o.find(key);
  return it != o.end() && it->is_number_integer() && it->get<long long>() >= 0 ? it->get<long long>() : -1;
}

// The elements of the top-level array `name` (an empty array when absent or not one).
const json& Section(const json& root, const char* name) {
  static const json kEmpty = json::array();
  auto it = root.find(name);
  return it != root.end() && it->is_array() ? *it : kEmpty;
}

void Mark(std::vector<bool>* used, long long index) {
  if (index >= 0 && size_t(index) < used->size()) (*used)[size_t(index)] = true;
}

// Marks the texture of every textureInfo in `o` (a material or a part of it).
void MarkTextures(const json& o, std::vector<bool>* textures) {
  if (!o.is_object()) return;
  for (auto it = o.begin(); it != o.end(); ++it) {
    const std::string& key = it.key();
    if (key.size() >= 7 && key.compare(key.size() - 7, 7, "Texture") == 0) Mark(textures, IndexAt(it.value(), "index"));
    if (it.value().is_object()) MarkTextures(it.value(), textures);
  }
}

}  // namespace

GltfUse FindGltfUse(const json& root) {
  GltfUse use;
  if (!root.is_object()) return use;
  const json& nodes = Section(root, "nodes");
  const json& meshes = Section(root, "meshes");
  const json& materials = Section(root, "materials");
  const json& textures = Section(root, "textures");
  use.materials.assign(materials.size(), false);
  use.images.assign(Section(root, "images").size(), false);

  // The nodes the loaded scene holds: its roots and all below them.
  std::vector<bool> placed(nodes.size(), false);
  std::vector<long long> stack;
  const json& scenes = Section(root, "scenes");
  long long scene = root.contains("scene") ? IndexAt(root, "scene") : (scenes.empty() ? -1 : 0);
  if (scene >= 0 && size_t(scene) < scenes.size() && scenes[size_t(scene)].is_object() &&
      scenes[size_t(scene)].contains("nodes") && scenes[size_t(scene)]["nodes"].is_array()) {
    for (const json& n : scenes[size_t(scene)]["nodes"]) {
      if (n.is_number_integer()) stack.push_back(n.get<long long>());
    }
  } else {
    for (size_t i = 0; i < nodes.size(); ++i) stack.push_back(static_cast<long long>(i));  // no (valid) scene: every node
  }
  std::vector<bool> used_meshes(meshes.size(), false);
  while (!stack.empty()) {
    const long long n = stack.back();
    stack.pop_back();
    if (n < 0 || size_t(n) >= nodes.size() || placed[size_t(n)]) continue;
    placed[size_t(n)] = true;
    const json& node = nodes[size_t(n)];
    Mark(&used_meshes, IndexAt(node, "mesh"));
    if (node.is_object() && node.contains("children") && node["children"].is_array()) {
      for (const json& c : node["children"]) {
        if (c.is_number_integer()) stack.push_back(c.get<long long>());
      }
    }
  }
  for (size_t m = 0; m < meshes.size(); ++m) {
    if (!used_meshes[m] || !meshes[m].is_object() || !meshes[m].contains("primitives") ||
        !meshes[m]["primitives"].is_array()) {
      continue;
    }
    for (const json& p : meshes[m]["primitives"]) {
      const long long mode = p.is_object() && p.contains("mode") ? IndexAt(p, "mode") : 4;
      if (mode >= 0 && mode <= 3) continue;  // points and lines are skipped
      Mark(&use.materials, IndexAt(p, "material"));
    }
  }
  std::vector<bool> used_textures(textures.size(), false);
  for (size_t i = 0; i < materials.size(); ++i) {
    if (use.materials[i]) MarkTextures(materials[i], &used_textures);
  }
  for (size_t t = 0; t < textures.size(); ++t) {
    if (!used_textures[t] || !textures[t].is_object()) continue;
    Mark(&use.images, IndexAt(textures[t], "source"));
    if (textures[t].contains("extensions") && textures[t]["extensions"].is_object()) {
      for (const json& ext : textures[t]["extensions"]) Mark(&use.images, IndexAt(ext, "source"));
    }
  }
  return use;
}

}  // namespace lt
