#include "scene/gltf_json_check.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <vector>

#include <Eigen/Geometry>

#include "core/error.h"
#include "core/json_reader.h"
#include "scene/gltf_json_data.h"
#include "scene/gltf_schema.h"
#include "scene/gltf_used.h"
#include "scene/gltf_without_materials.h"


namespace lt {

namespace {

constexpr size_t kMaxJsonDepth = 256;        // nested arrays and objects

// ---------------------------------------------------------------- integers written as decimals

// The properties glTF 2.0 and the extensions read here define as integers (indices
// of other objects, counts, offsets, enums), besides the elements of `children`,
// `nodes` and `joints` and the values of `attributes` and of each morph target.
bool IsIntegerKey(const std::string& key) {
  static const std::set<std::string> kKeys = {
      "buffer", "bufferView", "byteOffset", "byteLength", "byteStride", "target", "count", "componentType",
      "mode", "indices", "material", "mesh", "skin", "camera", "node", "scene", "sampler", "source", "index",
      "texCoord", "input", "output", "skeleton", "inverseBindMatrices", "magFilter", "minFilter", "wrapS",
      "wrapT", "light"};
  return kKeys.count(key) != 0;
}
bool IsIntegerListKey(const std::string& key) { return key == "children" || key == "nodes" || key == "joints"; }

// A decimal with a zero fractional part that a double holds exactly.
bool IsIntegralDecimal(const nlohmann::json& v) {
  if (!v.is_number_float()) return false;
  const double d = v.get<double>();
  return std::isfinite(d) && std::floor(d) == d && std::fabs(d) <= 9007199254740992.0;
}

// Calls `at` on every value of `j` in an integer position (above), outermost first.
template <typename Json, typename Visit>
void ForEachIntegerPosition(Json& j, const Visit& at) {
  if (j.is_array()) {
    for (auto& e : j) ForEachIntegerPosition(e, at);
    return;
  }
  if (!j.is_object()) return;
  for (auto it = j.begin(); it != j.end(); ++it) {
    auto& v = it.value();
    if (IsIntegerKey(it.key())) at(v);
    if (IsIntegerListKey(it.key()) && v.is_array()) {
      for (auto& e : v) at(e);
    }
    if (it.key() == "attributes" && v.is_object()) {
      for (auto& e : v) at(e);
    }
    if (it.key() == "targets" && v.is_array()) {
      for (auto& target : v) {
        if (target.is_object()) {
          for (auto& e : target) at(e);
        }
      }
    }
    ForEachIntegerPosition(v, at);
  }
}

// Fails when arrays and objects nest deeper than kMaxJsonDepth. tinygltf converts
// extras and extensions recursively, so a file nested 100 000 levels deep would
// overflow its stack; this scan (strings skipped) runs before any parser sees the text.
void CheckJsonDepth(const std::string& text, const std::string& file) {
  size_t depth = 0, line = 1, line_start = 0;
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    switch (c) {
      case '"': in_string = true; break;
      case '\n':
        ++line;
        line_start = i + 1;
        break;
      case '[':
      case '{':
        if (++depth > kMaxJsonDepth) {
          throw InputError(file + ":" + std::to_string(line) + ":" + std::to_string(i - line_start + 1),
                           "invalid glTF: JSON nesting depth exceeds the limit of " + std::to_string(kMaxJsonDepth) +
                               " levels");
        }
        break;
      case ']':
      case '}':
        if (depth > 0) --depth;
        break;
      default: break;
    }
  }
}


// Whether a node's matrix places it as its translation / rotation / scale do
// (the identity for those not given), to about float precision. False when one
// of them is not an array of numbers of the right length (tinygltf reports it).
bool MatrixPlacesAsTrs(const nlohmann::json& node) {
  auto numbers = [&](const char* key, size_t count, std::vector<double> fallback) -> std::optional<std::vector<double>> {
    auto it = node.find(key);
    if (it == node.end()) return fallback;
    if (!it->is_array() || it->size() != count) return std::nullopt;
    std::vector<double> v;
    for (const auto& x : *it) {
      if (!x.is_number()) return std::nullopt;
      v.push_back(x.get<double>());
    }
    return v;
  };
  const auto m = numbers("matrix", 16, {});
  const auto t = numbers("translation", 3, {0, 0, 0});
  const auto r = numbers("rotation", 4, {0, 0, 0, 1});
  const auto s = numbers("scale", 3, {1, 1, 1});
  if (!m || !t || !r || !s) return false;
  Eigen::Matrix4d matrix;
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < 4; ++k) matrix(k, c) = (*m)[size_t(4 * c + k)];
  }
  const Eigen::Quaterniond q((*r)[3], (*r)[0], (*r)[1], (*r)[2]);
  if (!(q.norm() > 1e-6)) return false;
  Eigen::Affine3d trs = Eigen::Translation3d((*t)[0], (*t)[1], (*t)[2]) * q.normalized() *
                        Eigen::Scaling((*s)[0], (*s)[1], (*s)[2]);
  const double scale = std::max({1.0, matrix.cwiseAbs().maxCoeff(), trs.matrix().cwiseAbs().maxCoeff()});
  return matrix.allFinite() && (matrix - trs.matrix()).cwiseAbs().maxCoeff() <= 1e-5 * scale;
}

}  // namespace

void CheckGltfJson(const GltfContainer& container, const std::string& file, const std::filesystem::path& base_dir,
                   GltfExternalFiles* external, std::string* rewritten, std::vector<std::string>* warnings,
                   bool materials) {
  CheckJsonDepth(container.json_text, file);
  json::Document doc = json::Document::Parse(container.json_text, file, base_dir);
  nlohmann::json fixed;
  bool changed = false;
  // Without materials, nothing of them is checked or read further (gltf_without_materials.h).
  if (!materials && HasGltfMaterials(doc.Root().raw())) {
    fixed = doc.Root().raw();
    DropGltfMaterials(&fixed);
    changed = true;
  }
  // Integers written as decimals (most files have none: no copy then).
  bool decimals = false;
  ForEachIntegerPosition(changed ? fixed : doc.Root().raw(),
                         [&](const nlohmann::json& v) { decimals |= IsIntegralDecimal(v); });
  if (decimals) {
    if (!changed) fixed = doc.Root().raw();
    ForEachIntegerPosition(fixed, [](nlohmann::json& v) {
      if (IsIntegralDecimal(v)) v = static_cast<int64_t>(v.get<double>());
    });
    changed = true;
  }
  // What exporters wrote against glTF and viewers read (copied only then).
  if (NeedsGltfFixUp(changed ? fixed : doc.Root().raw())) {
    nlohmann::json copy = changed ? fixed : doc.Root().raw();
    std::vector<std::string> fix_warnings;
    if (FixUpGltfJson(&copy, file, &fix_warnings)) {
      fixed = std::move(copy);
      changed = true;
      if (warnings) warnings->insert(warnings->end(), fix_warnings.begin(), fix_warnings.end());
    }
  }
  if (changed && rewritten) *rewritten = fixed.dump();
  const nlohmann::json& root = changed ? fixed : doc.Root().raw();
  if (!root.is_object()) throw InputError(file, "invalid glTF: the top level must be a JSON object");
  auto asset = root.find("asset");
  if (asset == root.end() || !asset->is_object()) throw InputError(file + ": /asset", "missing required object");
  auto version = asset->find("version");
  if (version == asset->end() || !version->is_string() || version->get<std::string>().rfind("2.", 0) != 0) {
    // glTF 1.0 (obj2gltf 1.x, COLLADA2GLTF 1.x, CesiumJS's older tiles) and its drafts.
    const bool old = version != asset->end() && version->is_string() &&
                     (version->get<std::string>().rfind("1.", 0) == 0 || version->get<std::string>().rfind("0.", 0) == 0);
    throw InputError(file + ": /asset/version",
                     "glTF version must be 2.x, got " + (version == asset->end() ? std::string("none") : version->dump()) +
                         (old ? " (upgrade the file to glTF 2.0: gltf-pipeline -i in.gltf -o out.gltf does)" : ""));
  }
  CheckGltfSchema(root, file);
  // Read, converted, or ignored as glTF allows and warned about: lights (the
  // scene file sets the sensor and the lights), material variants (each
  // primitive's `material` is the one shown when no variant is chosen) and
  // animation pointers (animations are not played).
  static const std::set<std::string> kSupported = {
      "KHR_materials_emissive_strength", "KHR_mesh_quantization",         "KHR_texture_transform",
      "EXT_mesh_gpu_instancing",         "KHR_materials_pbrSpecularGlossiness", "KHR_materials_unlit",
      "KHR_materials_transmission",      "KHR_lights_punctual",          "KHR_materials_variants",
      "KHR_node_visibility",             "CESIUM_RTC",                   "KHR_animation_pointer"};
  if (auto req = root.find("extensionsRequired"); req != root.end() && req->is_array()) {
    for (size_t i = 0; i < req->size(); ++i) {
      const auto& e = (*req)[i];
      if (!e.is_string() || (kSupported.count(e.get<std::string>()) == 0 &&
                             (materials || !IsGltfMaterialExtension(e.get<std::string>())))) {
        // What to do about the extensions that optimising tools write.
        static const char* kShaders =
            "the materials are WebGL shader programs: give the object its own \"material\", which replaces them";
        static const std::map<std::string, std::string> kHints = {
            {"KHR_draco_mesh_compression", "the meshes are Draco-compressed: write or convert the file without compression"},
            {"EXT_meshopt_compression", "the buffers are meshopt-compressed: write the file without it, e.g. gltfpack without -c/-cc"},
            {"KHR_meshopt_compression", "the buffers are meshopt-compressed: write the file without it, e.g. gltfpack without -c/-cc"},
            {"KHR_texture_basisu", "the textures are KTX2: write or convert them as PNG or JPEG"},
            {"EXT_texture_webp", "the textures are WebP: write or convert them as PNG or JPEG"},
            {"EXT_texture_avif", "the textures are AVIF: write or convert them as PNG or JPEG"},
            {"KHR_techniques_webgl", kShaders},
            {"KHR_technique_webgl", kShaders},
            {"KHR_materials_common", "the materials are glTF 1.0's Blinn, Phong, Lambert or constant shading: give the "
                                     "object its own \"material\", which replaces them"}};
        auto hint = e.is_string() ? kHints.find(e.get<std::string>()) : kHints.end();
        throw InputError(file + ": /extensionsRequired/" + std::to_string(i),
                         "required extension " + e.dump() + " is not supported" +
                             (hint != kHints.end() ? " (" + hint->second + ")" : std::string()));
      }
    }
  }
  // glTF gives a node a matrix or translation / rotation / scale, never both.
  // tinygltf reads the matrix and drops the rest, which is right when the rest
  // is the identity or places the node as the matrix does; otherwise the node
  // would be placed without it.
  if (auto nodes = root.find("nodes"); nodes != root.end() && nodes->is_array()) {
    for (size_t i = 0; i < nodes->size(); ++i) {
      const auto& n = (*nodes)[i];
      if (!n.is_object() || !n.contains("matrix")) continue;
      const char* key = nullptr;
      for (const char* k : {"translation", "rotation", "scale"}) {
        if (!key && n.contains(k)) key = k;
      }
      if (key && !MatrixPlacesAsTrs(n)) {
        throw InputError(file + ": /nodes/" + std::to_string(i),
                         std::string("has both a matrix and a ") + key +
                             " that place it differently (glTF gives a node one or the other: a matrix, or "
                             "translation / rotation / scale)");
      }
    }
  }
  CheckGltfBufferData(root, container.binary, file, base_dir, external);
  // A GLB's buffer 0 without uri is its BIN chunk, which may be longer (padding), not shorter.
  if (auto buffers = root.find("buffers"); container.binary && buffers != root.end() && buffers->is_array() &&
                                           !buffers->empty() && (*buffers)[0].is_object() &&
                                           !(*buffers)[0].contains("uri")) {
    auto length = (*buffers)[0].find("byteLength");
    if (length != (*buffers)[0].end() && length->is_number_unsigned() &&
        length->get<uint64_t>() > (container.has_bin ? container.bin_length : 0)) {
      throw InputError(file + ": /buffers/0/byteLength",
                       std::to_string(length->get<uint64_t>()) + " bytes, but " +
                           (container.has_bin ? "the GLB's BIN chunk holds " + std::to_string(container.bin_length)
                                              : std::string("the GLB has no BIN chunk")) +
                           " (buffer 0 without a uri is the BIN chunk; a truncated or mis-written file?)");
    }
  }
  // A Draco-compressed primitive that is not required may keep uncompressed
  // attributes as a fallback; its accessors without a bufferView are placeholders
  // (zeros to a reader without Draco), so such a primitive cannot be read.
  auto accessors = root.find("accessors");
  auto has_data = [&](const nlohmann::json& index) {
    if (!index.is_number_unsigned() || accessors == root.end() || !accessors->is_array() ||
        index.get<uint64_t>() >= accessors->size()) {
      return true;  // a dangling reference is reported later, where it is read
    }
    const auto& a = (*accessors)[index.get<size_t>()];
    return !a.is_object() || a.contains("bufferView") || a.contains("sparse");
  };
  if (auto meshes = root.find("meshes"); meshes != root.end() && meshes->is_array()) {
    for (size_t mi = 0; mi < meshes->size(); ++mi) {
      const auto& mesh = (*meshes)[mi];
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      const auto& prims = mesh["primitives"];
      for (size_t pi = 0; pi < prims.size(); ++pi) {
        const auto& p = prims[pi];
        if (!p.is_object() || !p.contains("extensions") || !p["extensions"].is_object() ||
            !p["extensions"].contains("KHR_draco_mesh_compression")) {
          continue;
        }
        std::vector<std::pair<std::string, nlohmann::json>> refs;
        if (p.contains("indices")) refs.emplace_back("indices", p["indices"]);
        if (p.contains("attributes") && p["attributes"].is_object()) {
          for (const auto& [name, index] : p["attributes"].items()) refs.emplace_back("attributes/" + name, index);
        }
        for (const auto& [name, index] : refs) {
          if (!has_data(index)) {
            throw InputError(file + ": /meshes/" + std::to_string(mi) + "/primitives/" + std::to_string(pi),
                             "compressed with KHR_draco_mesh_compression, which is not supported, and accessor " +
                                 index.dump() + " (its " + name +
                                 ") has no uncompressed data to fall back on (no bufferView); write the file "
                                 "without Draco");
          }
        }
      }
    }
  }
  // Only the images of the materials some triangle uses are read (gltf_used.h).
  GltfUse use = FindGltfUse(root);
  CheckGltfImageFiles(root, file, base_dir, use.images, external);
  if (external != nullptr) external->use = std::move(use);
}

}  // namespace lt
