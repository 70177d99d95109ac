// Camera calibration from views of a planar target (docs/calibration.md):
// Zhang's closed form (a homography per view, the intrinsics from the image of
// the absolute conic with zero skew, the extrinsics from K⁻¹H), then
// Levenberg–Marquardt on the reprojection error of every corner over the
// intrinsics, the distortion coefficients and all view poses.
//
// Models: pinhole with Brown–Conrady distortion (fx fy cx cy k1 k2 p1 p2 k3, OpenCV
// order; k3 and the tangential pair can be held at zero), pinhole without
// distortion, and fisheye (Kannala–Brandt k1..k4, OpenCV's cv::fisheye).
//
// The result carries its uncertainty: the RMS reprojection error, and standard
// deviations of every parameter from C = σ²(JᵀJ)⁻¹ with σ² the a-posteriori
// variance of one corner coordinate. It is refused, with the reason, on
// degenerate input: fewer than min_views views, a view with too few corners or
// collinear corners, a non-planar target, closed-form intrinsics that do not
// exist (views too close to parallel to the image plane), parameters that the
// data do not determine (a singular normal matrix, or a focal length whose
// relative standard deviation exceeds max_relative_focal_std), a distortion
// that folds inside the image (a fisheye: inside the field the boards observed,
// plus fisheye_field_margin_deg), or an optimisation that does not converge.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/calib_geometry.h"
#include "sensor/camera.h"

namespace lt {

// One image of the target: corner positions in the target frame (z = 0,
// metres) and where they were detected (pixels), in the same order.
struct CalibrationView {
  std::vector<Eigen::Vector3d> target_points;
  std::vector<Eigen::Vector2d> pixels;
};

struct CameraCalibrationOptions {
  DistortionModel model = DistortionModel::kBrownConrady;
  // Brown–Conrady: hold k3 at 0. With it free, a fit whose distortion folds
  // inside the image is made again with k3 at 0 (CameraCalibrationResult::note).
  bool fix_k3 = false;
  bool fix_tangential = false;  // Brown–Conrady: hold p1, p2 at 0
  // Fisheye: k1..k<n> are fitted, the rest held at 0 (4: all). A fit whose
  // distortion folds beyond the field the boards observed (plus the margin)
  // but inside the image is made again with one coefficient fewer
  // (CameraCalibrationResult::note); one that folds within that field is refused.
  int fisheye_coefficients = 4;
  double fisheye_field_margin_deg = 10;
  int min_views = 3;
  int min_points_per_view = 6;
  // Refuse when σ(fx)/fx or σ(fy)/fy exceeds this (the data barely determine the focal length).
  double max_relative_focal_std = 0.02;
  int max_iterations = 200;

  // Throws lt::InputError ("option <name>: ...") on invalid values.
  void Check() const;
};

struct CameraCalibrationResult {
  bool ok = false;
  std::string reason;  // why the calibration was refused (empty when ok)
  std::string note;    // what the calibration decided on its own (k3 held at 0), else empty
  // The field the fit rests on: the largest angle between the optical axis and
  // the ray of a corner (radians), and the distorted normalised radius
  // |((u − cx)/fx, (v − cy)/fy)| of the farthest corner. Beyond it the
  // distortion is extrapolated.
  double observed_field_rad = 0;
  double observed_radius = 0;

  // Width, height, fx, fy, cx, cy and the distortion; the other fields keep
  // their defaults.
  CameraParams camera;
  double rms_px = 0;                // RMS reprojection error over all corner coordinates (x and y)
  std::vector<double> view_rms_px;  // per view
  double sigma_px = 0;              // a-posteriori σ of one corner coordinate (RMS corrected for the fitted parameters)
  std::vector<Pose> cam_from_target;  // per view
  std::vector<Vector6d> pose_std;     // per view: rotation (rad, left perturbation) and translation (m)

  // fx fy cx cy and the model's distortion coefficients in OpenCV order.
  std::vector<std::string> param_names;
  Eigen::VectorXd params;
  Eigen::VectorXd param_std;  // 0 for coefficients held fixed
  Eigen::MatrixXd param_covariance;

  std::vector<Pose> closed_form_cam_from_target;
  double closed_form_fx = 0, closed_form_fy = 0, closed_form_cx = 0, closed_form_cy = 0;
  int iterations = 0;
  std::string solver_message;
};

// Calibrates a camera of the given image size from >= min_views views. Throws
// lt::InputError only for invalid options or a view whose two lists differ in
// length; every other problem is a refusal in the result.
CameraCalibrationResult CalibrateCamera(const std::vector<CalibrationView>& views, int width, int height,
                                        const CameraCalibrationOptions& options = {});

// The pixel of a point in the camera frame under the model of `params` (no
// domain check beyond z > 0 for pinhole models); false when it has none.
bool ProjectWithModel(const CameraParams& params, const Eigen::Vector3d& p_in_cam, Eigen::Vector2d* pixel);

// Homography (3x3, h33 = 1) mapping target (x, y) to pixels by the normalised
// DLT (Hartley); false for fewer than 4 points or a degenerate configuration.
bool EstimateHomography(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to,
                        Eigen::Matrix3d* homography);

// The target's pose from its homography H ~ K [r1 r2 t] (Zhang's extrinsics,
// the rotation orthonormalised, the target in front of the camera).
Pose PoseFromHomography(const Eigen::Matrix3d& camera_matrix, const Eigen::Matrix3d& homography);

}  // namespace lt
