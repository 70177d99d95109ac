// LensDistortion's construction (sensor/distortion.h): where each model is valid. The
// Brown–Conrady domain table (the radius of the first fold in each direction) and its
// reading (DomainRadius), the fisheye's θ_max, and the check that every pixel of the
// image border has a ray. Distortion and its inverses are in distortion.cpp.
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "sensor/distortion.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

constexpr int kDirections = 512;         // radial directions of the Brown–Conrady domain table
constexpr double kExtentFactor = 4.0;    // domain examined up to 4 image half-diagonals
constexpr double kMaxUndistortedRadius = 1e4;  // 89.994° off axis
constexpr int kFisheyeScanSteps = 8192;

// det(∂t/∂x) and |t| of Brown–Conrady at (x, y), in plain scalars (the domain
// scan evaluates it ~10^5 times per camera).
inline double BcDet(const BrownConradyCoeffs& c, double x, double y, double* t_norm) {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  const double g = 2.0 * c.k1 + r2 * (4.0 * c.k2 + 6.0 * c.k3 * r2);
  const double cross = g * x * y + 2.0 * c.p1 * x + 2.0 * c.p2 * y;
  const double a = radial + g * x * x + 2.0 * c.p1 * y + 6.0 * c.p2 * x;
  const double d = radial + g * y * y + 6.0 * c.p1 * y + 2.0 * c.p2 * x;
  if (t_norm) {
    const double tx = x * radial + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x);
    const double ty = y * radial + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y;
    *t_norm = std::sqrt(tx * tx + ty * ty);
  }
  return a * d - cross * cross;
}

std::string PixelText(const Eigen::Vector2d& t, const ImageBounds& b) {
  return "(" + FormatNumber(b.fx * t.x() + b.cx) + ", " + FormatNumber(b.fy * t.y() + b.cy) + ")";
}

double MaxCornerRadius(const ImageBounds& b) {
  double r = 0;
  for (double x : {b.x_min, b.x_max}) {
    for (double y : {b.y_min, b.y_max}) r = std::max(r, std::hypot(x, y));
  }
  return r;
}

}  // namespace

// ---------------------------------------------------------------- construction

LensDistortion LensDistortion::BrownConrady(const BrownConradyCoeffs& c, const ImageBounds& bounds) {
  LensDistortion d;
  d.pixel_scale_ = std::max(bounds.fx, bounds.fy);
  if (c.IsZero()) return d;  // identical to no distortion
  d.model_ = DistortionModel::kBrownConrady;
  d.bc_ = c;
  const double extent = MaxCornerRadius(bounds);
  const double limit = kExtentFactor * extent;
  const double h_min = 5e-3 * extent;
  d.domain_radius_.resize(kDirections);
  for (int k = 0; k < kDirections; ++k) {
    const double phi = 2.0 * M_PI * k / kDirections;
    const double ex = std::cos(phi), ey = std::sin(phi);
    double r = 0.0, t_norm = 0.0;
    for (;;) {
      // Steps of 0.5% of the image extent, growing to 2% of r far out.
      double r_next = r + std::max(h_min, 0.02 * r);
      if (BcDet(c, r_next * ex, r_next * ey, &t_norm) <= 0.0) {
        // Fold between r and r_next: bisect for the first zero of the determinant.
        double lo = r, hi = r_next;
        for (int i = 0; i < 60; ++i) {
          double mid = 0.5 * (lo + hi);
          (BcDet(c, mid * ex, mid * ey, nullptr) > 0.0 ? lo : hi) = mid;
        }
        Eigen::Vector2d fold = c.Distort(lo * Eigen::Vector2d(ex, ey));
        if (bounds.Contains(fold)) {
          throw ParamError("distortion",
                           "the distortion folds inside the image: its Jacobian determinant reaches 0 at "
                           "pixel " + PixelText(fold, bounds) +
                               ", so pixels beyond it would have two rays; use coefficients valid over "
                               "the whole image");
        }
        r = lo;
        break;
      }
      r = r_next;
      if (t_norm > limit || r >= kMaxUndistortedRadius) break;
    }
    d.domain_radius_[k] = r;
  }
  d.CheckBorder(bounds);
  return d;
}

LensDistortion LensDistortion::Fisheye(const KannalaBrandtCoeffs& c, const ImageBounds& bounds) {
  LensDistortion d;
  d.pixel_scale_ = std::max(bounds.fx, bounds.fy);
  d.model_ = DistortionModel::kFisheye;
  d.kb_ = c;
  // First zero of dθ_d/dθ in (0, π]: the fisheye folds there.
  double prev = 0.0;
  d.theta_max_ = M_PI;
  for (int i = 1; i <= kFisheyeScanSteps; ++i) {
    double theta = M_PI * i / kFisheyeScanSteps;
    double deriv;
    c.ThetaD(theta, &deriv);
    if (deriv <= 0.0) {
      double lo = prev, hi = theta;
      for (int j = 0; j < 60; ++j) {
        double mid = 0.5 * (lo + hi);
        c.ThetaD(mid, &deriv);
        (deriv > 0.0 ? lo : hi) = mid;
      }
      d.theta_max_ = lo;
      d.fisheye_folds_ = true;
      break;
    }
    prev = theta;
  }
  d.theta_d_max_ = c.ThetaD(d.theta_max_);
  if (!(d.theta_d_max_ > 0.0)) {
    throw ParamError("distortion", "the fisheye distortion maps every angle to the image centre");
  }
  if (d.fisheye_folds_ && MaxCornerRadius(bounds) >= d.theta_d_max_) {
    Eigen::Vector2d corner(std::abs(bounds.x_min) > std::abs(bounds.x_max) ? bounds.x_min : bounds.x_max,
                           std::abs(bounds.y_min) > std::abs(bounds.y_max) ? bounds.y_min : bounds.y_max);
    Eigen::Vector2d fold = corner.normalized() * d.theta_d_max_;
    throw ParamError("distortion",
                     "the fisheye distortion folds inside the image: dθ_d/dθ reaches 0 at θ = " +
                         FormatNumber(d.theta_max_ * 180.0 / M_PI) + " deg, pixel " + PixelText(fold, bounds) +
                         "; use coefficients that keep θ_d increasing over the image");
  }
  d.CheckBorder(bounds);
  return d;
}

// Every pixel on the image border must have a valid ray (fisheye: unless it lies
// outside the image circle of a fold-free lens, which simply sees nothing).
void LensDistortion::CheckBorder(const ImageBounds& b) const {
  const int n = 256;
  for (int side = 0; side < 4; ++side) {
    for (int i = 0; i <= n; ++i) {
      double s = double(i) / n;
      Eigen::Vector2d t;
      switch (side) {
        case 0: t = {b.x_min + s * (b.x_max - b.x_min), b.y_min}; break;
        case 1: t = {b.x_min + s * (b.x_max - b.x_min), b.y_max}; break;
        case 2: t = {b.x_min, b.y_min + s * (b.y_max - b.y_min)}; break;
        default: t = {b.x_max, b.y_min + s * (b.y_max - b.y_min)}; break;
      }
      if (model_ == DistortionModel::kFisheye && !fisheye_folds_ && t.norm() > theta_d_max_) continue;
      if (!Undistort(t)) {
        throw ParamError("distortion", "pixel " + PixelText(t, b) +
                                           " on the image border has no valid ray: the distortion is not "
                                           "invertible over the image");
      }
    }
  }
}

// ---------------------------------------------------------------- Brown–Conrady domain table

double LensDistortion::DomainRadius(double phi) const {
  double s = phi / (2.0 * M_PI) * kDirections;
  s -= std::floor(s / kDirections) * kDirections;
  int k0 = int(s) % kDirections;
  int k1 = (k0 + 1) % kDirections;
  double w = s - std::floor(s);
  return (1.0 - w) * domain_radius_[k0] + w * domain_radius_[k1];
}

}  // namespace lt
