#include "scene/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <tuple>
#include <sstream>

#include "core/error.h"
#include "core/json_reader.h"
#include "core/text_fields.h"
#include "scene/gltf_container.h"
#include "scene/gltf_json_check.h"
#include "scene/gltf_materials.h"
#include "scene/gltf_accessors.h"
#include "scene/gltf_mesh.h"
#include "scene/gltf_nodes.h"

namespace lt {

namespace {

// Warnings of one kind over a file's meshes: up to kListed, one line each, as
// `one` words them; past that, one line, `many` (the count and what happened)
// naming the first kListed places. A CAD assembly or a viewer's export with an
// edge outline per part would otherwise print one line per part.
constexpr size_t kListed = 3;
void AddListed(const std::string& file, const std::vector<std::string>& places,
               const std::function<std::string(const std::string&)>& one, const std::string& many,
               std::vector<std::string>* warnings) {
  if (places.size() <= kListed) {
    for (const std::string& place : places) warnings->push_back(file + ": " + one(place));
    return;
  }
  warnings->push_back(file + ": " + many + ": " + ListFirst(places, kListed));
}

// ---------------------------------------------------------------- file access for tinygltf

// tinygltf looks for external files in the base folder and then in ".". Only
// absolute paths (the base folder is made absolute) are accepted, so nothing is
// ever picked up from the working directory by accident.
// An image file nothing reads "exists" (GltfExternalFiles::unread_images), so that
// tinygltf, which loads every image, asks for it and gets a placeholder.
bool FileExistsCallback(const std::string& path, void* user) {
  std::error_code ec;
  return std::filesystem::path(path).is_absolute() &&
         (std::filesystem::is_regular_file(path, ec) ||
          static_cast<const GltfExternalFiles*>(user)->unread_images.count(path) != 0);
}

// Maps the path tinygltf asks for to the file the uri names, as CheckGltfJson
// resolved it (ResolveGltfUri: file: URIs, backslashes, letter case; and '+',
// which tinygltf alone would read as a space). `user` is CheckGltfJson's
// GltfExternalFiles.
std::string ExpandFilePathCallback(const std::string& path, void* user) {
  const auto& files = static_cast<const GltfExternalFiles*>(user)->by_lookup_path;
  auto it = files.find(path);
  return it != files.end() ? it->second.string() : path;
}

// An external buffer file may be longer than its byteLength (glTF 2.0 only asks
// that it is not shorter), but tinygltf wants the exact size: such a file is cut
// to byteLength as it is read.
bool ReadWholeFileCallback(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  if (static_cast<const GltfExternalFiles*>(user)->unread_images.count(path) != 0) {
    *out = {0};  // an image nothing reads: a placeholder, never decoded (LoadImageCallback)
    return true;
  }
  try {
    *out = ReadFileBytes(path, path);
    const auto& lengths = static_cast<const GltfExternalFiles*>(user)->buffer_lengths;
    auto it = lengths.find(std::filesystem::path(path).lexically_normal());
    if (it != lengths.end() && out->size() > it->second) out->resize(size_t(it->second));
    return true;
  } catch (const InputError& e) {
    if (err) *err += e.what();
    return false;
  }
}

bool WriteWholeFileCallback(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "writing is not supported";
  return false;
}

// Decodes images through tinygltf's stb-based loader, after checking that an
// image stored in a buffer view lies inside its buffer (tinygltf does not). An
// image that cannot be decoded (WebP, KTX2, DDS, ... or corrupt bytes) is left
// empty and its reason kept: it is an error only if a texture uses it (an unused
// image, or an extension's alternative source with a PNG fallback, is fine).
// Images that no used material reads (GltfUse::images) are not decoded.
struct ImageLoadContext {
  const tinygltf::Model* model = nullptr;
  std::vector<std::string> errors;  // by image index
  const std::vector<bool>* read = nullptr;  // by image index
};

// A name for the format of undecodable image bytes: their signature, else the mimeType.
std::string ImageFormatName(const unsigned char* bytes, int size, const std::string& mime_type) {
  auto starts = [&](const char* magic, size_t n, size_t at = 0) {
    return bytes != nullptr && size_t(size) >= at + n && std::memcmp(bytes + at, magic, n) == 0;
  };
  if (starts("RIFF", 4) && starts("WEBP", 4, 8)) return "WebP";
  if (starts("\xABKTX 20\xBB", 8)) return "KTX2";
  if (starts("\xABKTX 11\xBB", 8)) return "KTX";
  if (starts("DDS ", 4)) return "DDS";
  if (starts("\x89PNG", 4)) return "a corrupt PNG";
  if (starts("\xFF\xD8", 2)) return "a corrupt or unsupported (progressive 12-bit, arithmetic) JPEG";
  if (!mime_type.empty()) return "\"" + mime_type + "\" of unknown signature";
  return "an unknown format";
}

bool LoadImageCallback(tinygltf::Image* image, const int index, std::string* err, std::string* warn, int, int,
                       const unsigned char* bytes, int size, void* user) {
  auto* ctx = static_cast<ImageLoadContext*>(user);
  if (image->bufferView >= 0) {
    const auto& m = *ctx->model;
    if (size_t(image->bufferView) >= m.bufferViews.size()) return false;
    const tinygltf::BufferView& bv = m.bufferViews[size_t(image->bufferView)];
    if (bv.buffer < 0 || size_t(bv.buffer) >= m.buffers.size()) return false;
    const size_t buffer_size = m.buffers[size_t(bv.buffer)].data.size();
    if (bv.byteOffset > buffer_size || bv.byteLength > buffer_size - bv.byteOffset ||
        bv.byteLength > size_t(INT32_MAX)) {
      if (err) {
        *err += "image[" + std::to_string(index) + "] bufferView " + std::to_string(image->bufferView) +
                " lies outside buffer " + std::to_string(bv.buffer) + " (" + std::to_string(buffer_size) + " bytes)";
      }
      return false;
    }
  }
  if (index < 0) return false;
  if (size_t(index) >= ctx->read->size() || !(*ctx->read)[size_t(index)]) return true;  // left empty
  if (ctx->errors.size() <= size_t(index)) ctx->errors.resize(size_t(index) + 1);
  std::string& failure = ctx->errors[size_t(index)];
  if (bytes == nullptr || size <= 0) {
    failure = "the image is empty (0 bytes)";
    return true;
  }
  std::string decode_err;
  if (!tinygltf::LoadImageData(image, index, &decode_err, warn, 0, 0, bytes, size, nullptr)) {
    failure = "cannot decode the image: " + ImageFormatName(bytes, size, image->mimeType) +
              " (PNG, JPEG, BMP, TGA, GIF, PSD, HDR and PNM images are read)";
    image->image.clear();
    image->width = image->height = 0;
  }
  return true;
}

std::string Trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\r')) s.pop_back();
  for (auto& c : s) {
    if (c == '\n') c = ';';
  }
  return s;
}

}  // namespace

GltfAsset LoadGltf(const std::filesystem::path& path, const std::string& display_name,
                   const GltfLoadOptions& options) {
  const std::string file = display_name.empty() ? path.string() : display_name;
  std::error_code ec;
  std::filesystem::path abs = std::filesystem::absolute(path, ec).lexically_normal();
  if (ec) abs = path;
  std::vector<unsigned char> bytes = ReadFileBytes(abs, file);
  GltfContainer container = ParseGltfContainer(bytes, file);
  const std::filesystem::path base = abs.parent_path();
  GltfExternalFiles external;
  std::string rewritten;
  std::vector<std::string> json_warnings;
  CheckGltfJson(container, file, base, &external, &rewritten, &json_warnings, options.materials);
  if (!rewritten.empty()) ReplaceGltfJson(&container, bytes, std::move(rewritten));

  GltfAsset asset;
  asset.path = path;
  asset.warnings = std::move(json_warnings);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  tinygltf::FsCallbacks fs{&FileExistsCallback, &ExpandFilePathCallback, &ReadWholeFileCallback,
                           &WriteWholeFileCallback, &external};
  loader.SetFsCallbacks(fs);
  ImageLoadContext image_ctx{&model, {}, &external.use.images};
  loader.SetImageLoader(&LoadImageCallback, &image_ctx);
  std::string err, warn;
  bool ok;
  if (container.binary) {
    const std::vector<unsigned char>& glb = container.aligned.empty() ? bytes : container.aligned;
    ok = loader.LoadBinaryFromMemory(&model, &err, &warn, glb.data(), unsigned(container.total_length),
                                     base.string());
  } else {
    ok = loader.LoadASCIIFromString(&model, &err, &warn, container.json_text.data(),
                                    unsigned(container.json_text.size()), base.string());
  }
  if (!ok) throw InputError(file, "invalid glTF: " + Trim(ShortenDataUris(err.empty() ? "parse failed" : err)));
  if (!container.warning.empty()) asset.warnings.push_back(file + ": " + container.warning);
  if (!warn.empty()) asset.warnings.push_back(file + ": " + Trim(ShortenDataUris(warn)));
  bytes = {};
  container = {};

  image_ctx.errors.resize(model.images.size());
  const GltfSource src{model, file, &image_ctx.errors};
  std::vector<bool> metallic_by_default;
  // Without materials the JSON held none (CheckGltfJson): every primitive takes the default.
  if (options.materials) {
    asset.materials = ConvertGltfMaterials(src, &asset.warnings, &metallic_by_default, &external.use.materials);
  }
  std::vector<GltfNodeUse> uses = WalkGltfScene(src, &asset.warnings);

  const uint32_t default_material = uint32_t(asset.materials.size());
  bool uses_default = false;
  // (glTF mesh, skin or -1, morph weights) -> index in asset.meshes, -1 when
  // empty. A skinned mesh is posed by its skin alone and a morphed one by its
  // weights, so each such triple is loaded once.
  using MeshKey = std::tuple<int, int, std::vector<double>>;
  std::map<MeshKey, long> mesh_slot;
  std::map<int, GltfSkinPose> skin_poses;
  std::vector<std::pair<std::string, std::vector<std::string>>> skipped;  // mode -> "mesh "m" primitive i"
  std::vector<std::string> empty_meshes;
  for (const GltfNodeUse& use : uses) {
    const MeshKey key{use.gltf_mesh, use.skin, use.morph.weights};
    auto it = mesh_slot.find(key);
    if (it == mesh_slot.end()) {
      GltfMeshStats stats;
      const GltfSkinPose* skin = nullptr;
      if (use.skin >= 0) {
        auto pose = skin_poses.find(use.skin);
        if (pose == skin_poses.end()) pose = skin_poses.emplace(use.skin, GltfSkinPoseOf(src, use.skin)).first;
        skin = &pose->second;
      }
      Mesh mesh = ConvertGltfMesh(src, use.gltf_mesh, asset.materials, default_material, &stats, &asset.warnings,
                                  skin, &use.morph);
      asset.degenerate_triangles += stats.degenerate_triangles;
      for (const auto& [mode, pi] : stats.skipped_primitives) {
        // Captured by name: C++17 lambdas may not capture a structured binding (Clang rejects it).
        auto kind = std::find_if(skipped.begin(), skipped.end(), [&m = mode](const auto& k) { return k.first == m; });
        if (kind == skipped.end()) kind = skipped.insert(skipped.end(), {mode, {}});
        kind->second.push_back("mesh \"" + mesh.name + "\" primitive " + std::to_string(pi));
      }
      long slot = -1;
      if (mesh.TriangleCount() > 0) {
        uses_default |= stats.uses_default_material;
        asset.texcoords_not_set_0 |= stats.texcoords_not_set_0;
        mesh.Validate();
        slot = long(asset.meshes.size());
        asset.meshes.push_back(std::move(mesh));
      } else {
        empty_meshes.push_back("\"" + mesh.name + "\"");
      }
      it = mesh_slot.emplace(key, slot).first;
    }
    if (it->second >= 0) asset.instances.push_back({size_t(it->second), use.transform, use.node_name});
  }
  for (const auto& [mode, places] : skipped) {
    const std::string what = mode + " skipped (only triangles are rendered)";
    AddListed(file, places, [&](const std::string& place) { return place + ": " + what; },
              what + " in " + std::to_string(places.size()) + " primitives", &asset.warnings);
  }
  AddListed(file, empty_meshes, [](const std::string& name) { return "mesh " + name + " has no triangles; it is skipped"; },
            std::to_string(empty_meshes.size()) + " meshes have no triangles; they are skipped", &asset.warnings);
  std::vector<bool> used(asset.materials.size(), false);
  for (const Mesh& mesh : asset.meshes) {
    for (uint32_t id : mesh.triangle_material) {
      if (id < used.size()) used[id] = true;
    }
  }
  std::vector<std::string> metals;
  for (size_t i = 0; i < used.size(); ++i) {
    if (used[i] && metallic_by_default[i]) metals.push_back("\"" + asset.materials[i].name + "\"");
  }
  if (!metals.empty()) asset.metallic_by_default = (metals.size() == 1 ? "material " : "materials ") + ListFirst(metals, kListed);
  if (uses_default || !options.materials) asset.materials.push_back(DefaultMaterial());
  asset.uses_default_material = uses_default && options.materials;
  if (!model.cameras.empty() || !model.lights.empty()) {
    auto count = [](size_t n, const char* one, const char* many) {
      return std::to_string(n) + " " + (n == 1 ? one : many);
    };
    std::string what = !model.cameras.empty() ? count(model.cameras.size(), "camera", "cameras") : "";
    if (!model.lights.empty()) {
      what += (what.empty() ? "" : " and ") + count(model.lights.size(), "KHR_lights_punctual light", "KHR_lights_punctual lights");
    }
    asset.warnings.push_back(file + ": " + what + " ignored (the scene file sets the sensor and the lights)");
  }
  if (auto it = model.extensions.find("KHR_materials_variants"); it != model.extensions.end()) {
    const tinygltf::Value& variants = it->second.Get("variants");
    const size_t n = variants.IsArray() ? variants.ArrayLen() : 0;
    asset.warnings.push_back(file + ": KHR_materials_variants: " + std::to_string(n) +
                             (n == 1 ? " variant" : " variants") +
                             " not applied; each primitive has its default material (its \"material\")");
  }
  // CESIUM_RTC (3D Tiles' b3dm content): positions are relative to a centre that 3D
  // Tiles add after turning the file's y up to z up, in the tileset's frame (ECEF
  // metres): it is not a translation in the file's own frame, so it is not applied.
  if (auto it = model.extensions.find("CESIUM_RTC"); it != model.extensions.end()) {
    const tinygltf::Value& c = it->second.Get("center");
    bool valid = c.IsArray() && c.ArrayLen() == 3;
    std::string centre;
    for (int i = 0; valid && i < 3; ++i) {
      valid = c.Get(i).IsNumber() && std::isfinite(c.Get(i).GetNumberAsDouble());
      if (valid) centre += (i ? ", " : "") + FormatNumber(c.Get(i).GetNumberAsDouble());
    }
    if (!valid) {
      throw InputError(file + ": /extensions/CESIUM_RTC/center", "must be an array of 3 finite numbers");
    }
    asset.warnings.push_back(file + ": CESIUM_RTC: the centre [" + centre +
                             "] m is not applied (3D Tiles add it in the tileset's z-up frame): the model is "
                             "placed relative to it; place it with the object's world_from_object");
  }
  if (!model.animations.empty()) {
    asset.warnings.push_back(file + ": " + std::to_string(model.animations.size()) +
                             (model.animations.size() == 1 ? " animation" : " animations") +
                             " not played: the nodes' transforms and morph weights are used as written");
  }
  if (asset.degenerate_triangles > 0) {
    asset.warnings.push_back(file + ": " + std::to_string(asset.degenerate_triangles) +
                             " degenerate triangles dropped");
  }
  if (asset.instances.empty()) asset.warnings.push_back(file + ": the scene holds no triangles");
  return asset;
}

}  // namespace lt
