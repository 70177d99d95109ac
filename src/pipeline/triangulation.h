// Triangulation of laser stripe points by ray-plane intersection
// (docs/pipeline.md). A stripe centre (u, v) found in the image, with the laser
// sheet it belongs to, is the point where the camera's ray through (u, v) meets
// that sheet's plane:
//
//   ray:    p(t) = t r,  r = Camera::Unproject(u, v)  (unit, camera frame, lens
//           distortion undone; the chief ray, which a thin lens focuses unchanged)
//   plane:  n·p + d = 0 (camera frame, unit n)
//   point:  t = -d / (n·r),  p = t r
//
// A ray that meets the plane at a small angle gives a point whose position
// depends violently on the pixel position (dp/du grows as 1 / sin(angle)), and a
// ray parallel to the plane gives none: rays within `min_ray_angle_deg` of the
// plane are rejected. So are pixels without a valid ray (outside the lens
// distortion's domain), intersections behind the camera or at its centre, and
// anything not finite. The output never holds NaN or infinity.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/extraction_options.h"
#include "pipeline/stripe_point.h"
#include "sensor/camera.h"
#include "sensor/plane.h"

namespace lt {

struct TriangulationOptions {
  // Rays closer than this to the plane (angle between the ray and the plane,
  // degrees) are rejected. 0 rejects only rays exactly parallel to the plane.
  double min_ray_angle_deg = 5.0;

  void Check() const;  // throws lt::InputError ("option min_ray_angle_deg")
};

// Why a point has no 3D position.
enum class TriangulationFailure {
  kNone,
  kNoPlane,   // plane -1 (not identified) or not one of the planes
  kNoRay,     // the pixel has no valid camera ray (outside the distortion's domain)
  kGrazing,   // the ray meets the plane within min_ray_angle_deg (or is parallel)
  kBehind,    // the intersection is behind the camera or at its centre
};
const char* TriangulationFailureName(TriangulationFailure failure);

// Where the ray origin + t dir (dir: unit) meets `plane`, for t > 0, when the
// ray makes an angle of at least min_ray_angle_rad with the plane. The result
// is finite whenever it is returned.
std::optional<Eigen::Vector3d> IntersectRayWithPlane(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                                     const Plane& plane, double min_ray_angle_rad,
                                                     TriangulationFailure* failure = nullptr);

class Triangulator {
 public:
  // `planes_in_cam`: the laser planes in the camera frame, indexed by the plane
  // numbers the stripe points carry. Options are checked; planes must have a
  // finite, unit normal and a finite d (throws lt::InputError "laser plane K").
  Triangulator(Camera camera, std::vector<Plane> planes_in_cam, TriangulationOptions options = {});

  const Camera& camera() const { return camera_; }
  const std::vector<Plane>& planes() const { return planes_; }
  const TriangulationOptions& options() const { return options_; }

  // The camera-frame point of image point `pixel` on plane `plane`.
  std::optional<Eigen::Vector3d> Triangulate(const Eigen::Vector2d& pixel, int plane,
                                             TriangulationFailure* failure = nullptr) const;

 private:
  Camera camera_;
  std::vector<Plane> planes_;
  TriangulationOptions options_;
  double min_angle_rad_ = 0;
};

// A stripe point with its 3D position, when known.
struct ScanPoint {
  StripePoint pixel;                           // image position, width, strength, plane
  std::optional<Eigen::Vector3d> p_in_cam;     // triangulated point (camera frame, metres)
  std::optional<Eigen::Vector3d> p_in_world;   // the same in the world frame, when the pose is known
};

// Counts of a frame's points by outcome.
struct TriangulationStats {
  int points = 0;        // stripe points in
  int triangulated = 0;  // with a 3D point
  int no_plane = 0, no_ray = 0, grazing = 0, behind = 0;
};

// Triangulates every point of a frame; world coordinates when world_from_cam is given.
std::vector<ScanPoint> TriangulatePoints(const Triangulator& triangulator, const std::vector<StripePoint>& points,
                                         const std::optional<Pose>& world_from_cam,
                                         TriangulationStats* stats = nullptr);

// The search axis along which stripes of these planes are best measured:
// rows when the first plane's stripe runs mostly top to bottom in the image
// (its image direction is (-n_y, n_x) at the principal point), columns
// otherwise. Throws lt::InputError when there is no plane.
SearchAxis StripeAxis(const std::vector<Plane>& planes_in_cam);

// The plane numbers in image order: left to right when searching rows, top to
// bottom when searching columns, as plane identification numbers its groups
// (pipeline/plane_identification.h). Each plane is placed where it crosses the
// image's central search line at the reference depth: the median depth at
// which the planes cross the optical axis (0.1 m when none does in front of the
// camera). Stripes of sheets that do not cross each other inside the working
// volume keep this order at every depth.
std::vector<int> PlanesInImageOrder(const std::vector<Plane>& planes_in_cam, SearchAxis axis);

}  // namespace lt
