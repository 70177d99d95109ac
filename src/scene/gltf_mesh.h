// Conversion of one glTF mesh (all its primitives) into an lt::Mesh. Used by the
// glTF loader; the accessor reads are bounds-checked (gltf_accessors.h).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "scene/gltf_accessors.h"
#include "scene/mesh.h"

namespace lt {

struct GltfMeshStats {
  size_t degenerate_triangles = 0;  // dropped
  bool uses_default_material = false;
};

// Converts mesh `index`. Triangle strips and fans become triangle lists, points
// and lines are skipped with a warning, primitives without NORMAL get flat normals
// (their vertices are unshared). Primitives without a material get
// `default_material`. Throws lt::InputError on malformed data.
Mesh ConvertGltfMesh(const GltfSource& src, int index, uint32_t default_material, GltfMeshStats* stats,
                     std::vector<std::string>* warnings);

}  // namespace lt
