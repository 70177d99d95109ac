// A first pass over a glTF's JSON before tinygltf parses it: the nesting depth (at
// most 256 levels: tinygltf recurses), the version, required extensions, the
// structure (scene/gltf_schema.h), and the data buffers and images name: data: URIs,
// and that every external buffer and image file exists, so a missing file is
// reported with the path looked for (scene/gltf_json_data.h).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "scene/gltf_container.h"
#include "scene/gltf_json_data.h"

namespace lt {

// Checks the JSON before the full parse (see above). base_dir is the folder of the
// file; `external` (optional) receives what the external files are. glTF 2.0 ("JSON
// encoding") lets an integer property be written as a decimal with a zero
// fractional part or with an exponent ("count": 24.0, "bufferView": 1e0), which
// tinygltf refuses: such values are read as the integers they are, and `rewritten`
// (optional) receives the JSON with them written as integers (empty when none).
// Buffer views' byteStride values that exporters wrote against glTF and viewers
// read (DropHarmlessByteStrides) are removed in `rewritten` too, and `warnings`
// (optional) says so. Without `materials`, the file's materials, textures, images
// and samplers are dropped first (DropGltfMaterials, in `rewritten`): none is checked,
// no image file is looked for, and required extensions that concern only them
// (IsGltfMaterialExtension) are accepted.
void CheckGltfJson(const GltfContainer& container, const std::string& file, const std::filesystem::path& base_dir,
                   GltfExternalFiles* external = nullptr, std::string* rewritten = nullptr,
                   std::vector<std::string>* warnings = nullptr, bool materials = true);

}  // namespace lt
