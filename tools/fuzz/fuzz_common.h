// Shared by the fuzz targets (tools/fuzz/README.md): the bytes as text, and a
// private scratch folder for the readers that take a path.
//
// A target catches only the project's error type for bad input (lt::InputError);
// anything else (std::out_of_range, std::bad_alloc, a ParamError that escaped its
// reader, a sanitizer report) ends the run as a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"

namespace lt::fuzz {

inline std::string Text(const uint8_t* data, size_t size) { return std::string(reinterpret_cast<const char*>(data), size); }

// /dev/shm/lt_fuzz_PID (or the temp folder): one per process, made once.
inline const std::filesystem::path& ScratchDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path base = std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    std::filesystem::path d = base / ("lt_fuzz_" + std::to_string(getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

// Writes the bytes as `name` in the scratch folder and returns its path.
inline std::filesystem::path WriteScratch(const std::string& name, const uint8_t* data, size_t size) {
  const std::filesystem::path p = ScratchDir() / name;
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  return p;
}

// Runs f; an lt::InputError (bad input, reported cleanly) is the expected failure.
template <typename F>
void ExpectCleanErrors(F&& f) {
  try {
    f();
  } catch (const lt::InputError&) {
  }
}

}  // namespace lt::fuzz
