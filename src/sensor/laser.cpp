#include "sensor/laser.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

constexpr double kDeg = M_PI / 180.0;

void CheckRotation(const Pose& pose, const std::string& key) {
  const Eigen::Matrix3d& R = pose.linear();
  double ortho = (R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(ortho < 1e-6) || !(std::abs(R.determinant() - 1.0) < 1e-6) || !pose.translation().allFinite()) {
    throw ParamError(key, "must be a rigid transform with a normalised rotation (R·Rᵀ deviates from I by " +
                              FormatNumber(ortho) + ")");
  }
}

}  // namespace

std::vector<double> EvenSheetAngles(int n, double spacing_rad) {
  std::vector<double> a(size_t(std::max(n, 0)));
  for (int k = 0; k < n; ++k) a[size_t(k)] = (k - 0.5 * (n - 1)) * spacing_rad;
  return a;
}

void LaserParams::Check() const {
  if (!(std::isfinite(power_w) && power_w > 0)) throw ParamError("power_mw", "must be > 0, got " + FormatNumber(power_w * 1e3));
  if (!(std::isfinite(wavelength_m) && wavelength_m > 0)) {
    throw ParamError("wavelength_nm", "must be > 0, got " + FormatNumber(wavelength_m * 1e9));
  }
  CheckRotation(cam_from_projector, "cam_from_projector");
  if (!(fan_angle_rad > 0 && fan_angle_rad <= 2 * M_PI)) {
    throw ParamError("fan_angle_deg", "must be in (0, 360], got " + FormatNumber(fan_angle_rad / kDeg));
  }
  if (gaussian_beam) {
    const auto& g = *gaussian_beam;
    if (!(std::isfinite(g.waist_m) && g.waist_m > 0)) throw ParamError("gaussian_beam/waist_um", "must be > 0");
    if (!(std::isfinite(g.rayleigh_range_m) && g.rayleigh_range_m > 0)) {
      throw ParamError("gaussian_beam/rayleigh_range_mm", "must be > 0");
    }
    if (!std::isfinite(g.waist_distance_m)) throw ParamError("gaussian_beam/waist_distance_mm", "must be finite");
    double far_sigma = g.waist_m / (2.0 * g.rayleigh_range_m);
    if (far_sigma > LaserProjector::kMaxSigmaRad) {
      throw ParamError("gaussian_beam", "far-field divergence 4·w0/(2·z_R) = " + FormatNumber(4 * far_sigma / kDeg) +
                                            " deg exceeds 40 deg");
    }
  } else if (!(divergence_rad > 0 && divergence_rad <= 4 * LaserProjector::kMaxSigmaRad + 1e-12)) {
    throw ParamError("divergence_deg", "must be in (0, 40], got " + FormatNumber(divergence_rad / kDeg));
  }
  if (sheet_angles_rad.empty()) throw ParamError("sheet_count", "must be >= 1, got 0");
  if (!sheet_power.empty() && sheet_power.size() != sheet_angles_rad.size()) {
    throw ParamError("sheet_power", "must have one value per sheet (" + std::to_string(sheet_angles_rad.size()) +
                                        "), got " + std::to_string(sheet_power.size()));
  }
  double sum = 0;
  for (size_t k = 0; k < sheet_power.size(); ++k) {
    if (!(std::isfinite(sheet_power[k]) && sheet_power[k] >= 0)) {
      throw ParamError("sheet_power/" + std::to_string(k), "must be >= 0");
    }
    sum += sheet_power[k];
  }
  if (!sheet_power.empty() && !(sum > 0)) throw ParamError("sheet_power", "must not be all zero");
  for (size_t k = 0; k < sheet_angles_rad.size(); ++k) {
    double a = sheet_angles_rad[k];
    if (!(std::abs(a) < 0.5 * M_PI)) {
      throw ParamError("sheet_angles_deg/" + std::to_string(k), "must be in (-90, 90), got " + FormatNumber(a / kDeg));
    }
    if (k > 0 && !(a > sheet_angles_rad[k - 1])) {
      throw ParamError("sheet_angles_deg/" + std::to_string(k), "sheet angles must increase");
    }
  }
}

LaserProjector::LaserProjector(const LaserParams& params) : params_(params) {
  params_.Check();
  if (params_.sheet_power.empty()) params_.sheet_power.assign(params_.sheet_angles_rad.size(), 1.0);
  double sum = std::accumulate(params_.sheet_power.begin(), params_.sheet_power.end(), 0.0);
  for (size_t k = 0; k < params_.sheet_angles_rad.size(); ++k) {
    double a = params_.sheet_angles_rad[k];
    sheet_power_w_.push_back(params_.power_w * params_.sheet_power[k] / sum);
    sheet_center_.emplace_back(0.0, std::sin(a), std::cos(a));
    sheet_normal_.emplace_back(0.0, std::cos(a), -std::sin(a));
  }
  if (params_.fan_profile == FanProfile::kFlatTop) {
    fan_norm_ = 1.0 / params_.fan_angle_rad;
  } else {
    double s = params_.fan_angle_rad / 4.0;
    fan_norm_ = 1.0 / (s * std::sqrt(2.0 * M_PI) * std::erf(M_PI / (s * std::sqrt(2.0))));
  }
}

Eigen::Vector3d LaserProjector::SheetDirection(int sheet) const { return sheet_center_.at(size_t(sheet)); }

double LaserProjector::Phi(int sheet, const Eigen::Vector3d& w) const {
  return std::atan2(w.x(), w.dot(sheet_center_[size_t(sheet)]));
}

double LaserProjector::Psi(int sheet, const Eigen::Vector3d& w) const {
  return std::asin(std::clamp(w.dot(sheet_normal_[size_t(sheet)]), -1.0, 1.0));
}

LaserProjector::SheetAngles LaserProjector::Angles(int sheet, const Eigen::Vector3d& w) const {
  return {Phi(sheet, w), Psi(sheet, w)};
}

Eigen::Vector3d LaserProjector::DirectionAt(int sheet, double phi, double psi) const {
  const Eigen::Vector3d& c = sheet_center_[size_t(sheet)];
  const Eigen::Vector3d& n = sheet_normal_[size_t(sheet)];
  return std::cos(psi) * (std::cos(phi) * c + std::sin(phi) * Eigen::Vector3d::UnitX()) + std::sin(psi) * n;
}

double LaserProjector::Fan(double phi) const {
  if (params_.fan_profile == FanProfile::kFlatTop) {
    return std::abs(phi) <= 0.5 * params_.fan_angle_rad ? fan_norm_ : 0.0;
  }
  double s = params_.fan_angle_rad / 4.0;
  return fan_norm_ * std::exp(-phi * phi / (2.0 * s * s));
}

double LaserProjector::Across(double psi, double sigma) const {
  double z = sigma * std::sqrt(2.0 * M_PI) * std::exp(-0.5 * sigma * sigma);
  return std::exp(-psi * psi / (2.0 * sigma * sigma)) / z;
}

double LaserProjector::SheetSigma(double r) const {
  if (!params_.gaussian_beam) return params_.divergence_rad / 4.0;
  const auto& g = *params_.gaussian_beam;
  if (std::isinf(r)) return g.waist_m / (2.0 * g.rayleigh_range_m);
  if (!(r > 0)) return kMaxSigmaRad;
  double u = (r - g.waist_distance_m) / g.rayleigh_range_m;
  double w = g.waist_m * std::sqrt(1.0 + u * u);
  return std::min(w / (2.0 * r), kMaxSigmaRad);
}

double LaserProjector::SheetIntensity(int sheet, const Eigen::Vector3d& dir) const {
  double n = dir.norm();
  if (!(n > 0) || !std::isfinite(n)) return 0.0;
  SheetAngles a = Angles(sheet, dir / n);
  return sheet_power_w_[size_t(sheet)] * Fan(a.phi) * Across(a.psi, SheetSigma(INFINITY));
}

double LaserProjector::RadiantIntensity(const Eigen::Vector3d& dir) const {
  double sum = 0;
  for (int k = 0; k < sheet_count(); ++k) sum += SheetIntensity(k, dir);
  return sum;
}

double LaserProjector::SheetIntensityAt(int sheet, const Eigen::Vector3d& p) const {
  double r = p.norm();
  if (!(r > 0) || !std::isfinite(r)) return 0.0;
  SheetAngles a = Angles(sheet, p / r);
  return sheet_power_w_[size_t(sheet)] * Fan(a.phi) * Across(a.psi, SheetSigma(r));
}

double LaserProjector::RadiantIntensityAt(const Eigen::Vector3d& p) const {
  double sum = 0;
  for (int k = 0; k < sheet_count(); ++k) sum += SheetIntensityAt(k, p);
  return sum;
}

double LaserProjector::IrradianceAt(const Eigen::Vector3d& p_in_cam, const Eigen::Vector3d& normal_in_cam) const {
  Eigen::Vector3d to_light = origin_in_cam() - p_in_cam;
  double r2 = to_light.squaredNorm();
  if (!(r2 > 0)) return 0.0;
  double cos_surface = normal_in_cam.dot(to_light) / std::sqrt(r2);
  if (!(cos_surface > 0)) return 0.0;
  Eigen::Vector3d p_in_projector = params_.cam_from_projector.inverse() * p_in_cam;
  return RadiantIntensityAt(p_in_projector) * cos_surface / r2;
}

double LaserProjector::SheetOffsetAngle(int sheet, const Eigen::Vector3d& dir) const {
  return Psi(sheet, dir.normalized());
}

double LaserProjector::FanHalfWidth(double k_sigma) const {
  return params_.fan_profile == FanProfile::kFlatTop ? 0.5 * params_.fan_angle_rad
                                                     : k_sigma * params_.fan_angle_rad / 4.0;
}

bool LaserProjector::MayIlluminate(const Eigen::Vector3d& p, double k_sigma) const {
  double r = p.norm();
  if (!(r > 0)) return true;
  double sigma = SheetSigma(r);
  Eigen::Vector3d w = p / r;
  for (int k = 0; k < sheet_count(); ++k) {
    // Across the sheet first: most points lie off every sheet.
    if (std::abs(Psi(k, w)) > k_sigma * sigma) continue;
    if (std::abs(Phi(k, w)) > FanHalfWidth(k_sigma)) continue;
    return true;
  }
  return false;
}

Plane LaserProjector::SheetPlaneInProjector(int sheet) const { return {sheet_normal_.at(size_t(sheet)), 0.0}; }

Plane LaserProjector::SheetPlane(int sheet) const {
  return SheetPlaneInProjector(sheet).Transformed(params_.cam_from_projector);
}

}  // namespace lt
