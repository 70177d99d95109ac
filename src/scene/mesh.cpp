#include "scene/mesh.h"

#include <cmath>
#include <stdexcept>

namespace lt {

Eigen::AlignedBox3d Mesh::Bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& p : positions) box.extend(p.cast<double>());
  return box;
}

size_t Mesh::MemoryBytes() const {
  return positions.capacity() * sizeof(Eigen::Vector3f) + normals.capacity() * sizeof(Eigen::Vector3f) +
         texcoords.capacity() * sizeof(Eigen::Vector2f) + colors.capacity() * sizeof(Eigen::Vector3f) +
         alphas.capacity() * sizeof(float) +
         indices.capacity() * sizeof(uint32_t) +
         triangle_material.capacity() * sizeof(uint32_t);
}

void Mesh::Validate() const {
  const std::string what = "mesh \"" + name + "\": ";
  if (normals.size() != positions.size()) throw std::logic_error(what + "normals/positions size mismatch");
  if (!texcoords.empty() && texcoords.size() != positions.size()) {
    throw std::logic_error(what + "texcoords/positions size mismatch");
  }
  if (!colors.empty() && colors.size() != positions.size()) {
    throw std::logic_error(what + "colors/positions size mismatch");
  }
  if (!alphas.empty() && alphas.size() != positions.size()) {
    throw std::logic_error(what + "alphas/positions size mismatch");
  }
  if (indices.size() % 3 != 0) throw std::logic_error(what + "index count not a multiple of 3");
  if (triangle_material.size() != TriangleCount()) {
    throw std::logic_error(what + "one material per triangle expected");
  }
  for (uint32_t i : indices) {
    if (i >= positions.size()) throw std::logic_error(what + "index out of range");
  }
  for (const auto& p : positions) {
    if (!p.allFinite()) throw std::logic_error(what + "non-finite position");
  }
}

Eigen::Vector3d FaceNormal(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                           const Eigen::Vector3f& p2) {
  Eigen::Vector3d a = p0.cast<double>(), b = p1.cast<double>(), c = p2.cast<double>();
  return (b - a).cross(c - a);
}

bool IsDegenerateTriangle(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                          const Eigen::Vector3f& p2) {
  Eigen::Vector3d a = p0.cast<double>(), b = p1.cast<double>(), c = p2.cast<double>();
  double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  if (longest2 == 0.0) return true;
  double area2 = (b - a).cross(c - a).norm();
  return !(area2 > 1e-12 * longest2);
}

}  // namespace lt
