// Conversion of glTF materials (metallic-roughness factors, base-colour texture with
// its sampler, emissive) into lt::Material. Used by the glTF loader.
#pragma once

#include <string>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/material.h"

namespace lt {

// All materials of the file, in order. Textures used by several materials are
// shared. alphaMode, alphaCutoff and the base colour's alpha are read (Material::
// alpha_mode; EmbreeScene applies them). Features that are not rendered (normal and
// occlusion textures) are ignored with a warning; metallic-roughness, emissive and
// specular-glossiness textures, which are not sampled either, scale their factors
// by their mean texel, with a warning.
// metallic_by_default (optional) receives, per material, whether its metallic is
// glTF's default 1 for want of a `metallicFactor` (and of a metallic-roughness
// texture, KHR_materials_unlit or _pbrSpecularGlossiness, which set it): a metal.
// COLLADA2GLTF writes no factor for its Phong materials, nor do KHR_materials_common
// materials; other exporters leave out factors equal to glTF's defaults. Whether or not
// a metal was meant, a scanner sees a conductor's reflection there.
// `used` (optional, by material index; FindGltfUse): a material no triangle uses keeps
// its index, and holds its name and core factors as written (alphaMode, doubleSided,
// the emissive strength): its textures and other extensions are not read, nothing of
// it is warned about, and its metallic_by_default is false.
std::vector<Material> ConvertGltfMaterials(const GltfSource& src, std::vector<std::string>* warnings,
                                           std::vector<bool>* metallic_by_default = nullptr,
                                           const std::vector<bool>* used = nullptr);

}  // namespace lt
