// ConvertGltfMaterials (gltf_materials.h): glTF materials and their extensions as
// lt::Materials, with warnings for what is not rendered. The textures' images (decoding,
// wrap modes, mean texels) are in gltf_textures.cpp.
#include "scene/gltf_materials.h"

#include <tiny_gltf.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <optional>

#include "core/error.h"
#include "core/text_fields.h"
#include "scene/gltf_textures.h"

namespace lt {

using namespace gltf_material_detail;

namespace {

// A factor glTF gives the range [0, 1]. A finite one outside it, as exporters write
// them (Babylon.js's 3ds Max exporter: a roughnessFactor of -90.47056; doubles of
// floats such as 1.0000000298), is clamped to it (as viewers' shaders clamp roughness
// and metallic; a base colour above 1 would reflect more light than reaches the
// surface, and glTF writes an emission above 1 with KHR_materials_emissive_strength),
// and its place and value are added to `clamped` unless within float noise of the range.
double UnitFactor(double v, const std::string& where, std::vector<std::string>* clamped) {
  if (!std::isfinite(v)) throw InputError(where, "must be in [0, 1], got " + FormatNumber(v));
  if (v >= 0.0 && v <= 1.0) return v;
  if (v < -1e-6 || v > 1.0 + 1e-6) {
    const size_t at = where.find(": /");
    clamped->push_back((at == std::string::npos ? where : where.substr(at + 2)) + " " + FormatNumber(v));
  }
  return std::clamp(v, 0.0, 1.0);
}

// A number of a tinygltf extension object, `fallback` when absent.
double ExtNumber(const tinygltf::Value& ext, const char* key, double fallback, const std::string& where) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  const double x = v.IsNumber() ? v.GetNumberAsDouble() : std::nan("");
  if (!std::isfinite(x)) throw InputError(where + "/" + key, "must be a finite number");
  return x;
}

// A [x, y] array of a tinygltf extension object, `fallback` when absent.
Eigen::Vector2d ExtVec2(const tinygltf::Value& ext, const char* key, const Eigen::Vector2d& fallback,
                        const std::string& where) {
  if (!ext.Has(key)) return fallback;
  const tinygltf::Value& v = ext.Get(key);
  if (!v.IsArray() || v.ArrayLen() != 2) throw InputError(where + "/" + key, "must be an array of 2 numbers");
  Eigen::Vector2d out;
  for (int i = 0; i < 2; ++i) {
    const tinygltf::Value& x = v.Get(i);
    out[i] = x.IsNumber() ? x.GetNumberAsDouble() : std::nan("");
    if (!std::isfinite(out[i])) throw InputError(where + "/" + key + "/" + std::to_string(i), "must be a finite number");
  }
  return out;
}

// Reads KHR_texture_transform of a textureInfo into mat->base_color_uv_transform;
// returns the TEXCOORD set the texture reads (the extension's texCoord overrides).
int ReadTextureTransform(const tinygltf::TextureInfo& info, const std::string& where, Material* mat) {
  auto it = info.extensions.find("KHR_texture_transform");
  if (it == info.extensions.end()) return info.texCoord;
  const std::string ext_where = where + "/extensions/KHR_texture_transform";
  const tinygltf::Value& ext = it->second;
  if (!ext.IsObject()) throw InputError(ext_where, "must be an object");
  mat->base_color_uv_transform = UvTransform::FromOffsetRotationScale(
      ExtVec2(ext, "offset", Eigen::Vector2d::Zero(), ext_where), ExtNumber(ext, "rotation", 0.0, ext_where),
      ExtVec2(ext, "scale", Eigen::Vector2d::Ones(), ext_where));
  if (!ext.Has("texCoord")) return info.texCoord;
  const tinygltf::Value& tc = ext.Get("texCoord");
  if (!tc.IsInt() || tc.GetNumberAsInt() < 0) throw InputError(ext_where + "/texCoord", "must be an integer >= 0");
  return tc.GetNumberAsInt();
}

// alphaMode and alphaCutoff (glTF 3.9.4): MASK cuts holes where alpha < alphaCutoff,
// BLEND reads alpha as coverage (EmbreeScene applies both).
void ReadAlphaMode(const tinygltf::Material& gm, const std::string& where, Material* mat) {
  if (gm.alphaMode == "OPAQUE") {
    mat->alpha_mode = AlphaMode::kOpaque;
  } else if (gm.alphaMode == "MASK") {
    mat->alpha_mode = AlphaMode::kMask;
  } else if (gm.alphaMode == "BLEND") {
    mat->alpha_mode = AlphaMode::kBlend;
  } else {
    throw InputError(where + "/alphaMode", "must be \"OPAQUE\", \"MASK\" or \"BLEND\", got \"" + gm.alphaMode + "\"");
  }
  if (!std::isfinite(gm.alphaCutoff) || gm.alphaCutoff < 0) {
    throw InputError(where + "/alphaCutoff", "must be a number >= 0, got " + FormatNumber(gm.alphaCutoff));
  }
  mat->alpha_cutoff = float(gm.alphaCutoff);
}

// A number for a warning: 3 significant digits.
std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// Appends a material's name, quoted, to a list of them ("a", "b").
void AddName(std::string* names, const std::string& name) { *names += (names->empty() ? "\"" : ", \"") + name + "\""; }

// "material \"a\"" or "materials \"a\", \"b\"", for a warning naming the materials in `names` (AddName).
std::string MaterialsNamed(const std::string& names) {
  return std::string("material") + (names.find(',') != std::string::npos ? "s " : " ") + names;
}

// Material extensions whose effect is not rendered: one warning each, naming the materials.
constexpr const char* kIgnoredMaterialExtensions[] = {
    "KHR_materials_volume",       "KHR_materials_ior",    "KHR_materials_specular",
    "KHR_materials_clearcoat",    "KHR_materials_sheen",  "KHR_materials_iridescence",
    "KHR_materials_anisotropy",   "KHR_materials_dispersion", "KHR_materials_diffuse_transmission"};

}  // namespace

std::vector<Material> ConvertGltfMaterials(const GltfSource& src, std::vector<std::string>* warnings,
                                           std::vector<bool>* metallic_by_default, const std::vector<bool>* used) {
  const auto& m = src.model;
  std::vector<std::shared_ptr<const Texture>> textures(m.textures.size());
  std::vector<Material> out;
  out.reserve(m.materials.size());
  std::map<std::string, std::string> ignored_extensions;  // name -> the materials using it
  std::string transmissive[2];
  std::string unlit_names;  // the materials with KHR_materials_unlit
  std::vector<std::string> clamped_used;  // factors outside [0, 1]: their pointers and values
  // Mean texel of (texture, sRGB-encoded), or why there is none (MeanTexel).
  std::map<std::pair<int, bool>, std::pair<std::optional<Eigen::Vector4d>, std::string>> texture_means;  // the materials with KHR_materials_transmission, [with a transmissionTexture]
  // Makes texture info.index (in range) mat's base colour texture, each texture
  // decoded once, with info's KHR_texture_transform and the TEXCOORD set it reads
  // (the meshes load that set for the primitives using the material).
  auto use_texture = [&](const tinygltf::TextureInfo& info, const std::string& info_where, Material* mat) {
    if (!textures[size_t(info.index)]) textures[size_t(info.index)] = MakeTexture(src, info.index);
    mat->base_color_texture = textures[size_t(info.index)];
    if (info.texCoord < 0) throw InputError(info_where + "/texCoord", "must be an integer >= 0");
    mat->base_color_texcoord = ReadTextureTransform(info, info_where, mat);
  };
  for (size_t i = 0; i < m.materials.size(); ++i) {
    const tinygltf::Material& gm = m.materials[i];
    const std::string where = GltfWhere(src, "materials", int(i));
    const bool in_use = used == nullptr || (i < used->size() && (*used)[i]);
    std::vector<std::string> unused_clamped;  // an unused material's: not warned about
    std::vector<std::string>& clamped = in_use ? clamped_used : unused_clamped;
    Material mat;
    mat.name = gm.name.empty() ? "material " + std::to_string(i) : gm.name;
    const auto& pbr = gm.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4) {
      throw InputError(where + "/pbrMetallicRoughness/baseColorFactor", "must have 4 elements");
    }
    for (int c = 0; c < 3; ++c) {
      mat.base_color[c] = float(UnitFactor(pbr.baseColorFactor[size_t(c)],
                                           where + "/pbrMetallicRoughness/baseColorFactor/" + std::to_string(c), &clamped));
    }
    mat.alpha = float(UnitFactor(pbr.baseColorFactor[3], where + "/pbrMetallicRoughness/baseColorFactor/3", &clamped));
    ReadAlphaMode(gm, where, &mat);
    mat.metallic = float(UnitFactor(pbr.metallicFactor, where + "/pbrMetallicRoughness/metallicFactor", &clamped));
    mat.roughness = float(UnitFactor(pbr.roughnessFactor, where + "/pbrMetallicRoughness/roughnessFactor", &clamped));
    if (gm.emissiveFactor.size() != 3) throw InputError(where + "/emissiveFactor", "must have 3 elements");
    double strength = 1.0;
    if (auto it = gm.extensions.find("KHR_materials_emissive_strength"); it != gm.extensions.end()) {
      const tinygltf::Value& ext = it->second;
      if (ext.IsObject() && ext.Has("emissiveStrength")) {
        const tinygltf::Value& s = ext.Get("emissiveStrength");
        strength = s.IsNumber() || s.IsInt() ? s.GetNumberAsDouble() : -1.0;
        if (!std::isfinite(strength) || strength < 0) {
          throw InputError(where + "/extensions/KHR_materials_emissive_strength/emissiveStrength",
                           "must be a number >= 0");
        }
      }
    }
    for (int c = 0; c < 3; ++c) {
      mat.emissive[c] = float(strength * UnitFactor(gm.emissiveFactor[size_t(c)], where + "/emissiveFactor/" + std::to_string(c), &clamped));
    }
    mat.double_sided = gm.doubleSided;
    if (!in_use) {  // no triangle uses it: nothing more is read (its texture indices are checked by the schema)
      if (metallic_by_default) metallic_by_default->push_back(false);
      out.push_back(std::move(mat));
      continue;
    }

    const int tex = pbr.baseColorTexture.index;
    if (tex >= 0) {
      if (size_t(tex) >= m.textures.size()) {
        throw InputError(where + "/pbrMetallicRoughness/baseColorTexture/index",
                         "texture " + std::to_string(tex) + " does not exist (" + std::to_string(m.textures.size()) +
                             " textures)");
      }
      use_texture(pbr.baseColorTexture, where + "/pbrMetallicRoughness/baseColorTexture", &mat);
    } else if (tex < -1) {
      throw InputError(where + "/pbrMetallicRoughness/baseColorTexture/index", "must be >= 0");
    }

    // KHR_materials_pbrSpecularGlossiness (older exporters, Sketchfab): the diffuse
    // colour and texture become the base colour, roughness = 1 - glossiness, metallic 0.
    if (auto it = gm.extensions.find("KHR_materials_pbrSpecularGlossiness"); it != gm.extensions.end()) {
      const std::string sg_where = where + "/extensions/KHR_materials_pbrSpecularGlossiness";
      const tinygltf::Value& sg = it->second;
      if (!sg.IsObject()) throw InputError(sg_where, "must be an object");
      mat.base_color = Eigen::Vector3f::Ones();
      if (sg.Has("diffuseFactor")) {
        const tinygltf::Value& d = sg.Get("diffuseFactor");
        if (!d.IsArray() || d.ArrayLen() != 4) throw InputError(sg_where + "/diffuseFactor", "must have 4 elements");
        for (int c = 0; c < 4; ++c) {
          const tinygltf::Value& x = d.Get(c);
          const std::string c_where = sg_where + "/diffuseFactor/" + std::to_string(c);
          if (!x.IsNumber()) throw InputError(c_where, "must be a number");
          const double v = UnitFactor(x.GetNumberAsDouble(), c_where, &clamped);
          (c < 3 ? mat.base_color[c] : mat.alpha) = float(v);  // alpha: the extension's coverage
        }
      } else {
        mat.alpha = 1;
      }
      mat.metallic = 0;
      mat.roughness = float(1.0 - UnitFactor(ExtNumber(sg, "glossinessFactor", 1.0, sg_where), sg_where + "/glossinessFactor", &clamped));
      mat.base_color_texture = nullptr;
      mat.base_color_uv_transform = UvTransform();
      mat.base_color_texcoord = 0;
      if (sg.Has("diffuseTexture")) {
        const std::string dt_where = sg_where + "/diffuseTexture";
        const tinygltf::Value& dt = sg.Get("diffuseTexture");
        const tinygltf::Value& index = dt.IsObject() ? dt.Get("index") : dt;
        if (!index.IsInt() || index.GetNumberAsInt() < 0 || size_t(index.GetNumberAsInt()) >= m.textures.size()) {
          throw InputError(dt_where + "/index", "must name one of the " + std::to_string(m.textures.size()) + " textures");
        }
        tinygltf::TextureInfo info;
        info.index = index.GetNumberAsInt();
        if (dt.Has("texCoord")) {
          const tinygltf::Value& tc = dt.Get("texCoord");
          if (!tc.IsInt() || tc.GetNumberAsInt() < 0) throw InputError(dt_where + "/texCoord", "must be an integer >= 0");
          info.texCoord = tc.GetNumberAsInt();
        }
        if (dt.Has("extensions") && dt.Get("extensions").IsObject()) {
          const tinygltf::Value& exts = dt.Get("extensions");
          for (const std::string& key : exts.Keys()) info.extensions[key] = exts.Get(key);
        }
        use_texture(info, dt_where, &mat);
      }
      warnings->push_back(src.file + ": material \"" + mat.name +
                          "\": KHR_materials_pbrSpecularGlossiness converted to metallic-roughness (diffuse as base "
                          "colour, roughness = 1 - glossiness, metallic 0); the specular colour is approximated by "
                          "a dielectric's");
    }
    // The metallic-roughness and emissive textures are not sampled, but they scale
    // their factors (glTF 3.9.2, 3.9.5): metallic = factor * B, roughness = factor * G,
    // emission = factor * texture. Exporters write factor 1 beside such a texture
    // (Blender, Sketchfab, the Khronos samples), so the factor alone made a painted
    // part a rough metal (no diffuse laser return) and a part with a few glowing
    // texels glow all over; the texture's mean is the constant closest to it.
    // KHR_materials_unlit (photogrammetry, Sketchfab, "shadeless" exports): colour =
    // base colour, and every other PBR property is only a fallback for viewers without
    // the extension. Unlit shading has no light to answer, and a scanner sees the light a
    // part reflects, so the part is a diffuse surface of its base colour (with its alpha
    // and vertex colours): UnlitTest's materials, with no metallicFactor, were metals.
    const bool unlit = gm.extensions.count("KHR_materials_unlit") != 0;
    std::string approximated;
    auto scale_by_mean = [&](const tinygltf::TextureInfo& info, const std::string& info_where, const char* what,
                             bool srgb, const std::function<std::string(const Eigen::Vector4d&)>& apply) {
      if (info.index < 0) return;
      // Each (texture, encoding) once: files share one large texture among many materials.
      auto cached = texture_means.find({info.index, srgb});
      if (cached == texture_means.end()) {
        std::string why;
        std::optional<Eigen::Vector4d> mean = MeanTexel(src, info, info_where, srgb, &why);
        cached = texture_means.emplace(std::pair{info.index, srgb}, std::pair{mean, why}).first;
      }
      const auto& [mean, why] = cached->second;
      approximated += std::string(approximated.empty() ? "" : "; ") + what +
                      (mean ? " texture not sampled, its mean used: " + apply(*mean)
                            : " texture ignored (" + why + "), the factor used alone");
    };
    if (const auto sg = gm.extensions.find("KHR_materials_pbrSpecularGlossiness"); sg != gm.extensions.end()) {
      // It replaced the metallic-roughness values; its texture's alpha scales the glossiness.
      if (sg->second.Has("specularGlossinessTexture")) {
        const std::string sgt_where = where + "/extensions/KHR_materials_pbrSpecularGlossiness/specularGlossinessTexture";
        const tinygltf::Value& sgt = sg->second.Get("specularGlossinessTexture");
        const tinygltf::Value& index = sgt.IsObject() ? sgt.Get("index") : sgt;
        if (!index.IsInt() || index.GetNumberAsInt() < 0) throw InputError(sgt_where + "/index", "must be an integer >= 0");
        tinygltf::TextureInfo info;
        info.index = index.GetNumberAsInt();
        scale_by_mean(info, sgt_where, "specular-glossiness", true, [&](const Eigen::Vector4d& mean) {
          const double glossiness = 1.0 - double(mat.roughness);
          mat.roughness = float(1.0 - glossiness * mean[3]);
          return "glossiness " + Short(glossiness) + " x " + Short(mean[3]);
        });
      }
    } else if (!unlit) {
      scale_by_mean(pbr.metallicRoughnessTexture, where + "/pbrMetallicRoughness/metallicRoughnessTexture",
                    "metallic-roughness", false, [&](const Eigen::Vector4d& mean) {
                      const std::string text = "metallic " + Short(mat.metallic) + " x " +
                                               Short(mean[2]) + ", roughness " + Short(mat.roughness) +
                                               " x " + Short(mean[1]);
                      mat.metallic = float(mat.metallic * mean[2]);
                      mat.roughness = float(mat.roughness * mean[1]);
                      return text;
                    });
    }
    if (metallic_by_default) {
      // tinygltf fills `values` with the pbrMetallicRoughness keys the file writes.
      metallic_by_default->push_back(!unlit && pbr.metallicRoughnessTexture.index < 0 &&
                                     gm.values.count("metallicFactor") == 0 &&
                                     gm.extensions.count("KHR_materials_pbrSpecularGlossiness") == 0);
    }
    if (unlit) {
      mat.metallic = 0;
      mat.roughness = 1;
      mat.emissive = Eigen::Vector3f::Zero();
      AddName(&unlit_names, mat.name);
    } else {
      scale_by_mean(gm.emissiveTexture, where + "/emissiveTexture", "emissive", true,
                    [&](const Eigen::Vector4d& mean) {
                      for (int c = 0; c < 3; ++c) mat.emissive[c] = float(mat.emissive[c] * mean[c]);
                      return "emissive factor times (" + Short(mean[0]) + ", " + Short(mean[1]) + ", " +
                             Short(mean[2]) + ")";
                    });
    }
    // KHR_materials_transmission: glTF's dielectric is mix(diffuse, transmission,
    // transmissionFactor) under the specular layer. Transmitted light is not traced,
    // but the diffuse share it takes is removed, so a clear part does not show a
    // bright diffuse laser stripe: the dielectric's base colour is scaled by
    // 1 - transmission (exact for metallic 0; a metal has no transmission).
    if (auto it = gm.extensions.find("KHR_materials_transmission"); it != gm.extensions.end()) {
      const std::string t_where = where + "/extensions/KHR_materials_transmission";
      if (!it->second.IsObject()) throw InputError(t_where, "must be an object");
      const double t = UnitFactor(ExtNumber(it->second, "transmissionFactor", 0.0, t_where), t_where + "/transmissionFactor", &clamped);
      mat.base_color *= float(1.0 - t * (1.0 - double(mat.metallic)));
      AddName(&transmissive[it->second.Has("transmissionTexture")], mat.name);
    }
    for (const char* name : kIgnoredMaterialExtensions) {
      if (gm.extensions.count(name) != 0) {
        AddName(&ignored_extensions[name], mat.name);
      }
    }

    std::string ignored;
    auto note = [&](bool present, const char* what) {
      if (present) ignored += (ignored.empty() ? "" : ", ") + std::string(what);
    };
    for (const auto& [index, key] : {std::pair{gm.normalTexture.index, "normalTexture"},
                                     std::pair{gm.occlusionTexture.index, "occlusionTexture"}}) {
      if (index >= 0 && size_t(index) >= m.textures.size()) {
        throw InputError(where + "/" + key + "/index", "texture " + std::to_string(index) + " does not exist (" +
                                                           std::to_string(m.textures.size()) + " textures)");
      }
    }
    note(gm.normalTexture.index >= 0, "normal texture");
    note(gm.occlusionTexture.index >= 0, "occlusion texture");
    if (!ignored.empty() || !approximated.empty()) {
      warnings->push_back(src.file + ": material \"" + mat.name + "\": " +
                          (ignored.empty() ? "" : "ignored " + ignored) +
                          (ignored.empty() || approximated.empty() ? "" : "; ") + approximated);
    }
    out.push_back(std::move(mat));
  }
  for (int with_texture = 0; with_texture < 2; ++with_texture) {
    const std::string& names = transmissive[with_texture];
    if (names.empty()) continue;
    warnings->push_back(src.file + ": KHR_materials_transmission: transmitted light is not traced; the diffuse "
                        "share it takes is removed (base colour times 1 - transmissionFactor" +
                        std::string(with_texture ? "; the transmission texture is ignored" : "") + "), " +
                        MaterialsNamed(names));
  }
  if (!unlit_names.empty()) {
    warnings->push_back(src.file + ": KHR_materials_unlit: read as a diffuse surface of the base colour (metallic 0, "
                        "roughness 1, no emission; the other properties are the extension's fallbacks), " +
                        MaterialsNamed(unlit_names));
  }
  if (!clamped_used.empty()) {
    warnings->push_back(src.file + ": " + std::to_string(clamped_used.size()) +
                        (clamped_used.size() == 1 ? " material factor is" : " material factors are") +
                        " outside glTF's range [0, 1] and clamped to it: " + ListFirst(clamped_used, 3));
  }
  for (const auto& [name, materials] : ignored_extensions) {
    warnings->push_back(src.file + ": " + name + " ignored (not rendered), used by " + MaterialsNamed(materials));
  }
  return out;
}

}  // namespace lt
