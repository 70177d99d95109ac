// The images of glTF textures, for ConvertGltfMaterials (gltf_materials.h): a texture
// decoded for the renderer to sample, and the mean texel of one it does not sample.
// Internal to gltf_materials.cpp; defined in gltf_textures.cpp.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>

#include "scene/gltf_accessors.h"
#include "scene/material.h"

namespace tinygltf {
struct TextureInfo;
}

namespace lt::gltf_material_detail {

// Decoded RGBA8 image of glTF texture `texture_index`, with its sampler's wrap modes.
std::shared_ptr<Texture> MakeTexture(const GltfSource& src, int texture_index);

// The mean texel of a textureInfo's texture, or nullopt with the reason in `why`
// (see gltf_textures.cpp).
std::optional<Eigen::Vector4d> MeanTexel(const GltfSource& src, const tinygltf::TextureInfo& info,
                                         const std::string& where, bool srgb, std::string* why);

}  // namespace lt::gltf_material_detail
