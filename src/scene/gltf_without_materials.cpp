#include "scene/gltf_without_materials.h"

namespace lt {

namespace {

using JsonValue = nlohmann::json;

constexpr const char* kSections[] = {"materials", "textures", "images", "samplers"};
constexpr const char* kVariants = "KHR_materials_variants";

// Calls `f` on each mesh primitive that is an object.
template <typename Json, typename F>
void ForEachPrimitive(Json& root, F f) {
  auto meshes = root.find("meshes");
  if (meshes == root.end() || !meshes->is_array()) return;
  for (auto& mesh : *meshes) {
    if (!mesh.is_object()) continue;
    auto prims = mesh.find("primitives");
    if (prims == mesh.end() || !prims->is_array()) continue;
    for (auto& p : *prims) {
      if (p.is_object()) f(p);
    }
  }
}

template <typename Json>
bool HasVariants(Json& o) {
  auto ext = o.find("extensions");
  return ext != o.end() && ext->is_object() && ext->contains(kVariants);
}

void EraseVariants(JsonValue& o) {
  auto ext = o.find("extensions");
  if (ext == o.end() || !ext->is_object()) return;
  ext->erase(kVariants);
  if (ext->empty()) o.erase("extensions");
}

}  // namespace

bool IsGltfMaterialExtension(const std::string& name) {
  if (name.rfind("KHR_materials_", 0) == 0) return true;
  // KHR_techniques_webgl (and its 2.0-draft name, which COLLADA2GLTF's -t wrote):
  // materials as WebGL shader programs.
  for (const char* e : {"KHR_texture_basisu", "KHR_texture_transform", "EXT_texture_webp", "EXT_texture_avif",
                        "MSFT_texture_dds", "KHR_techniques_webgl", "KHR_technique_webgl"}) {
    if (name == e) return true;
  }
  return false;
}

bool HasGltfMaterials(const nlohmann::json& root) {
  if (!root.is_object()) return false;
  for (const char* s : kSections) {
    if (root.contains(s)) return true;
  }
  bool any = HasVariants(root);
  ForEachPrimitive(root, [&](const JsonValue& p) { any = any || p.contains("material") || HasVariants(p); });
  return any;
}

void DropGltfMaterials(nlohmann::json* root) {
  if (!root->is_object()) return;
  for (const char* s : kSections) root->erase(s);
  EraseVariants(*root);
  ForEachPrimitive(*root, [](JsonValue& p) {
    p.erase("material");
    EraseVariants(p);
  });
}

}  // namespace lt
