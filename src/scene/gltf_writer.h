// Writing glTF 2.0 files: a small builder that holds the JSON document and one
// binary buffer, used by the demo-scene generator, benchmarks and tests. It writes
// .glb, or .gltf with the buffer external (.bin) or embedded (base64 data URI).
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/base64.h"  // Base64Encode, used for embedded buffers

namespace lt {

class GltfBuilder {
 public:
  GltfBuilder();

  // The document; edit freely (tests use it to make malformed files).
  nlohmann::json& json() { return doc_; }
  const nlohmann::json& json() const { return doc_; }
  std::vector<uint8_t>& bin() { return bin_; }

  // Appends bytes to the buffer (at a 4-byte aligned offset) as a new buffer view.
  // Returns the buffer view index. byte_stride 0 leaves it out (tightly packed).
  int AddBufferView(const void* data, size_t bytes, int byte_stride = 0);
  // Adds an accessor; min/max are written for VEC3 float data (glTF requires them for POSITION).
  int AddAccessor(int buffer_view, int component_type, size_t count, const std::string& type,
                  bool normalized = false, size_t byte_offset = 0);
  // Float data as a new view + accessor. `type` is "SCALAR", "VEC2", "VEC3", "VEC4" or "MAT4".
  int AddFloats(const std::vector<float>& values, const std::string& type);
  // Index data as a new view + accessor with the given component type (5121, 5123 or 5125).
  int AddIndices(const std::vector<uint32_t>& indices, int component_type = 5125);

  // A mesh of one triangle-list primitive. normals/texcoords may be empty,
  // indices empty = non-indexed, material -1 = none. Returns the mesh index.
  int AddTriangleMesh(const std::string& name, const std::vector<float>& positions,
                      const std::vector<float>& normals, const std::vector<float>& texcoords,
                      const std::vector<uint32_t>& indices, int material = -1, int mode = 4);
  // A metallic-roughness material. Returns its index.
  int AddMaterial(const std::string& name, const std::vector<double>& base_color_rgba, double metallic,
                  double roughness, const std::vector<double>& emissive = {0, 0, 0});
  // A node holding a mesh (mesh -1 = none), added to the default scene when root.
  int AddNode(const std::string& name, int mesh, const std::vector<double>& translation = {},
              bool root = true);

  // Binary glTF.
  std::vector<uint8_t> ToGlb() const;
  // Text glTF; the buffer goes to `bin_uri` (written by WriteGltf) or, when
  // bin_uri is empty, into a base64 data URI.
  std::string ToGltf(const std::string& bin_uri = "") const;
  void WriteGlb(const std::filesystem::path& path) const;
  // Writes path and, unless embedded, path's stem + ".bin" beside it.
  void WriteGltf(const std::filesystem::path& path, bool embedded) const;

 private:
  nlohmann::json Finalized(const std::string& bin_uri, bool with_buffer_uri) const;

  nlohmann::json doc_;
  std::vector<uint8_t> bin_;
};

}  // namespace lt
