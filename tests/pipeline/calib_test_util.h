// Shared fixtures of the calibration tests: the default rig's camera and a
// checkerboard with its poses.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/image.h"
#include "core/pose.h"
#include "pipeline/calib_checkerboard.h"
#include "sensor/camera.h"

namespace lt {

// The corner detection tests' 640x480 camera (f 800 px), with Brown-Conrady
// distortion or without.
inline Camera CornerTestCamera(bool distortion = true) {
  CameraParams p;
  p.width = 640;
  p.height = 480;
  p.fx = p.fy = 800;
  p.cx = 321.5;
  p.cy = 238.5;
  if (distortion) {
    p.distortion = DistortionModel::kBrownConrady;
    p.brown_conrady = {-0.15, 0.05, 2e-4, -1e-4, 0};
  }
  return Camera(p);
}

// The demo rig's camera (1280x1024, 4.8 um pixels, 8.9 mm), with mild barrel distortion.
inline Camera RigCamera() {
  CameraParams p;
  p.width = 1280;
  p.height = 1024;
  p.fx = p.fy = 1851.9;
  p.cx = 639.5;
  p.cy = 511.5;
  p.pixel_pitch_m = 4.8e-6;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.1, 0.05, 0, 0, 0};
  return Camera(p);
}

// A 640x480 camera with Brown-Conrady distortion (k1 k2 p1 p2 k3): the
// calibration tests' small camera.
inline CameraParams Camera640Params(const BrownConradyCoeffs& k) {
  CameraParams p;
  p.width = 640;
  p.height = 480;
  p.fx = 805;
  p.fy = 803;
  p.cx = 323.4;
  p.cy = 236.8;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = k;
  return p;
}

// A 7 x 10 inner-corner board of 6 mm squares.
inline CheckerboardSpec Board() {
  CheckerboardSpec b;
  b.rows = 7;
  b.cols = 10;
  b.square_m = 6e-3;
  return b;
}

// The board's centre at (ox, oy, z), tilted by `tilt` about an in-plane axis
// at angle `axis`, turned by `spin` about its normal.
inline Pose BoardPose(double ox, double oy, double z, double tilt, double axis, double spin) {
  const CheckerboardSpec b = Board();
  const Eigen::Vector3d centre(0.5 * (b.cols - 1) * b.square_m, 0.5 * (b.rows - 1) * b.square_m, 0);
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)) *
                Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(ox, oy, z) - p.linear() * centre;
  return p;
}

// Separable Gaussian blur of standard deviation `sigma` px (edges clamped).
inline Image<float> Blurred(const Image<float>& img, double sigma) {
  const int r = int(std::ceil(4 * sigma));
  std::vector<double> k(size_t(2 * r + 1));
  double sum = 0;
  for (int i = -r; i <= r; ++i) sum += k[size_t(i + r)] = std::exp(-0.5 * i * i / (sigma * sigma));
  for (double& v : k) v /= sum;
  Image<float> tmp(img.width, img.height, 1), out(img.width, img.height, 1);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double a = 0;
      for (int i = -r; i <= r; ++i) a += k[size_t(i + r)] * img.At(std::clamp(x + i, 0, img.width - 1), y);
      tmp.At(x, y) = float(a);
    }
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double a = 0;
      for (int i = -r; i <= r; ++i) a += k[size_t(i + r)] * tmp.At(x, std::clamp(y + i, 0, img.height - 1));
      out.At(x, y) = float(a);
    }
  return out;
}

}  // namespace lt
