// The LED flood illuminator: a one-sided Lambertian rectangle of uniform
// radiance. LED frame: the rectangle lies in the x–y plane centred on the
// origin (width along x, height along y) and emits toward +z.
#pragma once

#include <Eigen/Core>
#include <array>

#include "core/pose.h"

namespace lt {

struct LedParams {
  double width_m = 0.01;
  double height_m = 0.01;
  // Radiance per broadband band (R, G, B), W/(m² sr) in each band.
  std::array<double, 3> radiance = {{100.0, 100.0, 100.0}};
  Pose cam_from_led = Pose::Identity();

  // Throws ParamError naming the key.
  void Check() const;
};

struct LedSample {
  Eigen::Vector3d p_in_cam;
  Eigen::Vector3d normal_in_cam;
  double pdf_area = 0;  // 1/(width·height), per m²
};

class Led {
 public:
  Led() : Led(LedParams{}) {}
  explicit Led(const LedParams& params);  // checks params

  const LedParams& params() const { return params_; }
  const std::array<double, 3>& radiance() const { return params_.radiance; }
  const Pose& cam_from_led() const { return params_.cam_from_led; }
  double area_m2() const { return params_.width_m * params_.height_m; }
  Eigen::Vector3d center_in_cam() const { return params_.cam_from_led.translation(); }
  Eigen::Vector3d normal_in_cam() const { return params_.cam_from_led.linear().col(2); }
  // Radiant flux per band: π·L·area (Lambertian, one-sided).
  std::array<double, 3> PowerW() const;

  // A point uniformly distributed on the rectangle for u in [0,1)².
  LedSample Sample(const Eigen::Vector2d& u) const;
  // Radiance leaving the LED in direction `dir_in_cam` (from the LED outward):
  // the configured radiance on the emitting side, 0 behind.
  std::array<double, 3> Radiance(const Eigen::Vector3d& dir_in_cam) const;

 private:
  LedParams params_;
};

}  // namespace lt
