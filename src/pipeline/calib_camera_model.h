// The camera model as CalibrateCamera (calib_camera.h) refines it: the layout of its
// state vector (intrinsics, distortion, one pose per view), the parameters a state
// holds, and one view's reprojection residuals. Internal to calib_camera.cpp; defined
// in calib_camera_model.cpp.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "pipeline/calib_camera.h"

namespace lt::calib_camera_detail {

int DistortionCount(DistortionModel m);

// The names of the intrinsics in state order: fx fy cx cy, then the distortion's.
std::vector<std::string> ParamNames(DistortionModel m);

// State layout: [fx fy cx cy | distortion | pose_0 (rvec, t) | pose_1 | ...].
struct Layout {
  DistortionModel model;
  int intrinsic_count;            // 4 + distortion count
  std::vector<int> free_intrinsics;  // state indices of the free intrinsics
  int views;
  int PoseOffset(int v) const { return intrinsic_count + 6 * v; }
  int StateSize() const { return intrinsic_count + 6 * views; }
  int TangentSize() const { return int(free_intrinsics.size()) + 6 * views; }
  int TangentPose(int v) const { return int(free_intrinsics.size()) + 6 * v; }
};

CameraParams ParamsFromState(const Layout& l, const Eigen::VectorXd& x, int width, int height);

// Residuals (projection − detection, pixels) of one view into out[0 .. 2n).
bool ViewResiduals(const CameraParams& p, const Pose& cam_from_target, const CalibrationView& view, double* out);

}  // namespace lt::calib_camera_detail
