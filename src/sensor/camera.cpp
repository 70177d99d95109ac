#include "sensor/camera.h"

#include <cmath>
#include <limits>

#include "core/error.h"
#include "sensor/param_error.h"

namespace lt {

namespace {
bool Finite(double v) { return std::isfinite(v); }
}  // namespace

void CameraParams::Check() const {
  if (width <= 0 || height <= 0) {
    throw ParamError("resolution", "width and height must be > 0, got " + std::to_string(width) + " x " +
                                       std::to_string(height));
  }
  if (!(Finite(fx) && fx > 0)) throw ParamError("fx", "must be > 0, got " + FormatNumber(fx));
  if (!(Finite(fy) && fy > 0)) throw ParamError("fy", "must be > 0, got " + FormatNumber(fy));
  if (!Finite(cx)) throw ParamError("cx", "must be finite");
  if (!Finite(cy)) throw ParamError("cy", "must be finite");
  if (!(Finite(pixel_pitch_m) && pixel_pitch_m > 0)) {
    throw ParamError("pixel_pitch_um", "must be > 0, got " + FormatNumber(pixel_pitch_m * 1e6));
  }
  if (!(Finite(f_number) && f_number > 0)) throw ParamError("f_number", "must be > 0, got " + FormatNumber(f_number));
  if (focus_distance_m && !(Finite(*focus_distance_m) && *focus_distance_m > 0)) {
    throw ParamError("focus_distance_m", "must be > 0, got " + FormatNumber(*focus_distance_m));
  }
  const auto& b = brown_conrady;
  for (double k : {b.k1, b.k2, b.p1, b.p2, b.k3, fisheye.k1, fisheye.k2, fisheye.k3, fisheye.k4}) {
    if (!Finite(k)) throw ParamError("distortion", "coefficients must be finite");
  }
}

Camera::Camera(const CameraParams& params) : params_(params) {
  params_.Check();
  ImageBounds b;
  b.fx = params_.fx;
  b.fy = params_.fy;
  b.cx = params_.cx;
  b.cy = params_.cy;
  b.x_min = (-0.5 - params_.cx) / params_.fx;
  b.x_max = (params_.width - 0.5 - params_.cx) / params_.fx;
  b.y_min = (-0.5 - params_.cy) / params_.fy;
  b.y_max = (params_.height - 0.5 - params_.cy) / params_.fy;
  switch (params_.distortion) {
    case DistortionModel::kNone: break;
    case DistortionModel::kBrownConrady:
      distortion_ = LensDistortion::BrownConrady(params_.brown_conrady, b);
      break;
    case DistortionModel::kFisheye:
      distortion_ = LensDistortion::Fisheye(params_.fisheye, b);
      break;
  }
}

Eigen::Matrix3d Camera::K() const {
  Eigen::Matrix3d k;
  k << params_.fx, 0, params_.cx, 0, params_.fy, params_.cy, 0, 0, 1;
  return k;
}

bool Camera::InImage(const Eigen::Vector2d& p) const {
  return p.x() >= -0.5 && p.x() <= params_.width - 0.5 && p.y() >= -0.5 && p.y() <= params_.height - 0.5;
}

std::optional<Eigen::Vector2d> Camera::Project(const Eigen::Vector3d& p_in_cam) const {
  auto t = distortion_.Distort(p_in_cam);
  if (!t) return std::nullopt;
  return Eigen::Vector2d(params_.fx * t->x() + params_.cx, params_.fy * t->y() + params_.cy);
}

std::optional<Eigen::Vector3d> Camera::Unproject(const Eigen::Vector2d& pixel) const {
  Eigen::Vector2d t((pixel.x() - params_.cx) / params_.fx, (pixel.y() - params_.cy) / params_.fy);
  return distortion_.Undistort(t);
}

double Camera::focal_length_m() const {
  double v = image_distance_m();
  if (is_pinhole()) return v;
  double s = *params_.focus_distance_m;
  return v * s / (v + s);
}

double Camera::focus_distance_m() const {
  return is_pinhole() ? std::numeric_limits<double>::infinity() : *params_.focus_distance_m;
}

double Camera::CircleOfConfusionM(double depth_m) const {
  if (is_pinhole() || !(depth_m > 0)) return 0.0;
  double f = focal_length_m(), s = *params_.focus_distance_m;
  return aperture_diameter_m() * f * std::abs(depth_m - s) / (depth_m * (s - f));
}

Eigen::Vector2d ConcentricDisk(const Eigen::Vector2d& u) {
  double a = 2.0 * u.x() - 1.0, b = 2.0 * u.y() - 1.0;
  if (a == 0.0 && b == 0.0) return Eigen::Vector2d::Zero();
  double r, phi;
  if (std::abs(a) > std::abs(b)) {
    r = a;
    phi = M_PI / 4.0 * (b / a);
  } else {
    r = b;
    phi = M_PI / 2.0 - M_PI / 4.0 * (a / b);
  }
  return {r * std::cos(phi), r * std::sin(phi)};
}

std::optional<CameraRay> Camera::GenerateRay(const Eigen::Vector2d& pixel, const Eigen::Vector2d& lens_sample) const {
  auto d = Unproject(pixel);
  if (!d) return std::nullopt;
  CameraRay ray;
  ray.direction = *d;
  if (is_pinhole()) return ray;
  const double s = *params_.focus_distance_m;
  const double radius = 0.5 * aperture_diameter_m();
  Eigen::Vector2d disk = ConcentricDisk(lens_sample) * radius;
  Eigen::Vector3d focus_point;
  if (distortion_.model() == DistortionModel::kFisheye) {
    // Aperture facing the chief ray; focus on the sphere of radius S.
    Eigen::Vector3d helper = std::abs(d->x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    Eigen::Vector3d e1 = d->cross(helper).normalized();
    Eigen::Vector3d e2 = d->cross(e1);
    ray.origin = disk.x() * e1 + disk.y() * e2;
    focus_point = *d * s;
  } else {
    ray.origin = Eigen::Vector3d(disk.x(), disk.y(), 0.0);
    focus_point = *d * (s / d->z());
  }
  ray.direction = (focus_point - ray.origin).normalized();
  return ray;
}

double Camera::PixelSolidAngle(const Eigen::Vector2d& pixel) const {
  Eigen::Vector2d t((pixel.x() - params_.cx) / params_.fx, (pixel.y() - params_.cy) / params_.fy);
  return distortion_.SolidAngleDensity(t) / (params_.fx * params_.fy);
}

double Camera::RadianceToIrradiance(const Eigen::Vector2d& pixel) const {
  auto d = Unproject(pixel);
  if (!d) return 0.0;
  const double a = aperture_diameter_m();
  const double aperture_area = M_PI * a * a / 4.0;
  const double cos_theta = distortion_.model() == DistortionModel::kFisheye ? 1.0 : d->z();
  // PixelSolidAngle is per px²; divide by the pixel's area for per m² of sensor.
  return aperture_area * cos_theta * PixelSolidAngle(pixel) / pixel_area_m2();
}

}  // namespace lt
