// MakeTexture and MeanTexel (gltf_textures.h): glTF textures' decoded images, with their
// samplers' wrap modes, and the mean texel of a texture the renderer does not sample.
// Used by ConvertGltfMaterials (gltf_materials.cpp).
#include "scene/gltf_textures.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/error.h"

namespace lt::gltf_material_detail {

namespace {

WrapMode ToWrap(int mode, const std::string& where) {
  switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_REPEAT: return WrapMode::kRepeat;
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return WrapMode::kClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return WrapMode::kMirroredRepeat;
    default: throw InputError(where, "unknown wrap mode " + std::to_string(mode));
  }
}

}  // namespace

// Decoded RGBA8 image of glTF image `index`.
std::shared_ptr<Texture> MakeTexture(const GltfSource& src, int texture_index) {
  const auto& m = src.model;
  const std::string tex_where = GltfWhere(src, "textures", texture_index);
  const tinygltf::Texture& tex = m.textures[size_t(texture_index)];
  if (tex.source == -1) {
    std::string alternatives;
    for (const auto& [name, value] : tex.extensions) alternatives += (alternatives.empty() ? "" : ", ") + name;
    throw InputError(tex_where, alternatives.empty()
                                    ? "texture has no source image"
                                    : "texture has no source image that can be read (only an image of " +
                                          alternatives + ", which is not supported)");
  }
  if (tex.source < 0 || size_t(tex.source) >= m.images.size()) {
    throw InputError(tex_where + "/source", "image " + std::to_string(tex.source) + " does not exist (" +
                                                std::to_string(m.images.size()) + " images)");
  }
  const tinygltf::Image& img = m.images[size_t(tex.source)];
  const std::string img_where = GltfWhere(src, "images", tex.source);
  auto out = std::make_shared<Texture>();
  out->name = !img.name.empty() ? img.name : (!img.uri.empty() && img.uri.rfind("data:", 0) != 0 ? img.uri : "image " + std::to_string(tex.source));
  if (src.image_errors != nullptr && size_t(tex.source) < src.image_errors->size() &&
      !(*src.image_errors)[size_t(tex.source)].empty()) {
    throw InputError(img_where, (*src.image_errors)[size_t(tex.source)] + " (used by texture " +
                                    std::to_string(texture_index) + ")");
  }
  if (img.image.empty() || img.width < 1 || img.height < 1) {
    throw InputError(img_where, "image could not be loaded" + (img.uri.empty() ? "" : " from \"" + img.uri.substr(0, 64) + "\""));
  }
  if (img.component != 4 || (img.bits != 8 && img.bits != 16)) {
    throw InputError(img_where, "unsupported pixel layout (" + std::to_string(img.component) + " channels, " +
                                    std::to_string(img.bits) + " bits)");
  }
  const size_t n = size_t(img.width) * size_t(img.height) * 4;
  if (img.image.size() != n * size_t(img.bits / 8)) throw InputError(img_where, "decoded image has the wrong size");
  out->image = Image<uint8_t>(img.width, img.height, 4);
  if (img.bits == 8) {
    std::copy(img.image.begin(), img.image.end(), out->image.pixels.begin());
  } else {  // 16-bit: keep the high byte (rounded)
    for (size_t i = 0; i < n; ++i) {
      uint16_t v;
      std::memcpy(&v, &img.image[2 * i], 2);
      out->image.pixels[i] = uint8_t((uint32_t(v) + 128) / 257);
    }
  }
  if (tex.sampler >= 0) {
    if (size_t(tex.sampler) >= m.samplers.size()) {
      throw InputError(tex_where + "/sampler", "sampler " + std::to_string(tex.sampler) + " does not exist");
    }
    const tinygltf::Sampler& s = m.samplers[size_t(tex.sampler)];
    const std::string s_where = GltfWhere(src, "samplers", tex.sampler);
    out->wrap_s = ToWrap(s.wrapS, s_where + "/wrapS");
    out->wrap_t = ToWrap(s.wrapT, s_where + "/wrapT");
  } else if (tex.sampler < -1) {
    throw InputError(tex_where + "/sampler", "must be >= 0");
  }
  return out;
}

// The mean texel of texture `index` (glTF 3.9: metallic-roughness data are linear,
// emissive colour sRGB-encoded and decoded here when `srgb`), for a texture the
// renderer does not sample: a texture scales its factor, and its mean is the
// constant closest to it. nullopt, with the reason in `why`, when the texture has
// no image that was decoded (an undecodable image is no error here: the texture
// was never needed to render).
std::optional<Eigen::Vector4d> MeanTexel(const GltfSource& src, const tinygltf::TextureInfo& info,
                                         const std::string& where, bool srgb, std::string* why) {
  const auto& m = src.model;
  if (info.index < 0 || size_t(info.index) >= m.textures.size()) {
    throw InputError(where + "/index", "texture " + std::to_string(info.index) + " does not exist (" +
                                           std::to_string(m.textures.size()) + " textures)");
  }
  const int source = m.textures[size_t(info.index)].source;
  if (source < 0 || size_t(source) >= m.images.size()) {
    *why = "texture " + std::to_string(info.index) + " has no image that can be read";
    return std::nullopt;
  }
  if (src.image_errors != nullptr && size_t(source) < src.image_errors->size() &&
      !(*src.image_errors)[size_t(source)].empty()) {
    *why = "image " + std::to_string(source) + ": " + (*src.image_errors)[size_t(source)];
    return std::nullopt;
  }
  const tinygltf::Image& img = m.images[size_t(source)];
  const size_t texels = size_t(std::max(img.width, 0)) * size_t(std::max(img.height, 0));
  const int bytes = img.bits / 8;
  if (texels == 0 || img.component < 1 || img.component > 4 || (bytes != 1 && bytes != 2) ||
      img.image.size() != texels * size_t(img.component) * size_t(bytes)) {
    *why = "image " + std::to_string(source) + " could not be decoded";
    return std::nullopt;
  }
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  for (size_t i = 0; i < texels; ++i) {
    Eigen::Vector4d texel(0, 0, 0, 1);
    for (int c = 0; c < img.component; ++c) {
      const unsigned char* p = &img.image[(i * size_t(img.component) + size_t(c)) * size_t(bytes)];
      uint32_t v = p[0];
      if (bytes == 2) {
        uint16_t v16;
        std::memcpy(&v16, p, 2);
        v = (uint32_t(v16) + 128) / 257;  // to 8 bits, as base-colour textures are kept
      }
      // Grey (and alpha) images: channel 0 is every colour channel, channel 1 the alpha.
      const int to = img.component >= 3 ? c : (c == 0 ? 0 : 3);
      texel[to] = srgb && to < 3 ? double(SrgbToLinear(uint8_t(v))) : v / 255.0;
    }
    if (img.component < 3) texel[1] = texel[2] = texel[0];
    sum += texel;
  }
  return sum / double(texels);
}

}  // namespace lt::gltf_material_detail
