#include "sensor/distortion.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

constexpr int kDirections = 512;         // radial directions of the Brown–Conrady domain table
constexpr double kExtentFactor = 4.0;    // domain examined up to 4 image half-diagonals
constexpr double kMaxUndistortedRadius = 1e4;  // 89.994° off axis
constexpr double kTolerancePx = 1e-9;    // round-trip tolerance of the inverse
constexpr int kFisheyeScanSteps = 8192;

double Det(const Eigen::Matrix2d& m) { return m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0); }

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

const char* DistortionModelName(DistortionModel m) {
  switch (m) {
    case DistortionModel::kNone: return "none";
    case DistortionModel::kBrownConrady: return "brown_conrady";
    case DistortionModel::kFisheye: return "fisheye";
  }
  return "?";
}

OpenCvDistCoeffsProblem BrownConradyFromOpenCv(const std::vector<double>& d, BrownConradyCoeffs* c) {
  static const char* const kExtra[] = {"k4", "k5", "k6", "s1", "s2", "s3", "s4", "tauX", "tauY"};
  const size_t n = d.size();
  if (n != 4 && n != 5 && n != 8 && n != 12 && n != 14) {
    return {-1, "must have 4, 5, 8, 12 or 14 elements (OpenCV's k1 k2 p1 p2 [k3 [k4 k5 k6 [s1 s2 s3 s4 [tauX tauY]]]]), got " +
                    std::to_string(n)};
  }
  for (size_t i = 5; i < n; ++i) {
    if (d[i] != 0) {
      return {static_cast<int>(i),
              std::string(kExtra[i - 5]) + " is not modelled (only k1 k2 p1 p2 k3): must be 0, got " + FormatNumber(d[i])};
    }
  }
  *c = {d[0], d[1], d[2], d[3], n > 4 ? d[4] : 0.0};
  return {};
}

Eigen::Vector2d BrownConradyCoeffs::Distort(const Eigen::Vector2d& p, Eigen::Matrix2d* jacobian) const {
  const double x = p.x(), y = p.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
  if (jacobian) {
    const double g = 2.0 * k1 + r2 * (4.0 * k2 + 6.0 * k3 * r2);  // (∂radial/∂x) / x
    const double cross = g * x * y + 2.0 * p1 * x + 2.0 * p2 * y;
    (*jacobian)(0, 0) = radial + g * x * x + 2.0 * p1 * y + 6.0 * p2 * x;
    (*jacobian)(0, 1) = cross;
    (*jacobian)(1, 0) = cross;
    (*jacobian)(1, 1) = radial + g * y * y + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return {xd, yd};
}

double KannalaBrandtCoeffs::ThetaD(double theta, double* derivative) const {
  const double t2 = theta * theta;
  if (derivative) {
    *derivative = 1.0 + t2 * (3.0 * k1 + t2 * (5.0 * k2 + t2 * (7.0 * k3 + t2 * 9.0 * k4)));
  }
  return theta * (1.0 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))));
}

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

// ---------------------------------------------------------------- Brown–Conrady

double LensDistortion::DomainRadius(double phi) const {
  double s = phi / (2.0 * M_PI) * kDirections;
  s -= std::floor(s / kDirections) * kDirections;
  int k0 = int(s) % kDirections;
  int k1 = (k0 + 1) % kDirections;
  double w = s - std::floor(s);
  return (1.0 - w) * domain_radius_[k0] + w * domain_radius_[k1];
}

bool LensDistortion::InBcDomain(const Eigen::Vector2d& x) const {
  double r = x.norm();
  if (!(r <= DomainRadius(std::atan2(x.y(), x.x())))) return false;
  Eigen::Matrix2d J;
  bc_.Distort(x, &J);
  return Det(J) > 0.0;
}

// Newton's method with the analytic Jacobian and a backtracking line search on
// |D(x) - t|; stays where the Jacobian is positive. Returns true on convergence.
bool LensDistortion::NewtonBc(const Eigen::Vector2d& t, Eigen::Vector2d* x, int max_iterations) const {
  Eigen::Matrix2d J;
  Eigen::Vector2d f = bc_.Distort(*x, &J) - t;
  double fn = f.norm();
  for (int it = 0; it < max_iterations; ++it) {
    if (fn * pixel_scale_ < 1e-3 * kTolerancePx) return true;
    double det = Det(J);
    if (!(det > 0.0)) return false;
    Eigen::Vector2d step(( J(1, 1) * f.x() - J(0, 1) * f.y()) / det,
                         (-J(1, 0) * f.x() + J(0, 0) * f.y()) / det);
    double lambda = 1.0;
    bool improved = false;
    for (int ls = 0; ls < 40; ++ls, lambda *= 0.5) {
      Eigen::Vector2d xn = *x - lambda * step;
      Eigen::Matrix2d Jn;
      Eigen::Vector2d fnew = bc_.Distort(xn, &Jn) - t;
      double fnn = fnew.norm();
      if (fnn < fn && Det(Jn) > 0.0) {
        *x = xn;
        f = fnew;
        fn = fnn;
        J = Jn;
        improved = true;
        break;
      }
    }
    if (!improved) return fn * pixel_scale_ <= kTolerancePx;  // at machine precision
  }
  return fn * pixel_scale_ <= kTolerancePx;
}

std::optional<Eigen::Vector2d> LensDistortion::UndistortBc(const Eigen::Vector2d& t) const {
  const double rho = t.norm();
  if (rho == 0.0) return Eigen::Vector2d::Zero();
  // Start: the radial part alone, inverted along t's direction (bracketed Newton).
  const double phi = std::atan2(t.y(), t.x());
  const double r_hi = DomainRadius(phi);
  auto radial = [&](double r, double* deriv) {
    double r2 = r * r;
    *deriv = 1.0 + r2 * (3.0 * bc_.k1 + r2 * (5.0 * bc_.k2 + 7.0 * bc_.k3 * r2));
    return r * (1.0 + r2 * (bc_.k1 + r2 * (bc_.k2 + r2 * bc_.k3)));
  };
  double lo = 0.0, hi = r_hi, deriv;
  double r = std::min(rho, 0.5 * r_hi);
  if (radial(hi, &deriv) < rho) {
    r = 0.999 * hi;
  } else {
    for (int i = 0; i < 60; ++i) {
      double g = radial(r, &deriv) - rho;
      if (g < 0) lo = r; else hi = r;
      double rn = r - g / deriv;
      if (!(deriv > 0.0) || !(rn > lo && rn < hi)) rn = 0.5 * (lo + hi);
      if (std::abs(rn - r) < 1e-15 * (1.0 + r)) {
        r = rn;
        break;
      }
      r = rn;
    }
  }
  Eigen::Vector2d x = r * t / rho;
  bool ok = NewtonBc(t, &x, 50);
  if (!ok || !InBcDomain(x)) {
    // Fallback: continuation from the axis, following D(x) = s·t for s -> 1.
    x.setZero();
    ok = true;
    const int steps = 16;
    for (int s = 1; s <= steps && ok; ++s) {
      Eigen::Vector2d ts = t * (double(s) / steps);
      ok = NewtonBc(ts, &x, s == steps ? 60 : 8) || s < steps;
      if (!InBcDomain(x)) ok = false;
    }
    if (!ok) return std::nullopt;
  }
  if (!InBcDomain(x)) return std::nullopt;
  if ((bc_.Distort(x) - t).norm() * pixel_scale_ > kTolerancePx) return std::nullopt;
  return x;
}

// ---------------------------------------------------------------- fisheye

double LensDistortion::SolveTheta(double theta_d) const {
  double lo = 0.0, hi = theta_max_;
  double theta = std::min(theta_d, theta_max_);
  for (int i = 0; i < 100; ++i) {
    double deriv;
    double g = kb_.ThetaD(theta, &deriv) - theta_d;
    if (g == 0.0) return theta;
    if (g < 0) lo = theta; else hi = theta;
    double tn = theta - g / deriv;
    if (!(deriv > 0.0) || !(tn >= lo && tn <= hi)) tn = 0.5 * (lo + hi);
    if (std::abs(tn - theta) <= 1e-16 * (1.0 + theta)) return tn;
    theta = tn;
  }
  return theta;
}

// ---------------------------------------------------------------- public

std::optional<Eigen::Vector2d> LensDistortion::Distort(const Eigen::Vector3d& ray) const {
  if (!ray.allFinite()) return std::nullopt;
  switch (model_) {
    case DistortionModel::kNone: {
      if (!(ray.z() > 0.0)) return std::nullopt;
      return Eigen::Vector2d(ray.x() / ray.z(), ray.y() / ray.z());
    }
    case DistortionModel::kBrownConrady: {
      if (!(ray.z() > 0.0)) return std::nullopt;
      Eigen::Vector2d x(ray.x() / ray.z(), ray.y() / ray.z());
      if (!InBcDomain(x)) return std::nullopt;
      return bc_.Distort(x);
    }
    case DistortionModel::kFisheye: {
      double rho = std::hypot(ray.x(), ray.y());
      double theta = std::atan2(rho, ray.z());
      if (!(theta <= theta_max_) || (rho == 0.0 && !(ray.z() > 0.0))) return std::nullopt;
      if (rho == 0.0) return Eigen::Vector2d::Zero();
      double td = kb_.ThetaD(theta);
      return Eigen::Vector2d(td * ray.x() / rho, td * ray.y() / rho);
    }
  }
  return std::nullopt;
}

std::optional<Eigen::Vector3d> LensDistortion::Undistort(const Eigen::Vector2d& t) const {
  if (!t.allFinite()) return std::nullopt;
  switch (model_) {
    case DistortionModel::kNone:
      return Eigen::Vector3d(t.x(), t.y(), 1.0).normalized();
    case DistortionModel::kBrownConrady: {
      auto x = UndistortBc(t);
      if (!x) return std::nullopt;
      return Eigen::Vector3d(x->x(), x->y(), 1.0).normalized();
    }
    case DistortionModel::kFisheye: {
      double rho = t.norm();
      if (rho == 0.0) return Eigen::Vector3d::UnitZ();
      // At or beyond a fold the pixel is ambiguous or unreachable; beyond θ_d(π) it sees nothing.
      if (fisheye_folds_ ? !(rho < theta_d_max_) : !(rho <= theta_d_max_)) return std::nullopt;
      double theta = SolveTheta(rho);
      if (std::abs(kb_.ThetaD(theta) - rho) * pixel_scale_ > kTolerancePx) return std::nullopt;
      double s = std::sin(theta) / rho;
      return Eigen::Vector3d(s * t.x(), s * t.y(), std::cos(theta));
    }
  }
  return std::nullopt;
}

double LensDistortion::SolidAngleDensity(const Eigen::Vector2d& t) const {
  switch (model_) {
    case DistortionModel::kNone: {
      double q = 1.0 + t.squaredNorm();
      return 1.0 / (q * std::sqrt(q));
    }
    case DistortionModel::kBrownConrady: {
      auto x = UndistortBc(t);
      if (!x) return 0.0;
      Eigen::Matrix2d J;
      bc_.Distort(*x, &J);
      double q = 1.0 + x->squaredNorm();
      return 1.0 / (Det(J) * q * std::sqrt(q));
    }
    case DistortionModel::kFisheye: {
      double rho = t.norm();
      if (rho == 0.0) return 1.0;
      if (fisheye_folds_ ? !(rho < theta_d_max_) : !(rho <= theta_d_max_)) return 0.0;
      double theta = SolveTheta(rho);
      double deriv;
      kb_.ThetaD(theta, &deriv);
      // dΩ = sinθ dθ dφ, dA = θ_d dθ_d dφ.
      return std::sin(theta) / (rho * deriv);
    }
  }
  return 0.0;
}

}  // namespace lt
