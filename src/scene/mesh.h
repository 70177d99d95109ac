// Triangle meshes in object space, as loaded from glTF: what Embree traces and what
// the renderer interpolates at a hit.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace lt {

// One mesh, in the units and frame of its file (metres, object space). Every
// vertex has a normal (normals.size() == positions.size()); texcoords are either
// empty (no primitive had TEXCOORD_0) or one per vertex. Triangles are indices
// into the vertex arrays, three per triangle, wound counter-clockwise seen from
// the front (glTF convention). Each triangle carries a material index into the
// scene's material table.
struct Mesh {
  std::string name;
  std::vector<Eigen::Vector3f> positions;
  std::vector<Eigen::Vector3f> normals;    // unit length
  std::vector<Eigen::Vector2f> texcoords;  // glTF UV: (0,0) top left of the image
  // Linear RGB per vertex (glTF COLOR_0), multiplying the material's base
  // colour; empty when the mesh has none.
  std::vector<Eigen::Vector3f> colors;
  // The alpha of an RGBA COLOR_0 per vertex ([0, 1]; glTF: it multiplies the
  // base colour's alpha), empty when no primitive had one (alpha 1).
  std::vector<float> alphas;
  std::vector<uint32_t> indices;           // 3 per triangle
  std::vector<uint32_t> triangle_material; // 1 per triangle

  size_t TriangleCount() const { return indices.size() / 3; }
  size_t VertexCount() const { return positions.size(); }
  // Axis-aligned bounds of the vertices (empty box for an empty mesh).
  Eigen::AlignedBox3d Bounds() const;
  // Bytes held by the arrays (for memory reports).
  size_t MemoryBytes() const;
  // Throws std::logic_error when the arrays are inconsistent (sizes, indices out
  // of range, non-finite values). Loaders call it before handing a mesh out.
  void Validate() const;
};

// Unnormalised face normal (p1 - p0) x (p2 - p0) in double; zero for a degenerate triangle.
Eigen::Vector3d FaceNormal(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                           const Eigen::Vector3f& p2);

// A triangle is degenerate when two indices coincide or its area is zero to
// float precision (|cross| <= 1e-12 * longest_edge^2, i.e. the corners are collinear).
bool IsDegenerateTriangle(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                          const Eigen::Vector3f& p2);

}  // namespace lt
