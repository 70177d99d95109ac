#include "sensor/pattern_projector.h"

#include <cmath>

#include "core/error.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

// Solid angle of the rectangle [0, x] x [0, y] on the plane z = 1 (signed).
double RectangleCorner(double x, double y) { return std::atan(x * y / std::sqrt(1.0 + x * x + y * y)); }

}  // namespace

void PatternProjectorParams::Check() const {
  if (pattern.empty()) throw ParamError("image", "the pattern image is empty");
  double sum = 0;
  for (float w : pattern.pixels) {
    if (!(w >= 0.0f) || !std::isfinite(w)) throw ParamError("image", "pattern values must be finite and >= 0");
    sum += w;
  }
  if (!(sum > 0)) throw ParamError("image", "the pattern is all zero");
  if (!(horizontal_fov_rad > 0 && horizontal_fov_rad < M_PI)) {
    throw ParamError("fov_deg", "horizontal field of view must be in (0, 180) deg");
  }
  if (!(vertical_fov_rad >= 0 && vertical_fov_rad < M_PI)) {
    throw ParamError("fov_deg", "vertical field of view must be in (0, 180) deg");
  }
  if (!(power_w > 0 && std::isfinite(power_w))) throw ParamError("power_mw", "must be > 0");
  if (!(wavelength_m > 0 && std::isfinite(wavelength_m))) throw ParamError("wavelength_nm", "must be > 0");
  const Eigen::Matrix3d& R = cam_from_projector.linear();
  double ortho = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho < 1e-6) || !(std::abs(R.determinant() - 1.0) < 1e-6) || !cam_from_projector.translation().allFinite()) {
    throw ParamError("cam_from_projector", "must be a rigid transform with a normalised rotation");
  }
}

PatternProjector::PatternProjector(const PatternProjectorParams& params) : params_(params) {
  params_.Check();
  const int w = params_.pattern.width, h = params_.pattern.height, ch = params_.pattern.channels;
  fx_ = w / (2.0 * std::tan(0.5 * params_.horizontal_fov_rad));
  fy_ = params_.vertical_fov_rad > 0 ? h / (2.0 * std::tan(0.5 * params_.vertical_fov_rad)) : fx_;
  cx_ = 0.5 * (w - 1);
  cy_ = 0.5 * (h - 1);
  if (!(0.5 * h / fy_ < 1e6)) throw ParamError("fov_deg", "vertical field of view is too wide");
  std::vector<double> weight(size_t(w) * size_t(h));
  double sum = 0;
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      double m = 0;
      for (int c = 0; c < ch; ++c) m += params_.pattern.At(i, j, c);
      weight[size_t(j) * size_t(w) + size_t(i)] = m / ch;
      sum += m / ch;
    }
  }
  intensity_.resize(weight.size());
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      size_t k = size_t(j) * size_t(w) + size_t(i);
      intensity_[k] = float(params_.power_w * weight[k] / (sum * PixelSolidAngle(i, j)));
    }
  }
}

double PatternProjector::PixelSolidAngle(int i, int j) const {
  double x1 = (i - 0.5 - cx_) / fx_, x2 = (i + 0.5 - cx_) / fx_;
  double y1 = (j - 0.5 - cy_) / fy_, y2 = (j + 0.5 - cy_) / fy_;
  return RectangleCorner(x2, y2) - RectangleCorner(x1, y2) - RectangleCorner(x2, y1) + RectangleCorner(x1, y1);
}

double PatternProjector::RadiantIntensity(const Eigen::Vector3d& d) const {
  if (!(d.z() > 0) || !d.allFinite()) return 0.0;
  double u = fx_ * d.x() / d.z() + cx_, v = fy_ * d.y() / d.z() + cy_;
  if (!(u >= -0.5 && u < width() - 0.5 && v >= -0.5 && v < height() - 0.5)) return 0.0;
  int i = std::min(width() - 1, int(std::floor(u + 0.5)));
  int j = std::min(height() - 1, int(std::floor(v + 0.5)));
  return intensity_[size_t(j) * size_t(width()) + size_t(i)];
}

double PatternProjector::IrradianceAt(const Eigen::Vector3d& p_in_cam, const Eigen::Vector3d& normal_in_cam) const {
  Eigen::Vector3d to_light = origin_in_cam() - p_in_cam;
  double r2 = to_light.squaredNorm();
  if (!(r2 > 0)) return 0.0;
  double cos_surface = normal_in_cam.dot(to_light) / std::sqrt(r2);
  if (!(cos_surface > 0)) return 0.0;
  return RadiantIntensity(projector_from_cam() * p_in_cam) * cos_surface / r2;
}

}  // namespace lt
