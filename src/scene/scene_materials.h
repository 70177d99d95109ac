// The "materials" section of a scene file: named materials that objects can use
// in place of their glTF materials, including the subsurface term for plastics.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "core/json_reader.h"
#include "scene/material.h"

namespace lt {

// A material as written in the scene file, with its texture file (if any).
struct SceneMaterial {
  Material material;                     // name = the key in "materials"
  std::filesystem::path base_color_texture_path;  // empty when none
};

// Parses the "materials" object (name -> material), sorted by name. Texture files
// are read here; a missing one is an error naming the path looked for.
std::vector<SceneMaterial> ParseSceneMaterials(const json::Value& value);

// Reads an 8- or 16-bit image file as an sRGB RGBA8 texture (grey and RGB
// images are expanded, alpha defaults to opaque). `value` is the JSON node that
// named it, for errors.
std::shared_ptr<Texture> LoadTextureFile(const std::filesystem::path& path, const json::Value& value);

}  // namespace lt
