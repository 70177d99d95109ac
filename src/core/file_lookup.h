// The file a path written on another system meant: Windows folder separators
// and letter case (scene files and glTF files made on Windows or macOS).
#pragma once

#include <filesystem>

namespace lt {

// The file a user or exporter meant by `path`: the path itself when it is a
// file; else the path with backslashes read as folder separators (as written
// on Windows); else the one file whose path matches ignoring case, folder by
// folder (files named on a case-insensitive file system). Returns `path`
// unchanged when none of these is a file.
std::filesystem::path FindExportedFile(const std::filesystem::path& path);

}  // namespace lt
