// The data a glTF's buffers and images name, checked before tinygltf parses the
// file (scene/gltf_json_check.h): each buffer's data: URI (media type, base64,
// length) and that every external buffer and image file exists, so a missing file
// is reported with the path looked for.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "scene/gltf_used.h"

namespace lt {

// The external files of a glTF as CheckGltfJson found them, for tinygltf's file
// callbacks.
struct GltfExternalFiles {
  // The path tinygltf asks for (TinygltfLookupPath) -> the file the uri names
  // (ResolveGltfUri), for every external buffer and image.
  std::map<std::string, std::filesystem::path> by_lookup_path;
  // The byteLength of each external buffer file, by its normalized path, where it
  // is shorter than the file.
  std::map<std::filesystem::path, uint64_t> buffer_lengths;
  // What the triangles use (FindGltfUse); the images not in use.images are not read.
  GltfUse use;
  // The files of images nothing reads (and no buffer or read image names), which
  // need not exist: tinygltf gets a placeholder byte for them, never decoded.
  std::set<std::filesystem::path> unread_images;
};

// Data: URIs of buffers and images written as browsers read them but tinygltf and
// the check below do not: a header in upper case (`DATA:`, `;BASE64,`, a media type
// such as `Image/PNG`; URI schemes and media types are case-insensitive) and base64
// wrapped into lines, ASCII whitespace (tab, line feed, form feed, carriage return,
// space) in the data (Python's base64.encodebytes, MIME and OpenSSL encoders write
// 76- or 64-character lines; a data: URL's base64 is decoded forgivingly, whitespace
// skipped); an image's data in RFC 2397's percent-encoded form (no ";base64": glTF's
// image URIs are RFC 2397 data: URIs, its buffers' base64 ones), decoded as browsers
// decode it ('%' and two hex digits a byte, any other character itself); and a
// buffer's media type with parameters (`application/octet-stream;charset=binary;base64,`,
// which RFC 2397 and glTF-Validator read as application/octet-stream).
// DataUrisNeedNormalizing says whether `root` holds one; NormalizeDataUris writes the
// header in lower case, removes the whitespace from data otherwise of base64
// characters (other data is left for CheckGltfBufferData, which skips whitespace, to
// name the place as written), writes a percent-encoded image as
// `data:application/octet-stream;base64,` (images are decoded by their content) and a
// buffer's header without its parameters, and returns whether it changed any.
bool DataUrisNeedNormalizing(const nlohmann::json& root);
bool NormalizeDataUris(nlohmann::json* root);

// Checks `root`'s buffers: a data: URI's media type, base64 (percent-encoded data is
// refused: glTF embeds buffers as base64) and length, an external
// file's existence and size (at least byteLength), a buffer without uri (only a
// GLB's, `binary`, first may omit it; a meshopt fallback buffer is named as such).
// `external` (optional) receives the external files.
void CheckGltfBufferData(const nlohmann::json& root, bool binary, const std::string& file,
                         const std::filesystem::path& base_dir, GltfExternalFiles* external);

// Checks that every image file `root`'s images name exists (data: URIs are decoded
// later), but for the images `read` (by index) says are not read: their uri is not
// looked at (a missing file, a remote URI, ...) and their files, when resolved, are
// entered in external->unread_images. `external` (optional) receives them.
void CheckGltfImageFiles(const nlohmann::json& root, const std::string& file, const std::filesystem::path& base_dir,
                         const std::vector<bool>& read, GltfExternalFiles* external);

}  // namespace lt
