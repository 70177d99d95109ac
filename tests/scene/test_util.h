// Helpers shared by the scene tests: temporary folders, error capture and small
// glTF files built in memory.
#pragma once

#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "error_of.h"
#include "scene/gltf_loader.h"
#include "scene/gltf_writer.h"

namespace lt::test {

// A fresh folder under the system temp folder, removed with the object.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("lt_scene_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

inline void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline void WriteBytes(const std::filesystem::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A unit square in the z = 0 plane, [0,1]^2, as two counter-clockwise triangles
// (normal +z) with texture coordinates u = x, v = 1 - y.
inline std::vector<float> SquarePositions() { return {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}; }
inline std::vector<float> SquareNormals() { return {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}; }
inline std::vector<float> SquareTexcoords() { return {0, 1, 1, 1, 1, 0, 0, 0}; }
inline std::vector<uint32_t> SquareIndices() { return {0, 1, 2, 0, 2, 3}; }

// A builder holding one square mesh on one root node.
inline GltfBuilder SquareBuilder(bool normals = true, bool texcoords = false) {
  GltfBuilder b;
  int mesh = b.AddTriangleMesh("square", SquarePositions(), normals ? SquareNormals() : std::vector<float>{},
                               texcoords ? SquareTexcoords() : std::vector<float>{}, SquareIndices());
  b.AddNode("square_node", mesh);
  return b;
}

// `b` written as dir/model.gltf (its buffers embedded) and loaded from there, so
// that relative image paths resolve against `dir`.
inline GltfAsset LoadWrittenGltf(const GltfBuilder& b, const TempDir& dir) {
  b.WriteGltf(dir / "model.gltf", false);
  return LoadGltf(dir / "model.gltf", "model.gltf");
}

// A loaded file's warnings, one a line, for HasSubstr checks.
inline std::string AllWarnings(const GltfAsset& a) {
  std::string s;
  for (const auto& w : a.warnings) s += w + "\n";
  return s;
}

}  // namespace lt::test
