// A plane n·p + d = 0 with unit normal n. Laser sheets are planes; the pipeline
// triangulates by intersecting camera rays with them.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace lt {

struct Plane {
  Eigen::Vector3d n = Eigen::Vector3d::UnitZ();  // unit normal
  double d = 0.0;                                // n·p + d = 0 for points p on the plane

  // The plane through `point` with normal `normal` (normalised here).
  static Plane FromPointNormal(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
    Eigen::Vector3d u = normal.normalized();
    return {u, -u.dot(point)};
  }
  double SignedDistance(const Eigen::Vector3d& p) const { return n.dot(p) + d; }
  // The same plane expressed in frame b, given b_from_a (this plane is in frame a).
  Plane Transformed(const Eigen::Isometry3d& b_from_a) const {
    Eigen::Vector3d nb = b_from_a.linear() * n;
    return {nb, d - nb.dot(b_from_a.translation())};
  }
  // Where the ray origin + t·dir meets the plane (t > 0), or nullopt when the ray is
  // parallel to the plane or the plane lies behind the origin.
  std::optional<double> IntersectRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
    double denom = n.dot(dir);
    if (std::abs(denom) < 1e-15) return std::nullopt;
    double t = -SignedDistance(origin) / denom;
    if (!(t > 0.0)) return std::nullopt;
    return t;
  }
};

}  // namespace lt
