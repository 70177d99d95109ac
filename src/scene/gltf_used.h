// What of a glTF's look its triangles use, found from the JSON before anything is
// read: the materials of the triangle primitives of the meshes the default scene
// places, and the images of those materials' textures. Exporters write whole
// material libraries (pygltflib, CAD appearances): the materials, textures and images
// no triangle uses are neither read nor warned about (only glTF's schema, their
// references in range included, is checked: gltf_schema.h). Used by CheckGltfJson.
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

namespace lt {

struct GltfUse {
  std::vector<bool> materials;  // by index of the top-level "materials"
  std::vector<bool> images;     // by index of "images": read (a used material's texture names it)
};

// The use of `root`'s materials and images. A superset of what the loader reads:
// the scene is the one WalkGltfScene loads ("scene", else scene 0, else every node),
// every node below it counts (even one the loader refuses later), and a primitive of
// any mode but points and lines uses its material; every textureInfo of a used
// material (a key ending in "Texture" holding an "index", extensions included) uses
// its texture, whose "source" and extensions' "source" images are read.
GltfUse FindGltfUse(const nlohmann::json& root);

}  // namespace lt
