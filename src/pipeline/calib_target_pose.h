// The pose of a planar target seen by a calibrated camera (planar PnP): the
// homography from the target plane to the undistorted normalised image
// (Camera::Unproject, so the lens distortion is removed), Zhang's extrinsics
// from it, then Levenberg–Marquardt on the reprojection error of the corners
// through the camera's full model. The result carries the RMS reprojection
// error and the pose's standard deviations from σ²(JᵀJ)⁻¹.
#pragma once

#include <string>

#include "core/pose.h"
#include "pipeline/calib_camera.h"
#include "pipeline/calib_geometry.h"
#include "sensor/camera.h"

namespace lt {

struct TargetPoseResult {
  bool ok = false;
  std::string reason;  // why there is no pose (empty when ok)
  Pose cam_from_target = Pose::Identity();
  double rms_px = 0;                       // RMS over all corner coordinates
  Vector6d pose_std = Vector6d::Zero();    // rotation (rad, left perturbation), translation (m)
};

// Refused when the view has fewer than 4 points, points without a camera ray,
// non-finite or non-planar (z != 0) target points, a degenerate homography or
// an optimisation that does not converge. Throws lt::InputError when the two
// lists differ in length.
TargetPoseResult EstimateTargetPose(const Camera& camera, const CalibrationView& view);

}  // namespace lt
