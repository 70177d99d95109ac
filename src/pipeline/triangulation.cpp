#include "pipeline/triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.h"

namespace lt {

void TriangulationOptions::Check() const {
  if (!(min_ray_angle_deg >= 0 && min_ray_angle_deg < 90)) {
    throw InputError("option min_ray_angle_deg", "must be in [0, 90) degrees, got " + FormatNumber(min_ray_angle_deg));
  }
}

const char* TriangulationFailureName(TriangulationFailure failure) {
  switch (failure) {
    case TriangulationFailure::kNone: return "none";
    case TriangulationFailure::kNoPlane: return "no plane";
    case TriangulationFailure::kNoRay: return "no camera ray";
    case TriangulationFailure::kGrazing: return "grazing ray";
    case TriangulationFailure::kBehind: return "behind the camera";
  }
  return "?";
}

std::optional<Eigen::Vector3d> IntersectRayWithPlane(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                                     const Plane& plane, double min_ray_angle_rad,
                                                     TriangulationFailure* failure) {
  auto fail = [&](TriangulationFailure f) -> std::optional<Eigen::Vector3d> {
    if (failure) *failure = f;
    return std::nullopt;
  };
  // sin(angle between ray and plane) = |n·dir| for unit n and dir.
  const double denom = plane.n.dot(dir);
  const double sin_angle = std::abs(denom);
  if (!(sin_angle > 0) || sin_angle < std::sin(min_ray_angle_rad)) return fail(TriangulationFailure::kGrazing);
  const double t = -plane.SignedDistance(origin) / denom;
  if (!(t > 0)) return fail(TriangulationFailure::kBehind);  // also NaN
  Eigen::Vector3d p = origin + t * dir;
  if (!p.allFinite()) return fail(TriangulationFailure::kGrazing);  // overflow: parallel in all but name
  if (failure) *failure = TriangulationFailure::kNone;
  return p;
}

Triangulator::Triangulator(Camera camera, std::vector<Plane> planes_in_cam, TriangulationOptions options)
    : camera_(std::move(camera)), planes_(std::move(planes_in_cam)), options_(options) {
  options_.Check();
  for (size_t k = 0; k < planes_.size(); ++k) {
    const Plane& p = planes_[k];
    if (!p.n.allFinite() || !std::isfinite(p.d) || std::abs(p.n.norm() - 1.0) > 1e-9) {
      throw InputError("laser plane " + std::to_string(k),
                       "needs a finite unit normal and finite d, got n = (" + FormatNumber(p.n.x()) + ", " +
                           FormatNumber(p.n.y()) + ", " + FormatNumber(p.n.z()) + "), d = " + FormatNumber(p.d));
    }
  }
  min_angle_rad_ = options_.min_ray_angle_deg * M_PI / 180.0;
}

std::optional<Eigen::Vector3d> Triangulator::Triangulate(const Eigen::Vector2d& pixel, int plane,
                                                         TriangulationFailure* failure) const {
  if (plane < 0 || plane >= int(planes_.size())) {
    if (failure) *failure = TriangulationFailure::kNoPlane;
    return std::nullopt;
  }
  std::optional<Eigen::Vector3d> ray = pixel.allFinite() ? camera_.Unproject(pixel) : std::nullopt;
  if (!ray) {
    if (failure) *failure = TriangulationFailure::kNoRay;
    return std::nullopt;
  }
  return IntersectRayWithPlane(Eigen::Vector3d::Zero(), *ray, planes_[size_t(plane)], min_angle_rad_, failure);
}

std::vector<ScanPoint> TriangulatePoints(const Triangulator& triangulator, const std::vector<StripePoint>& points,
                                         const std::optional<Pose>& world_from_cam, TriangulationStats* stats) {
  std::vector<ScanPoint> out;
  out.reserve(points.size());
  TriangulationStats s;
  for (const StripePoint& p : points) {
    ScanPoint sp;
    sp.pixel = p;
    TriangulationFailure why = TriangulationFailure::kNone;
    sp.p_in_cam = triangulator.Triangulate({p.u, p.v}, p.plane, &why);
    ++s.points;
    switch (why) {
      case TriangulationFailure::kNone: ++s.triangulated; break;
      case TriangulationFailure::kNoPlane: ++s.no_plane; break;
      case TriangulationFailure::kNoRay: ++s.no_ray; break;
      case TriangulationFailure::kGrazing: ++s.grazing; break;
      case TriangulationFailure::kBehind: ++s.behind; break;
    }
    if (sp.p_in_cam && world_from_cam) {
      Eigen::Vector3d w = *world_from_cam * *sp.p_in_cam;
      if (w.allFinite()) sp.p_in_world = w;
    }
    out.push_back(sp);
  }
  if (stats) *stats = s;
  return out;
}

SearchAxis StripeAxis(const std::vector<Plane>& planes_in_cam) {
  if (planes_in_cam.empty()) throw InputError("laser planes", "there is no laser plane");
  const Eigen::Vector3d& n = planes_in_cam.front().n;
  // The stripe's image direction near the principal point is (-n_y, n_x).
  return std::abs(n.x()) > std::abs(n.y()) ? SearchAxis::kRows : SearchAxis::kCols;
}

std::vector<int> PlanesInImageOrder(const std::vector<Plane>& planes_in_cam, SearchAxis axis) {
  const int n = int(planes_in_cam.size());
  std::vector<double> crossings;
  for (const Plane& p : planes_in_cam) {
    if (std::abs(p.n.z()) > 1e-12) {
      double z = -p.d / p.n.z();
      if (z > 0 && std::isfinite(z)) crossings.push_back(z);
    }
  }
  double z_ref = 0.1;
  if (!crossings.empty()) {
    std::nth_element(crossings.begin(), crossings.begin() + crossings.size() / 2, crossings.end());
    z_ref = crossings[crossings.size() / 2];
  }
  // Position across the central search line (normalised image coordinate, which
  // is monotonic in the pixel position along that line): rows search the row
  // through the principal point (y = 0) and order by x / z; columns search the
  // column x = 0 and order by y / z.
  std::vector<double> position(size_t(n), 0.0);
  for (int k = 0; k < n; ++k) {
    const Plane& p = planes_in_cam[size_t(k)];
    const double a = axis == SearchAxis::kRows ? p.n.x() : p.n.y();
    const double x = std::abs(a) > 1e-12 ? -(p.n.z() * z_ref + p.d) / a : std::numeric_limits<double>::infinity();
    position[size_t(k)] = x / z_ref;
  }
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return position[size_t(a)] < position[size_t(b)]; });
  return order;
}

}  // namespace lt
