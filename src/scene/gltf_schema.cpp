#include "scene/gltf_schema.h"

#include <cstdint>
#include <map>
#include <optional>
#include <set>

#include "core/error.h"
#include "core/text_fields.h"
#include "scene/gltf_json_data.h"

namespace lt {

namespace {

using nlohmann::json;

// A JSON integer (4, not 4.0: tinygltf refuses a float where glTF has an integer).
bool IsInteger(const json& v) { return v.is_number_integer(); }

int64_t AsInteger(const json& v) { return v.get<int64_t>(); }

struct Checker {
  const std::string& file;
  size_t textures = 0;  // the file's textures, which textureInfo indices name

  [[noreturn]] void Fail(const std::string& pointer, const std::string& message) const {
    throw InputError(file + ": " + pointer, message);
  }
  // The elements of the top-level array `name` (none when absent); an error when not an array of objects.
  const json* Array(const json& root, const char* name) const {
    auto it = root.find(name);
    if (it == root.end()) return nullptr;
    if (!it->is_array()) Fail(std::string("/") + name, "must be an array");
    for (size_t i = 0; i < it->size(); ++i) {
      if (!(*it)[i].is_object()) Fail(std::string("/") + name + "/" + std::to_string(i), "must be an object");
    }
    return &*it;
  }
  // Integer property `key` of `o`, `required` or absent, in [min, max] when given
  // (ranges the loader checks later with their meaning are left to it).
  void Integer(const json& o, const std::string& pointer, const char* key, bool required,
               int64_t min = INT64_MIN, int64_t max = INT64_MAX) const {
    auto it = o.find(key);
    if (it == o.end()) {
      if (required) Fail(pointer, std::string("missing required property \"") + key + "\"");
      return;
    }
    if (!IsInteger(*it) || AsInteger(*it) < min || AsInteger(*it) > max) {
      const std::string range = min == INT64_MIN ? ""
                                : max == INT64_MAX ? " >= " + std::to_string(min)
                                                   : " in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
      Fail(pointer + "/" + key, "must be an integer" + range + ", got " + it->dump());
    }
  }
  // Number property `key` of `o`, when present.
  void Number(const json& o, const std::string& pointer, const char* key) const {
    auto it = o.find(key);
    if (it != o.end() && !it->is_number()) Fail(pointer + "/" + key, "must be a number, got " + it->dump());
  }
  // Boolean property `key` of `o`, when present.
  void Boolean(const json& o, const std::string& pointer, const char* key) const {
    auto it = o.find(key);
    if (it != o.end() && !it->is_boolean()) Fail(pointer + "/" + key, "must be true or false, got " + it->dump());
  }
  // Number array property `key` of `o`, when present: `size` numbers (any count when 0).
  void Numbers(const json& o, const std::string& pointer, const char* key, size_t size) const {
    auto it = o.find(key);
    if (it == o.end()) return;
    const std::string at = pointer + "/" + key;
    if (!it->is_array() || (size != 0 && it->size() != size)) {
      const std::string what = size != 0 ? "an array of " + std::to_string(size) + " numbers" : "an array of numbers";
      Fail(at, "must be " + what + ", got " + (it->is_array() ? std::to_string(it->size()) + " elements" : it->dump()));
    }
    for (size_t k = 0; k < it->size(); ++k) {
      if (!(*it)[k].is_number()) Fail(at + "/" + std::to_string(k), "must be a number, got " + (*it)[k].dump());
    }
  }
  // Integer property `key` of `o`, when present, names one of the `count` `many`: a
  // dangling reference is refused wherever it is, used or not (negative values are
  // left to the loader).
  void Reference(const json& o, const std::string& pointer, const char* key, const char* one, const char* many,
                 size_t count) const {
    auto it = o.find(key);
    if (it == o.end() || !IsInteger(*it) || AsInteger(*it) < 0 || uint64_t(AsInteger(*it)) < count) return;
    Fail(pointer + "/" + key, std::string(one) + " " + it->dump() + " does not exist (" + std::to_string(count) + " " +
                                  many + ")");
  }
  // A textureInfo object `key` of `o` (baseColorTexture, normalTexture, ...), when present.
  void TextureInfo(const json& o, const std::string& pointer, const char* key) const {
    auto it = o.find(key);
    if (it == o.end()) return;
    const std::string at = pointer + "/" + key;
    if (!it->is_object()) Fail(at, "must be an object, got " + it->dump());
    Integer(*it, at, "index", true);
    Reference(*it, at, "index", "texture", "textures", textures);
    Integer(*it, at, "texCoord", false, 0);
    Number(*it, at, "scale");
    Number(*it, at, "strength");
  }
};

}  // namespace

void CheckGltfSchema(const json& root, const std::string& file) {
  auto count = [&](const char* name) {
    auto it = root.find(name);
    return it != root.end() && it->is_array() ? it->size() : size_t(0);
  };
  const Checker c{file, count("textures")};
  if (const json* accessors = c.Array(root, "accessors")) {
    static const std::set<int64_t> kComponentTypes = {5120, 5121, 5122, 5123, 5125, 5126};
    static const std::set<std::string> kTypes = {"SCALAR", "VEC2", "VEC3", "VEC4", "MAT2", "MAT3", "MAT4"};
    for (size_t i = 0; i < accessors->size(); ++i) {
      const json& a = (*accessors)[i];
      const std::string at = "/accessors/" + std::to_string(i);
      c.Integer(a, at, "bufferView", false);
      c.Integer(a, at, "byteOffset", false, 0);
      c.Integer(a, at, "count", true);
      c.Integer(a, at, "componentType", true);
      if (kComponentTypes.count(AsInteger(a["componentType"])) == 0) {
        c.Fail(at + "/componentType", "must be 5120 (byte), 5121 (unsigned byte), 5122 (short), 5123 (unsigned "
                                      "short), 5125 (unsigned int) or 5126 (float), got " + a["componentType"].dump());
      }
      auto type = a.find("type");
      if (type == a.end()) c.Fail(at, "missing required property \"type\"");
      if (!type->is_string() || kTypes.count(type->get<std::string>()) == 0) {
        c.Fail(at + "/type", "must be \"SCALAR\", \"VEC2\", \"VEC3\", \"VEC4\", \"MAT2\", \"MAT3\" or \"MAT4\", got " +
                                 type->dump());
      }
      c.Boolean(a, at, "normalized");
      // tinygltf: "the sparse object of this accessor doesn't have values", no place.
      if (auto sparse = a.find("sparse"); sparse != a.end()) {
        const std::string sat = at + "/sparse";
        if (!sparse->is_object()) c.Fail(sat, "must be an object, got " + sparse->dump());
        c.Integer(*sparse, sat, "count", true, 1);
        for (const char* key : {"indices", "values"}) {
          auto part = sparse->find(key);
          if (part == sparse->end()) c.Fail(sat, std::string("missing required property \"") + key + "\"");
          if (!part->is_object()) c.Fail(sat + "/" + key, "must be an object, got " + part->dump());
          c.Integer(*part, sat + "/" + key, "bufferView", true);
          c.Integer(*part, sat + "/" + key, "byteOffset", false, 0);
        }
        c.Integer((*sparse)["indices"], sat + "/indices", "componentType", true);
      }
    }
  }
  if (const json* views = c.Array(root, "bufferViews")) {
    for (size_t i = 0; i < views->size(); ++i) {
      const json& v = (*views)[i];
      const std::string at = "/bufferViews/" + std::to_string(i);
      c.Integer(v, at, "buffer", true);
      c.Integer(v, at, "byteLength", true, 0);
      c.Integer(v, at, "byteOffset", false, 0);
      c.Integer(v, at, "byteStride", false, 4, 252);
      if (v.contains("byteStride") && AsInteger(v["byteStride"]) % 4 != 0) {
        c.Fail(at + "/byteStride", "must be a multiple of 4, got " + v["byteStride"].dump());
      }
    }
  }
  if (const json* nodes = c.Array(root, "nodes")) {
    for (size_t i = 0; i < nodes->size(); ++i) {
      const json& n = (*nodes)[i];
      const std::string at = "/nodes/" + std::to_string(i);
      for (const char* key : {"mesh", "skin", "camera"}) c.Integer(n, at, key, false);
      // tinygltf keeps the numbers before a non-number (a "must have 3 elements" error
      // followed) and drops a value that is not an array (a "scale": 2 was no scale).
      c.Numbers(n, at, "matrix", 16);
      c.Numbers(n, at, "translation", 3);
      c.Numbers(n, at, "rotation", 4);
      c.Numbers(n, at, "scale", 3);
      c.Numbers(n, at, "weights", 0);
      if (auto children = n.find("children"); children != n.end()) {
        if (!children->is_array()) c.Fail(at + "/children", "must be an array of node indices, got " + children->dump());
        for (size_t k = 0; k < children->size(); ++k) {
          if (!IsInteger((*children)[k])) {
            c.Fail(at + "/children/" + std::to_string(k), "must be a node index (an integer), got " +
                                                              (*children)[k].dump());
          }
        }
      }
    }
  }
  if (const json* materials = c.Array(root, "materials")) {
    // tinygltf drops a factor of the wrong type and uses the default instead: a
    // "metallicFactor": "0" made a metal, a string in baseColorFactor made it white.
    for (size_t i = 0; i < materials->size(); ++i) {
      const json& m = (*materials)[i];
      const std::string at = "/materials/" + std::to_string(i);
      if (auto pbr = m.find("pbrMetallicRoughness"); pbr != m.end()) {
        const std::string pat = at + "/pbrMetallicRoughness";
        if (!pbr->is_object()) c.Fail(pat, "must be an object, got " + pbr->dump());
        c.Numbers(*pbr, pat, "baseColorFactor", 4);
        c.Number(*pbr, pat, "metallicFactor");
        c.Number(*pbr, pat, "roughnessFactor");
        c.TextureInfo(*pbr, pat, "baseColorTexture");
        c.TextureInfo(*pbr, pat, "metallicRoughnessTexture");
      }
      c.Numbers(m, at, "emissiveFactor", 3);
      c.Number(m, at, "alphaCutoff");
      c.Boolean(m, at, "doubleSided");
      if (auto mode = m.find("alphaMode"); mode != m.end() && !mode->is_string()) {
        c.Fail(at + "/alphaMode", "must be \"OPAQUE\", \"MASK\" or \"BLEND\", got " + mode->dump());
      }
      for (const char* key : {"normalTexture", "occlusionTexture", "emissiveTexture"}) c.TextureInfo(m, at, key);
    }
  }
  // Every texture's references, used or not (gltf_used.h: an unused one is not read).
  if (const json* textures = c.Array(root, "textures")) {
    for (size_t i = 0; i < textures->size(); ++i) {
      const std::string at = "/textures/" + std::to_string(i);
      c.Integer((*textures)[i], at, "sampler", false);
      c.Integer((*textures)[i], at, "source", false);
      c.Reference((*textures)[i], at, "sampler", "sampler", "samplers", count("samplers"));
      c.Reference((*textures)[i], at, "source", "image", "images", count("images"));
    }
  }
  if (const json* meshes = c.Array(root, "meshes")) {
    for (size_t i = 0; i < meshes->size(); ++i) {
      const std::string at = "/meshes/" + std::to_string(i);
      c.Numbers((*meshes)[i], at, "weights", 0);
      auto prims = (*meshes)[i].find("primitives");
      if (prims == (*meshes)[i].end()) c.Fail(at, "missing required property \"primitives\"");
      if (!prims->is_array()) c.Fail(at + "/primitives", "must be an array");
      for (size_t k = 0; k < prims->size(); ++k) {
        const json& p = (*prims)[k];
        const std::string pat = at + "/primitives/" + std::to_string(k);
        if (!p.is_object()) c.Fail(pat, "must be an object");
        auto attributes = p.find("attributes");
        if (attributes == p.end()) c.Fail(pat, "missing required property \"attributes\"");
        if (!attributes->is_object()) c.Fail(pat + "/attributes", "must be an object");
        for (const auto& [name, index] : attributes->items()) {
          if (!IsInteger(index)) {
            c.Fail(pat + "/attributes/" + name, "must be an accessor index (an integer), got " + index.dump());
          }
        }
        for (const char* key : {"indices", "material", "mode"}) c.Integer(p, pat, key, false);
      }
    }
  }
}

bool DropHarmlessByteStrides(json* root, const std::string& file, std::vector<std::string>* warnings) {
  auto views = root->find("bufferViews");
  if (!root->is_object() || views == root->end() || !views->is_array()) return false;
  auto stride_of = [&](size_t v) -> std::optional<int64_t> {
    const json& view = (*views)[v];
    if (!view.is_object()) return std::nullopt;
    auto it = view.find("byteStride");
    if (it == view.end() || !IsInteger(*it)) return std::nullopt;
    return AsInteger(*it);
  };
  auto valid = [](int64_t s) { return s >= 4 && s <= 252 && s % 4 == 0; };
  bool any = false;
  for (size_t v = 0; v < views->size(); ++v) {
    if (auto s = stride_of(v); s && !valid(*s)) any = true;
  }
  if (!any) return false;
  // The element size of each index accessor (mesh primitives' "indices").
  std::map<int64_t, int64_t> index_size;
  const json* accessors = root->contains("accessors") && (*root)["accessors"].is_array() ? &(*root)["accessors"] : nullptr;
  if (auto meshes = root->find("meshes"); meshes != root->end() && meshes->is_array() && accessors) {
    for (const json& mesh : *meshes) {
      if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
      for (const json& p : mesh["primitives"]) {
        if (!p.is_object() || !p.contains("indices") || !IsInteger(p["indices"])) continue;
        const int64_t a = AsInteger(p["indices"]);
        if (a < 0 || size_t(a) >= accessors->size() || !(*accessors)[size_t(a)].is_object()) continue;
        const json& acc = (*accessors)[size_t(a)];
        const int64_t type = acc.contains("componentType") && IsInteger(acc["componentType"]) ? AsInteger(acc["componentType"]) : 0;
        index_size[a] = type == 5121 ? 1 : type == 5123 ? 2 : type == 5125 ? 4 : -1;
      }
    }
  }
  // Per view: the index sizes read from it, or -1 once anything else reads it.
  std::map<size_t, int64_t> read_as;
  auto use = [&](const json& ref, int64_t size) {
    if (!IsInteger(ref) || AsInteger(ref) < 0) return;
    auto [it, added] = read_as.emplace(size_t(AsInteger(ref)), size);
    if (!added && it->second != size) it->second = -1;
  };
  if (accessors) {
    for (size_t a = 0; a < accessors->size(); ++a) {
      const json& acc = (*accessors)[a];
      if (!acc.is_object()) continue;
      auto idx = index_size.find(int64_t(a));
      if (acc.contains("bufferView")) use(acc["bufferView"], idx != index_size.end() ? idx->second : -1);
      if (acc.contains("sparse") && acc["sparse"].is_object()) {
        for (const char* part : {"indices", "values"}) {
          const json& sp = acc["sparse"];
          if (sp.contains(part) && sp[part].is_object() && sp[part].contains("bufferView")) use(sp[part]["bufferView"], -1);
        }
      }
    }
  }
  if (auto images = root->find("images"); images != root->end() && images->is_array()) {
    for (const json& im : *images) {
      if (im.is_object() && im.contains("bufferView")) use(im["bufferView"], -1);
    }
  }
  std::vector<std::string> zero, on_indices;
  for (size_t v = 0; v < views->size(); ++v) {
    const std::optional<int64_t> s = stride_of(v);
    if (!s || valid(*s)) continue;
    auto read = read_as.find(v);
    const std::string pointer = "/bufferViews/" + std::to_string(v) + "/byteStride";
    if (*s == 0) {
      zero.push_back(pointer);
    } else if (read != read_as.end() && read->second == *s) {
      on_indices.push_back(pointer + " (" + std::to_string(*s) + ")");
    } else {
      continue;
    }
    (*views)[v].erase("byteStride");
  }
  if (!zero.empty()) {
    warnings->push_back(file + ": byteStride 0 read as tightly packed (glTF asks for 4 to 252 or none) in " +
                        std::to_string(zero.size()) + (zero.size() == 1 ? " buffer view: " : " buffer views: ") +
                        ListFirst(zero, 3));
  }
  if (!on_indices.empty()) {
    warnings->push_back(file + ": byteStride of views read only as indices ignored (glTF gives it to vertex "
                        "attributes only; it equals the index size) in " + std::to_string(on_indices.size()) +
                        (on_indices.size() == 1 ? " buffer view: " : " buffer views: ") + ListFirst(on_indices, 3));
  }
  return !zero.empty() || !on_indices.empty();
}

namespace {

// The image data: URI prefixes (through ";base64,") tinygltf reads.
bool TinygltfReadsImageUri(const std::string& uri) {
  for (const char* h : {"data:application/octet-stream;base64,", "data:image/jpeg;base64,", "data:image/png;base64,",
                        "data:image/bmp;base64,", "data:image/gif;base64,"}) {
    if (uri.rfind(h, 0) == 0) return true;
  }
  return false;
}

// An image uri that is a base64 data: URI tinygltf would take for a file name.
bool OddImageDataUri(const json& image) {
  if (!image.is_object() || !image.contains("uri") || !image["uri"].is_string()) return false;
  const std::string& uri = image["uri"].get_ref<const std::string&>();
  if (uri.rfind("data:", 0) != 0 || TinygltfReadsImageUri(uri)) return false;
  const size_t comma = uri.find(',');
  return comma != std::string::npos && comma >= 7 && uri.compare(comma - 7, 7, ";base64") == 0;
}

}  // namespace

bool RelabelImageDataUris(json* root) {
  auto images = root->is_object() ? root->find("images") : root->end();
  if (images == root->end() || !images->is_array()) return false;
  bool any = false;
  for (json& image : *images) {
    if (!OddImageDataUri(image)) continue;
    std::string& uri = image["uri"].get_ref<std::string&>();
    uri = "data:application/octet-stream;base64," + uri.substr(uri.find(',') + 1);
    any = true;
  }
  return any;
}

bool NeedsGltfFixUp(const json& root) {
  if (!root.is_object()) return false;
  if (auto views = root.find("bufferViews"); views != root.end() && views->is_array()) {
    for (const json& v : *views) {
      auto s = v.is_object() ? v.find("byteStride") : v.end();
      if (s != v.end() && IsInteger(*s) && (AsInteger(*s) < 4 || AsInteger(*s) % 4 != 0)) return true;
    }
  }
  if (auto images = root.find("images"); images != root.end() && images->is_array()) {
    for (const json& image : *images) {
      if (OddImageDataUri(image)) return true;
    }
  }
  return DataUrisNeedNormalizing(root);
}

bool FixUpGltfJson(json* root, const std::string& file, std::vector<std::string>* warnings) {
  const bool strides = DropHarmlessByteStrides(root, file, warnings);
  const bool data = NormalizeDataUris(root);  // first: the relabelling reads lower-case headers
  const bool images = RelabelImageDataUris(root);
  return strides || images || data;
}

}  // namespace lt
