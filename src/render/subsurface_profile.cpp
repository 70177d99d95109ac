#include "render/subsurface_profile.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace lt {
namespace {

// K0(z) for z > 0; 0 where exp(-z) underflows.
double BesselK0(double z) { return z > 700.0 ? 0.0 : std::cyl_bessel_k(0.0, z); }

}  // namespace

double BurleyShapeFactor(double a, DiffusionFit fit) {
  switch (fit) {
    case DiffusionFit::kPerpendicularMeanFreePath: {
      const double t = std::abs(a - 0.8);
      return 1.85 - a + 7.0 * t * t * t;
    }
    case DiffusionFit::kDiffuseTransmissionMeanFreePath:
      return 1.9 - a + 3.5 * (a - 0.8) * (a - 0.8);
    case DiffusionFit::kPerpendicularDiffuseMeanFreePath: {
      const double t = (a - 0.33) * (a - 0.33);
      return 3.5 + 100.0 * t * t;
    }
  }
  return 1.0;
}

void DiffusionProfileParams::Check(const std::string& where) const {
  if (!(albedo >= 0.0 && albedo <= 1.0)) {
    throw InputError(where, "albedo must be in [0, 1], got " + FormatNumber(albedo));
  }
  if (!(mean_free_path > 0.0) || !std::isfinite(mean_free_path)) {
    throw InputError(where, "mean free path must be > 0, got " + FormatNumber(mean_free_path));
  }
}

BurleyProfile::BurleyProfile(const DiffusionProfileParams& p)
    : albedo_(p.albedo), d_(p.mean_free_path / BurleyShapeFactor(p.albedo, p.fit)) {}

BurleyProfile BurleyProfile::FromShapeDistance(double albedo, double d) { return BurleyProfile(albedo, d); }

double BurleyProfile::Evaluate(double r) const {
  r = std::max(r, kMinRadiusFraction * d_);
  const double e = std::exp(-r / (3.0 * d_));
  return albedo_ * (e * e * e + e) / (8.0 * M_PI * d_ * r);
}

double BurleyProfile::Cdf(double r) const {
  if (r <= 0.0) return 0.0;
  // 1 - exp(-r/d)/4 - 3 exp(-r/(3d))/4 = (1 - exp(-r/d))/4 + 3 (1 - exp(-r/(3d)))/4,
  // with expm1 so that small r keeps its precision.
  return -0.25 * std::expm1(-r / d_) - 0.75 * std::expm1(-r / (3.0 * d_));
}

double BurleyProfile::RadialPdf(double r) const {
  if (r < 0.0) return 0.0;
  const double e = std::exp(-r / (3.0 * d_));
  return (e * e * e + e) / (4.0 * d_);
}

double BurleyProfile::LogRoot(double u) {
  u = std::clamp(u, 0.0, std::nextafter(1.0, 0.0));
  return std::log(2.0 * std::sinh(std::asinh(2.0 * (1.0 - u)) / 3.0));
}

double BurleyProfile::RadiusOfLogRoot(double log_root) const { return std::max(0.0, -3.0 * d_ * log_root); }

double BurleyProfile::SampleRadius(double u) const { return RadiusOfLogRoot(LogRoot(u)); }

double BurleyProfile::LineSpread(double x) const {
  const double ax = std::max(std::abs(x), kMinRadiusFraction * d_);
  return albedo_ * (BesselK0(ax / d_) + BesselK0(ax / (3.0 * d_))) / (4.0 * M_PI * d_);
}

double BurleyProfile::LineSpreadGaussian(double x, double sigma) const {
  if (!(sigma > 0.0)) return LineSpread(x);
  // G(x) = integral_0^inf LSF(s) [N(x - s) + N(x + s)] ds. Only s within 10
  // sigma of |x| contributes (the Gaussian is below e^-50 elsewhere).
  const double ax = std::abs(x);
  const double norm = 1.0 / (sigma * std::sqrt(2.0 * M_PI));
  auto gauss_pair = [&](double s) {
    const double a = (x - s) / sigma, b = (x + s) / sigma;
    return norm * (std::exp(-0.5 * a * a) + std::exp(-0.5 * b * b));
  };
  const double hi = ax + 10.0 * sigma;
  double lo = ax - 10.0 * sigma;
  double head = 0.0;
  if (lo <= 0.0) {
    // Below s0 << sigma, d the Gaussians are constant to (s0/sigma)^2 = 1e-12 and
    // LSF ~ -log: integral_0^s0 K0(s/c) ds = s0 (K0(s0/c) + 1) + O(s0^3 log s0).
    const double s0 = 1e-6 * std::min(d_, sigma);
    head = gauss_pair(0.0) * albedo_ / (4.0 * M_PI * d_) * s0 *
           (BesselK0(s0 / d_) + BesselK0(s0 / (3.0 * d_)) + 2.0);
    lo = s0;
  }
  // With s = exp(v), ds = s dv, the integrand is smooth in v and vanishes at
  // both ends, where the trapezoid rule converges geometrically; steps of a
  // third of the narrowest feature (sigma / s, d / s) at the largest s.
  const double h = std::min({0.25, sigma / (3.0 * hi), d_ / (3.0 * hi)});
  const double vlo = std::log(lo), vhi = std::log(hi);
  const int n = std::max(2, int(std::ceil((vhi - vlo) / h)));
  const double step = (vhi - vlo) / n;
  auto integrand = [&](double v) {
    const double s = std::exp(v);
    return s * LineSpread(s) * gauss_pair(s);
  };
  double sum = 0.5 * (integrand(vlo) + integrand(vhi));
  for (int k = 1; k < n; ++k) sum += integrand(vlo + k * step);
  return head + sum * step;
}

}  // namespace lt
