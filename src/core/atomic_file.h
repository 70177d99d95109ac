// Writing output files so that an interrupted run never leaves a half-written
// file under its final name: write to "NAME.tmp-PID", then rename over NAME.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

namespace lt {

// Calls write(tmp_path) to produce the file, then renames tmp_path to path.
// On any exception the temporary file is removed and the exception propagates.
void WriteAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path& tmp_path)>& write);

// Writes a whole text or binary file atomically.
void WriteFileAtomically(const std::filesystem::path& path, const std::string& contents);

}  // namespace lt
