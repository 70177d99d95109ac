// The synthetic stripe renderer and the Gaussian kernels, checked against
// closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "pipeline/gaussian_filter.h"
#include "pipeline/synthetic_stripes.h"

namespace lt {
namespace {

TEST(SyntheticStripes, RowIntegralAndCentroidAreExact) {
  // Across a row, a line at angle a with profile A exp(-d^2 / 2s^2) integrates
  // to A s sqrt(2 pi) / cos(a); pixel integration preserves that sum, and
  // the intensity centroid of a row is the centre crossing (the profile is
  // symmetric along the row).
  for (double angle : {0.0, 20.0, 55.0}) {
    SyntheticFrame f;
    f.width = 200;
    f.height = 20;
    SyntheticStripe s;
    s.u0 = 100.3, s.v0 = 10, s.angle_rad = angle * M_PI / 180, s.sigma = 2.5, s.amplitude = 100;
    f.stripes.push_back(s);
    Image<float> img = RenderSyntheticFrame(f);
    for (int y = 0; y < f.height; ++y) {
      double sum = 0, sx = 0;
      for (int x = 0; x < f.width; ++x) sum += img.At(x, y), sx += x * double(img.At(x, y));
      EXPECT_NEAR(sum, 100 * 2.5 * std::sqrt(2 * M_PI) / std::cos(s.angle_rad), 1e-3 * sum) << angle;
      EXPECT_NEAR(sx / sum, s.CentreU(y), 1e-4) << angle;
    }
  }
}

TEST(SyntheticStripes, ArcDistanceAndNoise) {
  SyntheticStripe arc;
  arc.shape = SyntheticStripe::Shape::kArc;
  arc.cu = 0, arc.cv = 0, arc.radius = 100;
  double nx, ny;
  EXPECT_NEAR(arc.Distance(60, 80, &nx, &ny), 0, 1e-12);
  EXPECT_NEAR(arc.CentreU(80), 60, 1e-12);
  EXPECT_TRUE(std::isnan(arc.CentreU(120)));
  // Noise: deterministic and of the requested standard deviation (65536
  // samples: the sample standard deviation is within 1% with overwhelming
  // probability).
  SyntheticFrame f;
  f.width = 256;
  f.height = 256;
  f.noise_sigma = 3;
  Image<float> a = RenderSyntheticFrame(f), b = RenderSyntheticFrame(f);
  EXPECT_EQ(a.pixels, b.pixels);
  double s2 = 0;
  for (float v : a.pixels) s2 += double(v) * v;
  EXPECT_NEAR(std::sqrt(s2 / a.pixels.size()), 3.0, 0.03);
  Image<uint8_t> q = QuantizeImage<uint8_t>(a);
  EXPECT_EQ(*std::min_element(q.pixels.begin(), q.pixels.end()), 0);  // clamped, not wrapped
}

TEST(GaussianKernels, MomentsMatchTheContinuousDerivatives) {
  // Integrated kernels: sum k0 = 1, sum i k1(i) = -1 (first-derivative
  // moment: sum_i f(x - i) k1(i) = f'(x) for f linear), sum i^2 k2(i) / 2 = 1.
  // The kernels stop at 4 sigma + 1, which the i and i^2 weights magnify:
  // the moments are within 3e-3 (the zeroth within 1e-5). Symmetric stripes
  // are unaffected (truncation keeps the kernels' symmetry).
  for (double s : {0.7, 1.0, 2.5}) {
    GaussianKernels k(s);
    double m0 = 0, m1 = 0, m2 = 0;
    for (int i = -k.radius; i <= k.radius; ++i) {
      m0 += k.k0[i + k.radius];
      m1 += i * double(k.k1[i + k.radius]);
      m2 += 0.5 * i * i * double(k.k2[i + k.radius]);
    }
    EXPECT_NEAR(m0, 1, 1e-5) << s;
    EXPECT_NEAR(m1, -1, 3e-4) << s;
    EXPECT_NEAR(m2, 1, 3e-3) << s;
  }
}

TEST(GaussianKernels, SubpixelDerivativesOfAQuadratic) {
  // f(x, y) = x^2 + 3 x y - y^2 on a grid: smoothing a quadratic changes only
  // its constant term, so the derivatives at any point are exact:
  // fx = 2x + 3y, fy = 3x - 2y, fxx = 2, fxy = 3, fyy = -2 (with kernels long
  // enough, 8 sigma, that truncation is below the tolerances).
  Image<float> img(60, 60);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 60; ++x) img.At(x, y) = float(x * x + 3.0 * x * y - double(y) * y);
  const double px = 30.3, py = 28.8;
  SmoothedDerivatives d = SmoothedDerivativesAt(img.View(), px, py, 1.5, 12);
  EXPECT_NEAR(d.rx, 2 * px + 3 * py, 1e-3);
  EXPECT_NEAR(d.ry, 3 * px - 2 * py, 1e-3);
  EXPECT_NEAR(d.rxx, 2, 1e-4);
  EXPECT_NEAR(d.rxy, 3, 1e-4);
  EXPECT_NEAR(d.ryy, -2, 1e-4);
  EXPECT_EQ(MirrorIndex(-2, 10), 2);
  EXPECT_EQ(MirrorIndex(11, 10), 7);
  EXPECT_EQ(MirrorIndex(5, 1), 0);
}

}  // namespace
}  // namespace lt
