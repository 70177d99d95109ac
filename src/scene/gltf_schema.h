// Checks of the glTF JSON's structure that tinygltf reports without saying where
// ("'componentType' property is missing in Accessor.") or skips silently (a node's
// `children` or `mesh` of the wrong type dropped the subtree or the mesh): the
// required properties and integer references of accessors, buffer views, nodes and
// mesh primitives. Run on the parsed JSON before tinygltf sees it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace lt {

// Throws lt::InputError naming the file and the JSON pointer of the first
// element that glTF 2.0's schema refuses.
void CheckGltfSchema(const nlohmann::json& root, const std::string& file);

}  // namespace lt
