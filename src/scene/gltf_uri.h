// The files a glTF uri names: percent-decoding, file: URIs, and the file an
// exporter meant when the uri was written on another system (backslashes, letter
// case).
#pragma once

#include <filesystem>
#include <string>

#include "core/file_lookup.h"  // FindExportedFile

namespace lt {

// Percent-decodes a URI ("my%20file.bin" -> "my file.bin").
std::string DecodeUri(const std::string& uri);

// The local file an external (not data:) uri names: a relative reference is
// percent-decoded and joined to base_dir (the glTF file's folder); a file: URI
// names an absolute path (file:///a/b, file://localhost/a/b, file:/a/b). Either is
// then looked up with FindExportedFile. A uri of another scheme (http:, https:)
// or a file: URI naming another host is an lt::InputError at `where`: only local
// files are read. (A one-letter "scheme" is a Windows drive, C:\..., and is read
// as a path.)
std::filesystem::path ResolveGltfUri(const std::string& uri, const std::filesystem::path& base_dir,
                                     const std::string& where);

// The path tinygltf asks its file callbacks for when it loads `uri` from
// base_dir: the folder joined with tinygltf's own decoding of the uri, which
// reads '+' as a space (form encoding) besides %XX. ResolveGltfUri's file is
// handed to tinygltf under this name.
std::string TinygltfLookupPath(const std::string& uri, const std::string& base_dir);

}  // namespace lt
