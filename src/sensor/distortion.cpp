// Lens distortion models (sensor/distortion.h): the coefficients' forward maps, and
// LensDistortion's distortion, its iterative inverses and solid-angle density. The
// construction (where each model folds, the Brown–Conrady domain table) is in
// distortion_domain.cpp.
#include "sensor/distortion.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "sensor/param_error.h"

namespace lt {

namespace {

constexpr double kTolerancePx = 1e-9;    // round-trip tolerance of the inverse

double Det(const Eigen::Matrix2d& m) { return m(0, 0) * m(1, 1) - m(0, 1) * m(1, 0); }

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

// ---------------------------------------------------------------- Brown–Conrady

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
