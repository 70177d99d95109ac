// A 2D pattern projector (e.g. a DOE dot pattern or a structured-light slide):
// a monochromatic point source whose radiant intensity follows an image.
//
// Projector frame as a camera (OpenCV): +z forward, x right, y down; pattern
// pixel (0, 0) is the top-left one and its centre is at image coordinate (0, 0).
// The pattern's W x H pixels span the horizontal and vertical fields of view:
// a direction (x, y, z), z > 0, falls on image coordinate
//   u = fx·x/z + cx, v = fy·y/z + cy,  fx = W / (2 tan(hfov/2)), cx = (W − 1)/2
// (fy, cy likewise; fy = fx when the vertical fov is not given, i.e. square pattern
// pixels). Pattern pixel j receives the fraction w_j / Σw of the power (w_j: the
// mean of its channels), spread uniformly in intensity over the exact solid angle
// Ω_j of the pixel's rectangle: I = P·w_j / (Σw · Ω_j), nearest pixel, 0 outside.
// So ∫ I dΩ = P exactly.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/image.h"
#include "core/pose.h"

namespace lt {

struct PatternProjectorParams {
  Image<float> pattern;  // non-negative weights, any number of channels
  double horizontal_fov_rad = 0.0;
  double vertical_fov_rad = 0.0;  // 0: from the aspect ratio (square pattern pixels)
  double power_w = 5e-3;
  double wavelength_m = 650e-9;
  Pose cam_from_projector = Pose::Identity();

  // Throws ParamError naming the key.
  void Check() const;
};

class PatternProjector {
 public:
  explicit PatternProjector(const PatternProjectorParams& params);  // checks params

  const PatternProjectorParams& params() const { return params_; }
  double power_w() const { return params_.power_w; }
  double wavelength_m() const { return params_.wavelength_m; }
  const Pose& cam_from_projector() const { return params_.cam_from_projector; }
  Pose projector_from_cam() const { return params_.cam_from_projector.inverse(); }
  Eigen::Vector3d origin_in_cam() const { return params_.cam_from_projector.translation(); }
  int width() const { return params_.pattern.width; }
  int height() const { return params_.pattern.height; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }

  // Radiant intensity (W/sr) toward a direction in the projector frame.
  double RadiantIntensity(const Eigen::Vector3d& dir_in_projector) const;
  // Same, toward a point (identical for a point source; for interface symmetry with LaserProjector).
  double RadiantIntensityAt(const Eigen::Vector3d& p_in_projector) const { return RadiantIntensity(p_in_projector); }
  // Irradiance (W/m²) on a surface at p with unit normal n, both in the camera frame.
  double IrradianceAt(const Eigen::Vector3d& p_in_cam, const Eigen::Vector3d& normal_in_cam) const;
  // False when p (projector frame) lies outside the pattern or on a zero pixel.
  bool MayIlluminate(const Eigen::Vector3d& p_in_projector) const { return RadiantIntensity(p_in_projector) > 0; }
  // Solid angle (sr) of pattern pixel (i, j).
  double PixelSolidAngle(int i, int j) const;

 private:
  PatternProjectorParams params_;
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
  std::vector<float> intensity_;  // W/sr per pattern pixel
};

}  // namespace lt
