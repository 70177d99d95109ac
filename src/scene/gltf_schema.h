// Checks of the glTF JSON's structure that tinygltf reports without saying where
// ("'componentType' property is missing in Accessor.") or skips silently (a node's
// `children` or `mesh` of the wrong type dropped the subtree or the mesh): the
// required properties and integer references of accessors, buffer views, nodes and
// mesh primitives. Run on the parsed JSON before tinygltf sees it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace lt {

// Throws lt::InputError naming the file and the JSON pointer of the first
// element that glTF 2.0's schema refuses.
void CheckGltfSchema(const nlohmann::json& root, const std::string& file);

// Buffer views' byteStride values that glTF refuses but that real exporters wrote
// and viewers read: 0 (Google Poly's exports; CesiumJS, three.js and gltf-rs read
// it as absent, tightly packed) and, on a view read only as indices, the size of
// an index (three.js's GLTFExporter before r89 wrote 2 there; glTF gives byteStride
// to vertex attributes only). Such byteStride properties are removed from `root`,
// with one warning; returns whether any was. Other values are left to
// CheckGltfSchema to refuse.
bool DropHarmlessByteStrides(nlohmann::json* root, const std::string& file, std::vector<std::string>* warnings);

// Image data: URIs whose media type tinygltf does not take (image/jpg, image/webp,
// none, parameters before ";base64,") are relabelled application/octet-stream: an
// image is decoded by its content, as browsers and the image loader here do, so a
// PNG or JPEG so labelled reads and any other format gets the undecodable-image
// error naming /images/N. Returns whether any was.
bool RelabelImageDataUris(nlohmann::json* root);

// Whether `root` holds anything DropHarmlessByteStrides, RelabelImageDataUris or
// NormalizeDataUris (gltf_json_data.h) would change (cheap: no copy), and all
// three, with their warnings.
bool NeedsGltfFixUp(const nlohmann::json& root);
bool FixUpGltfJson(nlohmann::json* root, const std::string& file, std::vector<std::string>* warnings);

}  // namespace lt
