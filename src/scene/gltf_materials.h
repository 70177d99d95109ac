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
std::vector<Material> ConvertGltfMaterials(const GltfSource& src, std::vector<std::string>* warnings);

}  // namespace lt
