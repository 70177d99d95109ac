#include "sensor/led.h"

#include <cmath>

#include "core/error.h"
#include "sensor/param_error.h"

namespace lt {

void LedParams::Check() const {
  if (!(width_m > 0 && std::isfinite(width_m))) throw ParamError("size_m", "width must be > 0");
  if (!(height_m > 0 && std::isfinite(height_m))) throw ParamError("size_m", "height must be > 0");
  for (double l : radiance) {
    if (!(l >= 0 && std::isfinite(l))) throw ParamError("radiance_w_per_m2_sr", "must be >= 0");
  }
  const Eigen::Matrix3d& R = cam_from_led.linear();
  double ortho = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho < 1e-6) || !(std::abs(R.determinant() - 1.0) < 1e-6) || !cam_from_led.translation().allFinite()) {
    throw ParamError("cam_from_led", "must be a rigid transform with a normalised rotation");
  }
}

Led::Led(const LedParams& params) : params_(params) { params_.Check(); }

std::array<double, 3> Led::PowerW() const {
  std::array<double, 3> p;
  for (int b = 0; b < 3; ++b) p[size_t(b)] = M_PI * params_.radiance[size_t(b)] * area_m2();
  return p;
}

LedSample Led::Sample(const Eigen::Vector2d& u) const {
  Eigen::Vector3d p_in_led((u.x() - 0.5) * params_.width_m, (u.y() - 0.5) * params_.height_m, 0.0);
  return {params_.cam_from_led * p_in_led, normal_in_cam(), 1.0 / area_m2()};
}

std::array<double, 3> Led::Radiance(const Eigen::Vector3d& dir_in_cam) const {
  if (!(dir_in_cam.dot(normal_in_cam()) > 0)) return {{0.0, 0.0, 0.0}};
  return params_.radiance;
}

}  // namespace lt
