// Loading a glTF for its geometry alone, when the caller gives every primitive its
// own material (a scene object's "material"): the file's materials, textures, images
// and samplers are dropped from the JSON before anything reads or checks them, so a
// file whose look cannot be read (KTX2 or DDS textures, a missing or undecodable
// image, a malformed material) still gives its geometry. Used by CheckGltfJson.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace lt {

// Whether a required extension concerns only materials and textures
// (KHR_materials_*, KHR_texture_basisu, KHR_texture_transform, EXT_texture_webp,
// EXT_texture_avif, MSFT_texture_dds, KHR_techniques_webgl and its draft name
// KHR_technique_webgl): a file loaded without materials needs none of
// them. Geometry extensions (Draco, meshopt, quantization) are not such.
bool IsGltfMaterialExtension(const std::string& name);

// Whether `root` holds anything DropGltfMaterials removes (cheap: no copy).
bool HasGltfMaterials(const nlohmann::json& root);

// Removes the top-level `materials`, `textures`, `images` and `samplers`, each mesh
// primitive's `material` and KHR_materials_variants mappings, and the top-level
// KHR_materials_variants: every primitive is then without a material. Leaves
// anything of the wrong type that is not one of these to the checks that follow.
void DropGltfMaterials(nlohmann::json* root);

}  // namespace lt
