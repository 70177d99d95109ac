// Laser plane calibration (docs/calibration.md): the stripe seen on a planar
// target of known pose gives 3D points on the laser plane (each stripe pixel's
// ray meets the target plane); a plane is fitted to the points of all views by
// RANSAC (seeded lt::Rng, inlier threshold in metres) and refined by total least
// squares (SVD of the centred inliers). Several sheets (multi-line lasers) are
// fitted separately, by plane id.
//
// The fit reports its residual RMS and the standard deviations of its normal
// and offset (from the TLS covariance: tilt variance σ²/(N s²) about each
// principal axis, with s the RMS spread of the inliers along the other one),
// and is refused when the points do not determine a plane: too few points, too
// few inliers, or points nearly collinear (all target views in nearly the
// same plane), measured by the ratio of the second to the first principal
// spread. From target views (CalibrateLaserPlanes) it is also refused when the
// plane's inliers come from fewer than two views, or when the plane makes less
// than min_target_angle_deg with a target plane: all points of one view lie on
// its target plane, so stray points (reflections, a mis-grouped stripe) on
// views in one plane would otherwise yield the target plane itself.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/pose.h"
#include "sensor/camera.h"
#include "sensor/plane.h"

namespace lt {

// One view of the target with the laser on: the target's pose (from camera
// calibration or PnP) and the stripe centres detected on it.
struct LaserTargetView {
  Pose cam_from_target;  // the target plane is z = 0 of the target frame
  std::vector<Eigen::Vector2d> stripe_pixels;
  std::vector<int> plane_ids;  // one per pixel (laser sheet number); empty: all sheet 0
};

struct LaserPoint {
  Eigen::Vector3d p_in_cam = Eigen::Vector3d::Zero();
  int plane_id = 0;
  int view = 0;
};

// 3D points of the stripe pixels on the target planes (camera frame). Pixels
// without a ray, or whose ray is parallel to the target or meets it behind the
// camera, are skipped and counted in *skipped. Throws lt::InputError when a
// view's plane_ids is neither empty nor as long as its pixels, or a plane id is
// negative.
std::vector<LaserPoint> StripePointsOnTarget(const Camera& camera, const std::vector<LaserTargetView>& views,
                                             int* skipped = nullptr);

struct LaserPlaneFitOptions {
  double inlier_threshold_m = 0.1e-3;  // RANSAC: largest distance of an inlier to the plane
  double confidence = 0.999;           // RANSAC stops when a better sample is this unlikely
  int max_iterations = 5000;           // RANSAC samples at most
  double min_inlier_fraction = 0.5;
  int min_points = 20;
  // Refuse when the inliers' second principal spread is below this fraction of
  // the first (points nearly on a line: the plane's rotation about that line is
  // undetermined; the normal's error grows as 1/ratio).
  double min_spread_ratio = 0.05;
  // CalibrateLaserPlanes: smallest angle between the laser plane and a target plane.
  double min_target_angle_deg = 10.0;
  uint64_t seed = 1;

  // Throws lt::InputError ("option <name>: ...").
  void Check() const;
};

struct LaserPlaneFit {
  bool ok = false;
  std::string reason;  // why the fit was refused (empty when ok)
  int plane_id = 0;
  // Camera frame; the normal points away from the camera centre (d <= 0).
  Plane plane;
  int points = 0;
  int inliers = 0;
  double residual_rms_m = 0;  // RMS distance of the inliers to the plane
  double normal_std_rad = 0;  // standard deviation of the normal's direction (both tilt axes)
  double offset_std_m = 0;    // standard deviation of d
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the inliers
  Eigen::Vector3d spread_m = Eigen::Vector3d::Zero();  // RMS extent along the principal axes, largest first
  int ransac_iterations = 0;
};

// One plane through the points.
LaserPlaneFit FitLaserPlane(const std::vector<Eigen::Vector3d>& points, const LaserPlaneFitOptions& options = {},
                            int plane_id = 0);
// One fit per plane id present, in increasing id order.
std::vector<LaserPlaneFit> FitLaserPlanes(const std::vector<LaserPoint>& points,
                                          const LaserPlaneFitOptions& options = {});

// The whole laser calibration from target views: StripePointsOnTarget, then
// FitLaserPlanes, then the checks against the target planes described above.
std::vector<LaserPlaneFit> CalibrateLaserPlanes(const Camera& camera, const std::vector<LaserTargetView>& views,
                                                const LaserPlaneFitOptions& options = {}, int* skipped = nullptr);

// An estimated plane against the truth: the angle between the normals
// (radians, [0, π/2], sign-free) and the difference of the offsets d after
// orienting both normals alike (metres).
struct PlaneError {
  double normal_angle_rad = 0;
  double offset_m = 0;
};
PlaneError ComparePlanes(const Plane& estimate, const Plane& truth);

}  // namespace lt
