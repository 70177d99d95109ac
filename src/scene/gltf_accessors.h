// Bounds-checked reading of glTF accessors. tinygltf parses the JSON but does not
// check that accessors, buffer views and buffers fit inside each other; every read
// here does, so a malformed file is an lt::InputError ("part.gltf: /accessors/3:
// ..."), never a read out of bounds.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace lt {

// The model being read and how errors name its file.
struct GltfSource {
  const tinygltf::Model& model;
  std::string file;  // as shown in messages
  // Why image i could not be decoded (empty when it was, or when never tried);
  // the error is raised only when a texture uses the image. May be null.
  const std::vector<std::string>* image_errors = nullptr;
};

// Reads accessor `index` as `components` floats per element (count * components
// values), applying `normalized` integer scaling (glTF 2.0 3.11) and sparse
// substitution (an accessor without a bufferView starts from zeros). Accepts SCALAR/VEC2/VEC3/VEC4 accessors whose component count is
// `components`; integer components are converted to their (normalized) value.
std::vector<float> ReadFloatAccessor(const GltfSource& src, int index, int components);

// Reads a SCALAR accessor of unsigned bytes, shorts or ints (vertex indices).
std::vector<uint32_t> ReadIndexAccessor(const GltfSource& src, int index);

// Number of elements of accessor `index` (checks that the index exists).
size_t AccessorCount(const GltfSource& src, int index);

// "part.gltf: /accessors/3" style location of an element of the glTF document.
std::string GltfWhere(const GltfSource& src, const std::string& array, int index);

}  // namespace lt
