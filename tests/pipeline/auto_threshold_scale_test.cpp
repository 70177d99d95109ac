// The automatic threshold (pipeline/auto_threshold.h) on samples whose scale
// is not 1 DN of continuous light: 12-bit data stored MSB-aligned (a step of
// 16), linearized frames (--transfer: the curve's step), Bayer mosaics whose
// colours differ in noise, a background that varies (a slope, a texture, near
// full scale) and a stripe that crosses few lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pipeline/auto_threshold.h"
#include "pipeline/extract_transfer.h"
#include "pipeline/stripe_extractor.h"

namespace lt::test {
namespace {

ExtractionOptions Auto(ExtractionMethod m) {
  ExtractionOptions o;
  o.method = m;
  o.threshold_mode = ThresholdMode::kNoise;
  return o;
}

// A flat background of `level` steps with `rare` of the pixels one step
// higher (a nearly noise-free quantized frame), times `step`.
template <typename T>
Image<T> RareSteps(int level, double rare, int step, uint32_t seed, int w = 320, int h = 240) {
  Image<T> img(w, h);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (T& v : img.pixels) v = T((level + (u(rng) < rare ? 1 : 0)) * step);
  return img;
}

double Gauss(double x, double c, double s) { return std::exp(-0.5 * (x - c) * (x - c) / (s * s)); }

// 12-bit data MSB-aligned: the step (16) comes from the data, and the noise,
// floor and threshold are 16 times those of the LSB-aligned twin; neither
// gives a point (before: the MSB frame read its rare steps as noise-free
// stripes, 20 387 points on the reviewer's 320x240 frame).
TEST(AutoThresholdScale, MsbAlignedTwelveBitsScaleWithTheirStep) {
  const Image<uint16_t> lsb = RareSteps<uint16_t>(10, 0.05, 1, 3);
  const Image<uint16_t> msb = RareSteps<uint16_t>(10, 0.05, 16, 3);
  EXPECT_EQ(MeasureSampleScale(lsb.View()).step, 1);
  EXPECT_EQ(MeasureSampleScale(msb.View()).step, 16);
  for (auto m : {ExtractionMethod::kSteger, ExtractionMethod::kCom}) {
    SCOPED_TRACE(MethodName(m));
    StripeExtractor a(Auto(m)), b(Auto(m));
    EXPECT_TRUE(a.Extract(lsb.View()).empty());
    EXPECT_TRUE(b.Extract(msb.View()).empty());
    const NoiseThreshold& tl = *a.last_noise_threshold();
    const NoiseThreshold& tm = *b.last_noise_threshold();
    EXPECT_NEAR(tm.noise, 16 * tl.noise, 1e-3 * tm.noise + 1e-9);
    EXPECT_NEAR(tm.floor, 16 * tl.floor, 1e-9);
    EXPECT_NEAR(tm.threshold, 16 * tl.threshold, 1e-3 * tm.threshold);
  }
  // Gaussian noise of 0.8 steps reads the same in steps either way.
  Image<uint16_t> g(320, 240), g16(320, 240);
  std::mt19937 rng(5);
  std::normal_distribution<double> n(0, 0.8);
  for (size_t i = 0; i < g.pixels.size(); ++i) {
    g.pixels[i] = uint16_t(std::lround(100 + n(rng)));
    g16.pixels[i] = uint16_t(16 * g.pixels[i]);
  }
  const NoiseThreshold t1 = EstimateNoiseThreshold(g.View(), MeasureSampleScale(g.View()), true);
  const NoiseThreshold t16 = EstimateNoiseThreshold(g16.View(), MeasureSampleScale(g16.View()), true);
  EXPECT_NEAR(t1.noise, std::sqrt(0.64 + 1.0 / 12), 0.08 * std::sqrt(0.64 + 1.0 / 12));  // as AutoThreshold.EstimatesKnownGaussianNoise
  EXPECT_NEAR(t16.noise, 16 * t1.noise, 1e-3 * t16.noise);
}

// --transfer srgb linearizes 8-bit samples to floats, but they stay quantized:
// the step is the curve's at the background's code value, so the rare steps
// are noise with a floor (before: floats, noise 0, no floor, every rare step
// a stripe: 24 722 points on the reviewer's frame).
TEST(AutoThresholdScale, LinearizedFramesKeepTheirCodeStep) {
  const Image<uint8_t> img = RareSteps<uint8_t>(10, 0.05, 1, 7);
  for (Transfer tr : {Transfer::kSrgb, Transfer::kGamma}) {
    for (auto m : {ExtractionMethod::kSteger, ExtractionMethod::kCom, ExtractionMethod::kMax}) {
      SCOPED_TRACE(MethodName(m));
      ExtractionOptions o = Auto(m);
      o.transfer = tr;
      o.gamma = 2.2;
      StripeExtractor ex(o);
      EXPECT_TRUE(ex.Extract(img.View()).empty());
      const NoiseThreshold& t = *ex.last_noise_threshold();
      const double step = 255 * (DecodeTransfer(tr, 2.2, 10.5 / 255) - DecodeTransfer(tr, 2.2, 9.5 / 255));
      EXPECT_NEAR(t.step, step, 1e-6);
      EXPECT_GT(t.noise, 0);
      EXPECT_GE(t.threshold - t.background, 6 * step / std::sqrt(12.0) - 1e-9);
    }
  }
}

// A red-lit Bayer frame: R noise 6 DN, G and B 1.5 DN. Each colour's noise is
// taken on its own pixels: the red channel reads 6 (before: 1.97, pooled with
// G, and 480 noise points), green 1.5, their mean the worst pixel's
// sqrt(max over sites of sum w^2 share s^2).
TEST(AutoThresholdScale, BayerNoiseIsPerColour) {
  Image<uint8_t> img(320, 240);
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0, 1);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const double s = FilterChannel(ColorFilter::kRGGB, x, y) == 0 ? 6 : 1.5;
      img.Row(y)[x] = uint8_t(std::clamp(std::lround(60 + s * n(rng)), 0L, 255L));
    }
  }
  const double vr = 36 + 1.0 / 12, vg = 2.25 + 1.0 / 12;  // with the rounding
  const double mean = std::sqrt(std::max({vr + 0.5 * vg, 0.5 * vr + 1.5 * vg, 0.25 * vr + 1.25 * vg}) / 9);  // R, G, B sites
  for (int channel : {0, 1, -1}) {
    SCOPED_TRACE(channel);
    for (auto m : {ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
      ExtractionOptions o = Auto(m);
      o.bayer = ColorFilter::kRGGB;
      o.channel = channel;
      o.background_mode = BackgroundMode::kLocal;
      StripeExtractor ex(o);
      EXPECT_TRUE(ex.Extract(img.View()).empty());
      const double expected = channel == 0 ? std::sqrt(vr) : channel == 1 ? std::sqrt(vg) : mean;
      EXPECT_NEAR(ex.last_noise_threshold()->noise, expected, 0.05 * expected);
    }
  }
}

// A background that varies: its slope or texture adds its own height to the
// threshold, not 6 times it: on a 20..120 ramp (noise 2) it lies 3-9 sigma
// above the ramp's top (before: b + 6 x spread, 244); on an LED checker 60/180
// with a saturating stripe it stays under the stripe, found in every row
// (before: 841 on the reviewer's frame, nothing found; the default found it).
TEST(AutoThresholdScale, SlopeAndTextureAreNotMultiplied) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0, 2);
  const int W = 320, H = 96;
  Image<uint8_t> ramp(W, H), checker(W, H);
  for (int y = 0; y < H; ++y) {
    const double c = 280.3 + 0.05 * y;
    for (int x = 0; x < W; ++x) {
      const double r = 20 + 100.0 * x / W + n(rng) + 60 * Gauss(x, c, 2);
      ramp.Row(y)[x] = uint8_t(std::clamp(std::lround(r), 0L, 255L));
      const double k = ((x / 16 + y / 16) % 2 ? 60 : 180) + n(rng) + 200 * Gauss(x, 183.8, 2);  // mid-square
      checker.Row(y)[x] = uint8_t(std::clamp(std::lround(k), 0L, 255L));
    }
  }
  const NoiseThreshold t = EstimateNoiseThreshold(ramp.View(), MeasureSampleScale(ramp.View()), false);
  EXPECT_EQ(t.from, NoiseThreshold::From::kSpread);
  EXPECT_GT(t.threshold, 120 + 3 * 2);  // above the ramp's top (its last window's median is 4 below it) and its noise
  EXPECT_LT(t.threshold, 120 + 9 * 2);
  // On the ramp the stripe stands above the threshold, but a level background
  // (0) makes its half-height width the ramp's: --background local finds it
  // (AutoThreshold.AmbientLightWithLocalBackground). On the checker the
  // threshold stays under the saturated stripe: every row.
  for (auto m : {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
    SCOPED_TRACE(MethodName(m));
    StripeExtractor ex(Auto(m));
    const std::vector<StripePoint> pts = ex.Extract(checker.View());
    EXPECT_EQ(int(pts.size()), H) << DescribeNoiseThreshold(*ex.last_noise_threshold());
    for (const StripePoint& p : pts) EXPECT_NEAR(p.u, 183.8, 1.0) << p.v;
  }
  // A background reaching near full scale: the threshold stays one step under it.
  Image<uint8_t> bright(W, H);
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) bright.Row(y)[x] = uint8_t(std::clamp(std::lround(20 + 230.0 * x / W + 2 * n(rng)), 0L, 255L));
  }
  const NoiseThreshold c = EstimateNoiseThreshold(bright.View(), MeasureSampleScale(bright.View()), false);
  EXPECT_EQ(c.from, NoiseThreshold::From::kFullScale);
  EXPECT_EQ(c.threshold, 254);
}

// Noise-free float: a stripe in 20 of 240 rows, a faint glow (0.2% of it) in
// the others. The peak floor comes from the lines that hold a peak, so the
// glow stays under it (before: the 90th percentile of all lines' maxima was
// the glow's, and 220 points lay on it).
TEST(AutoThresholdScale, AStripeOnFewLinesSetsThePeakFloor) {
  Image<float> img(320, 240);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      img.Row(y)[x] = float(y < 20 ? Gauss(x, 160.3 + 0.1 * y, 2) : 0.002 * Gauss(x, 100, 20));
    }
  }
  for (auto m : {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
    SCOPED_TRACE(MethodName(m));
    StripeExtractor ex(Auto(m));
    const std::vector<StripePoint> pts = ex.Extract(img.View());
    EXPECT_EQ(ex.last_noise_threshold()->from, NoiseThreshold::From::kPeak);
    EXPECT_NEAR(ex.last_noise_threshold()->peak, 1.0, 0.01);
    EXPECT_EQ(pts.size(), 20u);
    for (const StripePoint& p : pts) EXPECT_LT(p.v, 20);
  }
}

}  // namespace
}  // namespace lt::test
