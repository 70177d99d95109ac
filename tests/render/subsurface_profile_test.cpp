#include "render/subsurface_profile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "chi_square.h"
#include "core/error.h"
#include "core/random.h"

namespace lt {
namespace {

// Integral of f over [lo, hi] (0 < lo) by Simpson's rule in v = log(s),
// ds = s dv: accurate for integrands with log or 1/s behaviour at 0 and
// exponential tails. n (even) intervals.
double IntegrateLog(const std::function<double(double)>& f, double lo, double hi, int n = 20000) {
  const double a = std::log(lo), b = std::log(hi), h = (b - a) / n;
  double sum = 0;
  for (int k = 0; k <= n; ++k) {
    const double s = std::exp(a + k * h);
    sum += (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0)) * f(s) * s;
  }
  return sum * h / 3;
}

// PLA-like: albedo 0.8, mean free path 0.5 mm.
BurleyProfile Pla() {
  DiffusionProfileParams p;
  p.albedo = 0.8;
  p.mean_free_path = 0.5e-3;
  return BurleyProfile(p);
}

TEST(BurleyProfile, ShapeDistanceFromMeanFreePath) {
  // d = l / s(A); at A = 0.8 the perpendicular fit gives s = 1.05.
  EXPECT_NEAR(Pla().d(), 0.5e-3 / 1.05, 1e-15);
  EXPECT_NEAR(BurleyShapeFactor(0.8, DiffusionFit::kDiffuseTransmissionMeanFreePath), 1.1, 1e-12);
  EXPECT_NEAR(BurleyShapeFactor(0.33, DiffusionFit::kPerpendicularDiffuseMeanFreePath), 3.5, 1e-12);
  // Every fit is positive over [0, 1], so d is finite.
  for (double a = 0; a <= 1.0; a += 0.01) {
    for (DiffusionFit fit : {DiffusionFit::kPerpendicularMeanFreePath, DiffusionFit::kDiffuseTransmissionMeanFreePath,
                             DiffusionFit::kPerpendicularDiffuseMeanFreePath}) {
      EXPECT_GT(BurleyShapeFactor(a, fit), 0.8);
    }
  }
}

// integral of 2 pi r R(r) dr over [0, inf) = A, to 1e-4 (the brief's bound;
// the quadrature reaches 1e-9). Lower limit 1e-12 d: the part below is 1e-12 A.
TEST(BurleyProfile, TotalReflectanceIsAlbedo) {
  for (double albedo : {0.2, 0.8, 1.0}) {
    const BurleyProfile p = BurleyProfile::FromShapeDistance(albedo, 2e-4);
    const double total =
        IntegrateLog([&](double r) { return 2 * M_PI * r * p.Evaluate(r); }, 1e-12 * p.d(), 200 * p.d());
    EXPECT_NEAR(total, albedo, 1e-4);
    EXPECT_NEAR(total, albedo, 1e-8);
  }
}

// The closed-form CDF equals the integral of the radial pdf, and the pdf is
// 2 pi r R / A.
TEST(BurleyProfile, CdfIsIntegralOfPdf) {
  const BurleyProfile p = Pla();
  for (double k : {0.01, 0.3, 1.0, 3.0, 10.0, 40.0}) {
    const double r = k * p.d();
    const double integral = IntegrateLog([&](double s) { return p.RadialPdf(s); }, 1e-12 * p.d(), r);
    EXPECT_NEAR(p.Cdf(r), integral, 1e-9) << k;
    EXPECT_NEAR(p.RadialPdf(r), 2 * M_PI * r * p.Evaluate(r) / p.albedo(), 1e-9 * p.RadialPdf(r));
  }
  EXPECT_EQ(p.Cdf(0), 0.0);
  EXPECT_NEAR(p.Cdf(1e3 * p.d()), 1.0, 1e-15);
  EXPECT_NEAR(p.RadialPdf(0), 1 / (2 * p.d()), 1e-9 / p.d());
}

TEST(BurleyProfile, InverseCdfRoundTrips) {
  const BurleyProfile p = Pla();
  for (double u : {0.0, 1e-12, 1e-6, 0.1, 0.5, 0.9, 0.999, 1 - 1e-9, 1 - 1e-15}) {
    const double r = p.SampleRadius(u);
    ASSERT_TRUE(std::isfinite(r));
    EXPECT_NEAR(p.Cdf(r), u, 1e-12) << u;
  }
  for (double k : {1e-4, 0.01, 0.5, 1.0, 7.0, 60.0}) {
    const double r = k * p.d();
    EXPECT_NEAR(p.SampleRadius(p.Cdf(r)), r, 1e-9 * r) << k;
  }
  EXPECT_LT(p.SampleRadius(0.0), 1e-12 * p.d());
  EXPECT_TRUE(std::isfinite(p.SampleRadius(1.0)));
  EXPECT_GT(p.SampleRadius(1.0), 100 * p.d());
}

// The radius from a LogRoot taken once is SampleRadius to the bit, for any d.
TEST(BurleyProfile, RadiusOfLogRootIsSampleRadius) {
  for (double u : {0.0, 0.3, 0.999, 1.0}) {
    const double log_root = BurleyProfile::LogRoot(u);
    for (double d : {1e-5, 1.3e-4, 2e-3}) {
      const BurleyProfile p = BurleyProfile::FromShapeDistance(0.8, d);
      EXPECT_EQ(p.RadiusOfLogRoot(log_root), p.SampleRadius(u)) << u << " " << d;
    }
  }
}

// Radii drawn with SampleRadius(u) follow the radial pdf: chi-square over 40
// bins of width d/4 plus a tail bin, expected counts from the CDF; 200k samples.
TEST(BurleyProfile, SampledRadiiMatchPdf) {
  const BurleyProfile p = Pla();
  const int bins = 41, n = 200000;
  std::vector<double> observed(bins, 0.0), expected(bins, 0.0);
  Rng rng(99);
  for (int i = 0; i < n; ++i) {
    const double r = p.SampleRadius(rng.NextDouble());
    observed[std::min(bins - 1, int(r / (0.25 * p.d())))] += 1;
  }
  for (int b = 0; b < bins; ++b) {
    const double hi = b == bins - 1 ? INFINITY : (b + 1) * 0.25 * p.d();
    expected[b] = n * ((std::isinf(hi) ? 1.0 : p.Cdf(hi)) - p.Cdf(b * 0.25 * p.d()));
  }
  const test::ChiSquare chi = test::PearsonChiSquare(observed, expected);
  EXPECT_LT(chi.z, 4.0) << chi.statistic << " dof " << chi.dof;
}

// The closed form A (K0(x/d) + K0(x/3d)) / (4 pi d) equals the direct
// numerical integral of R(sqrt(x^2 + y^2)) over y, to 1e-7 relative.
TEST(BurleyProfile, LineSpreadMatchesNumericalIntegral) {
  const BurleyProfile p = Pla();
  for (double k : {0.001, 0.1, 1.0, 5.0, 20.0}) {
    const double x = k * p.d();
    const double numeric =
        2 * IntegrateLog([&](double y) { return p.Evaluate(std::hypot(x, y)); }, 1e-12 * p.d(), x + 200 * p.d());
    EXPECT_NEAR(p.LineSpread(x), numeric, 1e-7 * numeric) << k;
    EXPECT_EQ(p.LineSpread(-x), p.LineSpread(x));
  }
  EXPECT_TRUE(std::isfinite(p.LineSpread(0.0)));
  EXPECT_EQ(p.LineSpread(2.0), 0.0);  // 4000 d away: K0 underflows, the guard returns 0
}

// integral of LSF over x = A, to 1e-4 (reached: 1e-9).
TEST(BurleyProfile, LineSpreadIntegratesToAlbedo) {
  const BurleyProfile p = Pla();
  const double total = 2 * IntegrateLog([&](double x) { return p.LineSpread(x); }, 1e-12 * p.d(), 200 * p.d());
  EXPECT_NEAR(total, p.albedo(), 1e-4);
  EXPECT_NEAR(total, p.albedo(), 1e-8);
}

// The Gaussian-blurred line spread: integrates to A; tends to LSF for a narrow
// Gaussian (x >= 20 sigma: 1e-3 relative, the blur of the LSF's curvature);
// and matches a Monte Carlo simulation of a stripe: Gaussian offset across the
// line plus the x-component of a profile-distributed displacement. The MC
// histogram has 200k samples; chi-square criterion as elsewhere.
TEST(BurleyProfile, LineSpreadGaussian) {
  const BurleyProfile p = Pla();
  for (double sigma_over_d : {0.05, 0.5, 3.0}) {
    const double sigma = sigma_over_d * p.d();
    // Symmetric: integrate x > 0 twice, with the log rule from 1e-9 d.
    const double total =
        2 * IntegrateLog([&](double x) { return p.LineSpreadGaussian(x, sigma); }, 1e-9 * p.d(),
                         200 * p.d() + 20 * sigma, 120);
    EXPECT_NEAR(total, p.albedo(), 1e-5) << sigma_over_d;
  }
  const double narrow = 1e-3 * p.d();
  for (double k : {0.02, 0.2, 2.0}) {
    EXPECT_NEAR(p.LineSpreadGaussian(k * p.d(), narrow), p.LineSpread(k * p.d()), 1e-3 * p.LineSpread(k * p.d()));
  }
  EXPECT_EQ(p.LineSpreadGaussian(0.3 * p.d(), 0.0), p.LineSpread(0.3 * p.d()));

  const double sigma = 0.7 * p.d(), width = 0.2 * p.d();
  const int bins = 60, n = 200000;  // bins of x in [-6 d, 6 d), outside pooled
  std::vector<double> observed(bins + 1, 0.0), expected(bins + 1, 0.0);
  Rng rng(4);
  for (int i = 0; i < n; ++i) {
    const double r = p.SampleRadius(rng.NextDouble());
    const double x = sigma * rng.NextGaussian() + r * std::cos(2 * M_PI * rng.NextDouble());
    const int b = int(std::floor((x + 6 * p.d()) / width));
    observed[b >= 0 && b < bins ? b : bins] += 1;
  }
  double inside = 0;
  for (int b = 0; b < bins; ++b) {
    // Simpson's rule over each bin.
    const double a = -6 * p.d() + b * width;
    const double f = (p.LineSpreadGaussian(a, sigma) + 4 * p.LineSpreadGaussian(a + width / 2, sigma) +
                      p.LineSpreadGaussian(a + width, sigma)) *
                     width / 6;
    expected[b] = n * f / p.albedo();
    inside += f / p.albedo();
  }
  expected[bins] = n * (1 - inside);
  const test::ChiSquare chi = test::PearsonChiSquare(observed, expected);
  EXPECT_LT(chi.z, 4.0) << chi.statistic << " dof " << chi.dof;
}

TEST(BurleyProfile, ParamsCheck) {
  DiffusionProfileParams p;
  EXPECT_NO_THROW(p.Check("s.json: /materials/pla/subsurface"));
  p.mean_free_path = 0;
  try {
    p.Check("s.json: /materials/pla/subsurface");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "s.json: /materials/pla/subsurface: mean free path must be > 0, got 0");
  }
  p.mean_free_path = INFINITY;
  EXPECT_THROW(p.Check("x"), InputError);
  p.mean_free_path = 1e-3;
  p.albedo = 1.2;
  EXPECT_THROW(p.Check("x"), InputError);
  p.albedo = NAN;
  EXPECT_THROW(p.Check("x"), InputError);
}

}  // namespace
}  // namespace lt
