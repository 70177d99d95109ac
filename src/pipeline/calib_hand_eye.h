// Hand-eye calibration (docs/calibration.md): the fixed transform X =
// tool_from_cam between the robot's tool (flange) frame and the camera, from
// robot poses base_from_tool_i and camera views of a fixed target
// cam_from_target_i. With Y = base_from_target (also unknown, fixed),
//   base_from_tool_i · X · cam_from_target_i = Y   for every i,
// so for each pair of views A X = X B with A = tool_i_from_tool_j and
// B = cam_i_from_cam_j.
//
// Closed form (Park & Martin 1994): the rotation from the log maps of the
// relative rotations (α = R_X β, solved as an orthogonal Procrustes problem
// over all pairs), the translation by linear least squares on
// (R_A − I) t_X = R_X t_B − t_A. Then Levenberg–Marquardt over X, Y and a
// correction of every robot pose (held to the measured pose by a prior of the
// robot's stated accuracy, so that robot errors are not forced into X):
//   - with a camera and target corners: the reprojection error of the corners
//     through cam_from_target_i = X⁻¹ · base_from_tool_i⁻¹ · Y, over the
//     corner σ;
//   - otherwise the pose residual of each view, log(R̂_i R_iᵀ) and t̂_i − t_i
//     between predicted and measured cam_from_target_i over the view pose σ
//     (this is A X = X B over all pairs, but with each measurement used once,
//     so the covariance is sound).
// The standard deviations of X come from σ₀²(JᵀJ)⁻¹ with the a-posteriori
// variance factor σ₀² (reported: near 1 when the stated noise levels fit the data).
//
// Refused, with the reason, on degenerate motion: fewer than 3 views, relative
// rotations all smaller than min_rotation_deg, or rotation axes all within
// min_axis_angle_deg of each other (rotations about parallel axes leave the
// translation along that axis undetermined).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/calib_geometry.h"
#include "sensor/camera.h"

namespace lt {

struct HandEyeObservation {
  Pose base_from_tool;   // robot forward kinematics (tool = flange)
  Pose cam_from_target;  // the target seen by the camera (calibration extrinsics or PnP)
  // For the reprojection refinement: target corners (target frame, metres) and
  // their detected pixels, in the same order.
  std::vector<Eigen::Vector3d> target_points;
  std::vector<Eigen::Vector2d> pixels;
};

struct HandEyeOptions {
  double min_rotation_deg = 5.0;     // the largest relative rotation must reach this
  double min_axis_angle_deg = 10.0;  // two relative rotations >= min_rotation_deg with axes this far apart
  // Noise model of the refinement (standard deviations). The robot's pose
  // accuracy: both 0 holds the robot poses fixed.
  double robot_rotation_sigma_deg = 0.005;
  double robot_translation_sigma_m = 0.02e-3;
  double corner_sigma_px = 0.1;  // reprojection refinement
  // Pose refinement: accuracy of a measured cam_from_target.
  double view_rotation_sigma_deg = 0.02;
  double view_translation_sigma_m = 0.05e-3;
  int max_iterations = 100;

  // Throws lt::InputError ("option <name>: ...").
  void Check() const;
};

struct HandEyeResult {
  bool ok = false;
  std::string reason;  // why it was refused (empty when ok)

  Pose tool_from_cam = Pose::Identity();     // X
  Pose base_from_target = Pose::Identity();  // Y
  Pose closed_form_tool_from_cam = Pose::Identity();
  bool used_reprojection = false;

  // Standard deviations of X: rotation (rad, left perturbation about the tool
  // axes) and translation (m), and their root-sum-squares.
  Vector6d tool_from_cam_std = Vector6d::Zero();
  double rotation_std_rad = 0;
  double translation_std_m = 0;

  double variance_factor = 0;      // σ₀² = cost / (residuals − parameters)
  double reprojection_rms_px = 0;  // reprojection refinement only
  // Predicted vs measured cam_from_target over the views (both refinements).
  double rotation_rms_rad = 0;
  double translation_rms_m = 0;

  // Motion diagnostics: the largest relative rotation and the largest angle
  // between the axes of two relative rotations of at least min_rotation_deg.
  double largest_rotation_deg = 0;
  double largest_axis_angle_deg = 0;
  int iterations = 0;
};

// Without a camera the refinement uses the pose residuals; with one, every
// observation must carry at least 4 corners. Throws lt::InputError for invalid
// options, corner lists of different lengths, or (with a camera) an
// observation without corners.
HandEyeResult CalibrateHandEye(const std::vector<HandEyeObservation>& observations, const HandEyeOptions& options = {},
                               const Camera* camera = nullptr);

}  // namespace lt
