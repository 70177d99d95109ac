// The starting point of a camera calibration (pipeline/calib_camera.h,
// docs/calibration.md): Zhang's closed-form intrinsics from the views'
// homographies, and for a fisheye the start of an equidistant lens.
// EstimateHomography and PoseFromHomography (calib_camera.h) are defined
// with them, in calib_camera_start.cpp.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "pipeline/calib_camera.h"

namespace lt {

// Zhang's closed form with zero skew from homographies target (x, y) ->
// pixels; false when the image of the absolute conic is not positive definite
// (views too close to parallel to the image plane, or too few).
bool ClosedFormIntrinsics(const std::vector<Eigen::Matrix3d>& homographies, int width, int height,
                          Eigen::Matrix3d* k);

// The start of a fisheye calibration: the lens taken as equidistant about the
// image centre (the sensor's Kannala–Brandt model with k1..k4 = 0), its focal
// length the one whose lifted corners fit a homography per view best. Returns
// K = [f 0 cx; 0 f cy] and per view the homography of the lifted corners as
// seen through K; false when no focal length fits every view.
bool FisheyeStart(const std::vector<CalibrationView>& views, int width, int height, Eigen::Matrix3d* k,
                  std::vector<Eigen::Matrix3d>* lifted_homographies);

}  // namespace lt
