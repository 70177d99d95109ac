#include "render/speckle.h"

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/random.h"

namespace lt {
namespace {

constexpr double kPitch = 3.45e-6, kLambda = 650e-9;

// Grains of lambda N = `grain_px` pixels, sampled at pixel centres.
SpeckleOptions PointOptions(double grain_px, double contrast = 1.0) {
  SpeckleOptions o;
  o.wavelength = kLambda;
  o.pixel_pitch = kPitch;
  o.f_number = grain_px * kPitch / kLambda;
  o.contrast = contrast;
  o.integrate_pixels = false;
  return o;
}

double Mean(const Image<float>& im) {
  double s = 0;
  for (float v : im.pixels) s += v;
  return s / im.pixels.size();
}

// Normalised autocovariance estimate Cov(I(x), I(x + (dx, dy))) / mean^2.
double Covariance(const Image<float>& im, int dx, int dy) {
  const double m = Mean(im);
  double s = 0;
  long n = 0;
  for (int y = 0; y + dy < im.height; ++y) {
    for (int x = 0; x + dx < im.width; ++x) {
      s += (im.At(x, y) - m) * (im.At(x + dx, y + dy) - m);
      ++n;
    }
  }
  return s / n / (m * m);
}

TEST(Speckle, ClosedForms) {
  const double ln = kLambda * 4.0;  // lambda N
  EXPECT_EQ(SpeckleIntensityCorrelation(0.0, kLambda, 4.0), 1.0);
  // First zero of J1 at v = 3.8317: r = 1.2197 lambda N.
  EXPECT_NEAR(SpeckleIntensityCorrelation(3.831705970207512 / M_PI * ln, kLambda, 4.0), 0.0, 1e-12);
  const double fwhm = SpeckleGrainFwhm(kLambda, 4.0);
  EXPECT_NEAR(fwhm / ln, 1.02899, 1e-5);
  EXPECT_NEAR(SpeckleIntensityCorrelation(fwhm / 2, kLambda, 4.0), 0.5, 1e-12);
  // Continuous at the small-argument branch.
  EXPECT_NEAR(SpeckleIntensityCorrelation(1e-6 * ln / M_PI, kLambda, 4.0),
              SpeckleIntensityCorrelation(1.0001e-6 * ln / M_PI, kLambda, 4.0), 1e-12);
}

// Pixel-area averaging: the quadrature of the triangle-weighted integral
// equals the definition, E[c_I(|u1 - u2 + lag|)] over two independent uniform
// points u1, u2 in a pixel, estimated with 60k pairs (standard error below
// 1e-3; bound 5e-3). Grains much larger than a pixel keep the contrast.
TEST(Speckle, PixelAveragedCovariance) {
  for (double grain_px : {0.53, 1.5}) {
    SpeckleOptions o = PointOptions(grain_px, 0.8);
    o.integrate_pixels = true;
    for (auto [dx, dy] : {std::pair{0, 0}, {1, 1}}) {
      Rng rng(uint64_t(grain_px * 100) + dx + 7 * dy);
      const int n = 60000;
      double sum = 0;
      for (int i = 0; i < n; ++i) {
        const double ux = dx + rng.NextDouble() - rng.NextDouble(), uy = dy + rng.NextDouble() - rng.NextDouble();
        sum += SpeckleIntensityCorrelation(kPitch * std::hypot(ux, uy), o.wavelength, o.f_number);
      }
      EXPECT_NEAR(SpeckleExpectedCovariance(o, dx, dy), 0.64 * sum / n, 5e-3) << grain_px << " " << dx;
    }
  }
  SpeckleOptions o = PointOptions(20.0);
  o.integrate_pixels = true;
  EXPECT_GT(SpeckleExpectedContrast(o), 0.99);
  EXPECT_LT(SpeckleExpectedContrast(o), 1.0);
}

// Fully developed speckle sampled at pixel centres, grains of lambda N = 4 px,
// 512 x 512 pixels. Over 20 seeds (measured): contrast 1 - 0.002 +- 0.004,
// FWHM / closed form 1.004 +- 0.005 (linear interpolation between lags adds
// +0.4%), covariance deviations below 0.012. Bounds: contrast 0.025,
// covariance 0.03, FWHM 3.5%.
TEST(Speckle, FullyDevelopedStatistics) {
  const SpeckleOptions o = PointOptions(4.0);
  const Image<float> im = GenerateSpeckle(512, 512, o, 1);
  ASSERT_EQ(im.width, 512);
  ASSERT_EQ(im.height, 512);
  EXPECT_NEAR(Mean(im), 1.0, 1e-5);  // normalised exactly, up to float sums
  for (float v : im.pixels) ASSERT_GE(v, 0.0f);
  const double c0 = Covariance(im, 0, 0);
  EXPECT_NEAR(std::sqrt(c0), 1.0, 0.025);
  std::vector<double> axis(9);
  for (int lag = 0; lag < 9; ++lag) {
    const double cx = Covariance(im, lag, 0), cy = Covariance(im, 0, lag);
    EXPECT_NEAR(cx, SpeckleExpectedCovariance(o, lag, 0), 0.03) << lag;
    EXPECT_NEAR(cy, SpeckleExpectedCovariance(o, 0, lag), 0.03) << lag;
    axis[lag] = 0.5 * (cx + cy) / c0;
  }
  EXPECT_NEAR(Covariance(im, 2, 2), SpeckleExpectedCovariance(o, 2, 2), 0.03);
  int lag = 0;
  while (axis[lag + 1] > 0.5) ++lag;
  const double half_width = lag + (axis[lag] - 0.5) / (axis[lag] - axis[lag + 1]);
  const double fwhm_px = SpeckleGrainFwhm(o.wavelength, o.f_number) / o.pixel_pitch;
  EXPECT_NEAR(2 * half_width / fwhm_px, 1.0, 0.035);
}

// The contrast setting blends toward 1: the same key gives 1 + C (I - 1).
// Std/mean is then C within 0.025 C (as above).
TEST(Speckle, ContrastSetting) {
  const Image<float> full = GenerateSpeckle(256, 200, PointOptions(3.0, 1.0), 5);
  const Image<float> half = GenerateSpeckle(256, 200, PointOptions(3.0, 0.4), 5);
  for (size_t i = 0; i < full.pixels.size(); ++i) {
    ASSERT_NEAR(half.pixels[i], 1.0f + 0.4f * (full.pixels[i] - 1.0f), 1e-5f);
  }
  const Image<float> big = GenerateSpeckle(512, 512, PointOptions(4.0, 0.4), 6);
  EXPECT_NEAR(std::sqrt(Covariance(big, 0, 0)), 0.4, 0.025 * 0.4);
  const Image<float> none = GenerateSpeckle(64, 48, PointOptions(3.0, 0.0), 5);
  for (float v : none.pixels) ASSERT_EQ(v, 1.0f);
}

// Pixel-area integration with grains smaller than a pixel (lambda = 650 nm,
// N = 2.8, pitch 3.45 um: lambda N = 0.53 px): the contrast and neighbour
// covariance match the pixel-averaged closed form. 192 x 192 pixels: the
// standard error of the contrast is about 0.005 (contrast 0.46, correlation
// area about one pixel), of the covariance 0.004; bounds 0.025 and 0.015.
TEST(Speckle, PixelIntegration) {
  SpeckleOptions o = PointOptions(0.0);
  o.f_number = 2.8;
  o.integrate_pixels = true;
  const Image<float> im = GenerateSpeckle(192, 192, o, 3);
  EXPECT_NEAR(Mean(im), 1.0, 1e-5);
  EXPECT_NEAR(SpeckleExpectedContrast(o), 0.459, 0.005);  // far below 1: many grains per pixel
  EXPECT_NEAR(std::sqrt(Covariance(im, 0, 0)), SpeckleExpectedContrast(o), 0.025);
  EXPECT_NEAR(Covariance(im, 1, 0), SpeckleExpectedCovariance(o, 1, 0), 0.015);
  EXPECT_NEAR(Covariance(im, 0, 1), SpeckleExpectedCovariance(o, 0, 1), 0.015);
}

TEST(Speckle, SameKeyIdenticalOtherKeyDifferent) {
  const SpeckleOptions o = PointOptions(2.5);
  const Image<float> a = GenerateSpeckle(200, 150, o, 42);
  Image<float> b;
  // One thread against the default pool: the result must not depend on it.
  tbb::task_arena single(1);
  single.execute([&] { b = GenerateSpeckle(200, 150, o, 42); });
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)), 0);
  const Image<float> c = GenerateSpeckle(200, 150, o, 43);
  size_t differ = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != c.pixels[i];
  EXPECT_GT(differ, a.pixels.size() * 99 / 100);
}

TEST(Speckle, BadOptions) {
  SpeckleOptions o = PointOptions(3.0);
  o.f_number = 0;
  try {
    o.Check("scene.json: /sensor/laser/speckle");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "scene.json: /sensor/laser/speckle: f_number must be > 0, got 0");
  }
  o = PointOptions(3.0, 1.5);
  EXPECT_THROW(o.Check("x"), InputError);
  o = PointOptions(3.0);
  o.wavelength = NAN;
  EXPECT_THROW(GenerateSpeckle(8, 8, o, 1), InputError);
  EXPECT_THROW(GenerateSpeckle(-1, 8, PointOptions(3.0), 1), InputError);
  EXPECT_EQ(GenerateSpeckle(0, 8, PointOptions(3.0), 1).pixels.size(), 0u);
  // Grains 100x smaller than a pixel need 200 samples per pixel: refused.
  o = PointOptions(0.01);
  o.integrate_pixels = true;
  EXPECT_THROW(GenerateSpeckle(1000, 1000, o, 1), InputError);
}

}  // namespace
}  // namespace lt
