// The files a glTF uri names: percent-decoding, and the file an exporter meant
// when the uri was written on another system (backslashes, letter case).
#pragma once

#include <filesystem>
#include <string>

namespace lt {

// Percent-decodes a URI ("my%20file.bin" -> "my file.bin").
std::string DecodeUri(const std::string& uri);

// The file an exporter meant by `path` (a glTF file's folder joined with a decoded
// uri): the path itself when it is a file; else the path with backslashes read as
// folder separators (as exporters on Windows write them); else the one file whose
// path matches ignoring case, folder by folder (files made on a case-insensitive
// file system). Returns `path` unchanged when none of these is a file.
std::filesystem::path FindExportedFile(const std::filesystem::path& path);

}  // namespace lt
