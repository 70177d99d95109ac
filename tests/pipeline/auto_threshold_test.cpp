// The automatic threshold (--threshold auto, pipeline/auto_threshold.h):
// the noise and background estimates against known Gaussian noise, the
// threshold's effect on stripes of known height, noise-only and noise-free
// frames, ambient light with and without the local background, ROI, parsing.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/error.h"
#include "pipeline/auto_threshold.h"
#include "stripe_test_util.h"

namespace lt::test {
namespace {

const ExtractionMethod kAll[] = {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom,
                                 ExtractionMethod::kSteger};

ExtractionOptions AutoOptions(ExtractionMethod m) {
  ExtractionOptions o;
  o.method = m;
  o.threshold_mode = ThresholdMode::kNoise;
  return o;
}

SyntheticFrame NoiseFrame(double background, double sigma, uint64_t seed, int width = 640, int height = 480) {
  SyntheticFrame f;
  f.width = width;
  f.height = height;
  f.background = background;
  f.noise_sigma = sigma;
  f.seed = seed;
  return f;
}

template <typename T>
NoiseThreshold Estimate(const SyntheticFrame& f, bool local = false) {
  const Image<T> img = QuantizeImage<T>(RenderSyntheticFrame(f));
  return EstimateNoiseThreshold(img.View(), MeasureSampleScale(img.View()), local);
}

// Known Gaussian noise: the estimates within 3% of sigma (the MAD of ~65 000
// differences has a relative standard error of 0.7%), the background within
// 0.1 sigma, with a bright stripe in the frame (its pixels are under 1% of
// the samples: the medians ignore them). 8-bit samples add the rounding's
// variance, 1/12 DN^2; at sigma 0.6 DN most differences are 0 or 1 and the
// interpolated medians resolve it within 8% (0.70 for 0.67 DN: the
// interpolation takes the density as flat within a step; without it 1.05).
TEST(AutoThreshold, EstimatesKnownGaussianNoise) {
  for (double sigma : {0.6, 3.0, 12.0}) {
    SyntheticFrame f = NoiseFrame(40, sigma, 7);
    f.stripes.push_back(LineStripe(300.3, 240, 10, 2, 150));
    const double quantized = std::sqrt(sigma * sigma + 1.0 / 12.0);
    SCOPED_TRACE(sigma);
    const NoiseThreshold fl = Estimate<float>(f);
    EXPECT_NEAR(fl.noise, sigma, 0.03 * sigma);
    EXPECT_LT(fl.spread, NoiseThreshold::kVariedBackground * sigma);  // a flat background: its trend (running medians) near b
    EXPECT_NEAR(fl.background, 40, 0.1 * sigma);
    EXPECT_EQ(fl.from, NoiseThreshold::From::kNoise);
    EXPECT_NEAR(fl.threshold, fl.background + 6 * fl.noise, 1e-9);
    const NoiseThreshold u8 = Estimate<uint8_t>(f);
    const double tolerance = (sigma < 1 ? 0.08 : 0.03) * quantized;
    EXPECT_NEAR(u8.noise, quantized, tolerance);
    EXPECT_NEAR(u8.background, 40, 0.1 * quantized);
    const NoiseThreshold u16 = Estimate<uint16_t>(f);
    EXPECT_NEAR(u16.noise, quantized, tolerance);
  }
}

// A stripe 8 sigma high is found in every row by every method (steger: every
// row outside its 3-sigma border rows); one 2 sigma high is not claimed (no
// point at all: the rest of the frame is noise under 6 sigma).
TEST(AutoThreshold, FindsAStripeAtEightSigmaNotAtTwo) {
  const double sigma = 4;
  for (double height : {8 * sigma, 2 * sigma}) {
    SyntheticFrame f = NoiseFrame(30, sigma, 11, 640, 128);
    f.stripes.push_back(LineStripe(320.4, 64, 6, 2, height));
    for (auto m : kAll) {
      SCOPED_TRACE(std::string(MethodName(m)) + " at " + std::to_string(height / sigma) + " sigma");
      ExtractionOptions o = AutoOptions(m);
      o.background = 30;  // the half-maximum level between a spike and its neighbours, as in scan
      StripeExtractor ex(o);
      const Image<uint8_t> img = QuantizeImage<uint8_t>(RenderSyntheticFrame(f));
      const std::vector<StripePoint> pts = ex.Extract(img.View());
      ASSERT_NE(ex.last_noise_threshold(), nullptr);
      // steger's threshold is a contrast: no background in it.
      const double b = m == ExtractionMethod::kSteger ? 0 : 30;
      EXPECT_NEAR(ex.resolved_options().threshold, b + 6 * sigma, 0.3 * sigma);
      if (height < 3 * sigma) {
        EXPECT_TRUE(pts.empty()) << pts.size() << " points, first at row " << pts.front().v;
        continue;
      }
      // Every row holds a point within 3 px (max's noisy argmax strays 1-2 px;
      // multicom split one row's peak in two), and none lies elsewhere.
      std::set<int> rows;
      for (const StripePoint& p : pts) {
        if (std::abs(p.u - f.stripes[0].CentreU(p.v)) <= 3) rows.insert(int(p.v));
      }
      const int edge = ex.resolved_options().EdgeLinesWithoutPoints();
      EXPECT_EQ(int(rows.size()), f.height - 2 * edge);
      EXPECT_EQ(RowErrors(pts, f).unmatched, 0);
    }
  }
}

// Noise only, 640x480: no method claims a point, on 8-bit and float frames
// of five seeds each (the largest of the 307 200 samples lies near 5 sigma,
// the threshold at 6).
TEST(AutoThreshold, NoiseOnlyFramesGiveNoPoints) {
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    const SyntheticFrame f = NoiseFrame(25, 5, seed);
    for (auto m : kAll) {
      SCOPED_TRACE(std::string(MethodName(m)) + " seed " + std::to_string(seed));
      ExtractionOptions o = AutoOptions(m);
      o.background = 25;
      EXPECT_TRUE(ExtractFrom<uint8_t>(f, o).empty());
      EXPECT_TRUE(ExtractFrom<float>(f, o).empty());
    }
  }
}

// Noise-free frames: a flat quantized background reads as the rounding's
// noise (the interpolated medians take a step's values as spread over it:
// about 1/sqrt 12 = 0.29 DN), so the threshold lies 2 to 3 steps above it, not
// on it; a float one takes 1% of the stripe's peak. The stripe is found in
// every row and a faint glow under the floor is not.
TEST(AutoThreshold, NoiseFreeFramesUseTheFloors) {
  SyntheticFrame f = NoiseFrame(20, 0, 1, 128, 64);
  f.stripes.push_back(LineStripe(60.4, 32, 8, 2, 200));
  const NoiseThreshold q = Estimate<uint8_t>(f);
  EXPECT_LT(q.noise, 0.35);
  EXPECT_GT(q.threshold, 21.5);
  EXPECT_LT(q.threshold, 23);
  SyntheticFrame flat = NoiseFrame(20, 0, 1, 128, 64);
  const NoiseThreshold z = Estimate<uint8_t>(flat);
  EXPECT_EQ(z.from, NoiseThreshold::From::kQuantization);
  EXPECT_NEAR(z.threshold, 20 + 6 / std::sqrt(12.0), 1e-6);
  SyntheticFrame dark = f;
  dark.background = 0;
  dark.stripes.push_back(LineStripe(100.2, 32, 0, 3, 1.5));  // glow at 0.75% of the stripe
  const NoiseThreshold p = Estimate<float>(dark);
  EXPECT_EQ(p.from, NoiseThreshold::From::kPeak);
  EXPECT_NEAR(p.threshold, 0.01 * 200, 0.1);
  for (auto m : kAll) {
    SCOPED_TRACE(MethodName(m));
    const std::vector<StripePoint> pts = ExtractFrom<float>(dark, AutoOptions(m));
    const int edge = AutoOptions(m).EdgeLinesWithoutPoints();
    for (const StripePoint& pt : pts) EXPECT_NEAR(pt.u, dark.stripes[0].CentreU(pt.v), 1.0) << pt.v;
    EXPECT_EQ(int(pts.size()), dark.height - 2 * edge);
  }
}

// Ambient light: a bright ramp across the frame (20 to 120) under the noise.
// With a background level the threshold rises to the ramp's top (its running
// median's 99th percentile) + 6 x the noise, so the ramp's bright end is not
// taken for a stripe, and the stripe (10 sigma on the ramp's middle, under its
// top) cannot be told from it: nothing. With --background local the threshold
// is 6 x the noise above each peak's local background, and the stripe is
// found in every row. (AutoThresholdScale.SlopeAndTextureAreNotMultiplied: a
// stripe above the background's top is found with a level.)
TEST(AutoThreshold, AmbientLightWithLocalBackground) {
  const double sigma = 2;
  SyntheticFrame f = NoiseFrame(0, sigma, 5, 320, 96);
  Image<float> img = RenderSyntheticFrame(f);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) img.pixels[size_t(y) * img.width + x] += float(20 + 100.0 * x / img.width);
  }
  SyntheticFrame stripe = NoiseFrame(0, 0, 1, 320, 96);
  stripe.stripes.push_back(LineStripe(200.3, 48, 5, 2, 10 * sigma));
  const Image<float> s = RenderSyntheticFrame(stripe);
  for (size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] += s.pixels[i];
  const Image<uint8_t> frame = QuantizeImage<uint8_t>(img);

  const NoiseThreshold level = EstimateNoiseThreshold(frame.View(), MeasureSampleScale(frame.View()), false);
  EXPECT_EQ(level.from, NoiseThreshold::From::kSpread);
  EXPECT_GT(level.threshold, 125);            // above the ramp's top: nothing claimed on it
  EXPECT_LT(level.threshold, 120 + 9 * sigma);  // the slope is not multiplied (before: 6 x spread, 238)
  const NoiseThreshold local = EstimateNoiseThreshold(frame.View(), MeasureSampleScale(frame.View()), true);
  EXPECT_EQ(local.from, NoiseThreshold::From::kNoise);
  EXPECT_NEAR(local.threshold, 6 * sigma, 0.5);

  for (auto m : {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
    SCOPED_TRACE(MethodName(m));
    ExtractionOptions o = AutoOptions(m);
    StripeExtractor level_ex(o);
    EXPECT_TRUE(level_ex.Extract(frame.View()).empty());  // nothing on the ramp (nor the stripe under its top)
    o.background_mode = BackgroundMode::kLocal;
    StripeExtractor local_ex(o);
    const std::vector<StripePoint> pts = local_ex.Extract(frame.View());
    const ErrorStats e = RowErrors(pts, stripe);
    EXPECT_EQ(e.points, frame.height);
    EXPECT_EQ(e.unmatched, 0);
  }
}

// Per ROI: the left half of the frame is 5x noisier; an ROI on the right half
// measures the right half's noise, the whole frame something between.
TEST(AutoThreshold, EstimatedPerRoi) {
  SyntheticFrame quiet = NoiseFrame(30, 2, 3, 320, 128);
  SyntheticFrame loud = NoiseFrame(0, 10, 4, 320, 128);
  Image<float> img = RenderSyntheticFrame(quiet);
  const Image<float> extra = RenderSyntheticFrame(loud);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < 160; ++x) img.pixels[size_t(y) * 320 + x] += extra.pixels[size_t(y) * 320 + x];
  }
  ExtractionOptions o = AutoOptions(ExtractionMethod::kCom);
  o.roi = PixelRect{160, 0, 160, 128};
  StripeExtractor ex(o);
  ex.Extract(img.View());
  ASSERT_NE(ex.last_noise_threshold(), nullptr);
  EXPECT_NEAR(ex.last_noise_threshold()->noise, 2, 0.1);
  o.roi.reset();
  StripeExtractor whole(o);
  whole.Extract(img.View());
  EXPECT_GT(whole.last_noise_threshold()->noise, 3);
}

// A raw Bayer mosaic: demosaicing correlates neighbouring pixels, so the
// demosaiced image's differences read its noise 2-3x too low (sigma 4 read as
// 1.14 on the mean of R, G, B, 1.57 on R: 27 and 259 noise points on a
// noise-only 640x480 frame). The noise is taken on the raw mosaic instead
// (same-colour pixels two apart, each colour apart), and the channel mix's
// noise is that of its noisiest kind of pixel (MosaicNoise): no point.
TEST(AutoThreshold, BayerMosaicNoiseIsTakenOnTheRawSamples) {
  for (uint64_t seed : {1, 2}) {
    const SyntheticFrame f = NoiseFrame(40, 4, seed);
    for (int channel : {-1, 0}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + " channel " + std::to_string(channel));
      ExtractionOptions o = AutoOptions(ExtractionMethod::kMultiCom);
      o.bayer = ColorFilter::kRGGB;
      o.channel = channel;
      o.background = 40;
      const Image<uint8_t> img = QuantizeImage<uint8_t>(RenderSyntheticFrame(f));
      StripeExtractor ex(o);
      EXPECT_TRUE(ex.Extract(img.View()).empty());
      ASSERT_NE(ex.last_noise_threshold(), nullptr);
      // R alone: its own noise; the mean of R, G, B: at a G pixel R and B are
      // means of 2, G its own: (1/9)(16/2 + 16 + 16/2) = 2 x 16 / 9.
      const double v = 16 + 1.0 / 12;  // with the rounding
      EXPECT_NEAR(ex.last_noise_threshold()->noise, channel == 0 ? std::sqrt(v) : std::sqrt(2 * v / 9), 0.15);
    }
  }
}

TEST(AutoThreshold, ParsesAutoAndRefusesOtherWords) {
  double t = 7;
  ThresholdMode mode = ThresholdMode::kFixed;
  ParseThreshold("auto", "--threshold", &t, &mode);
  EXPECT_EQ(mode, ThresholdMode::kNoise);
  EXPECT_EQ(t, 7);
  ParseThreshold("12.5", "--threshold", &t, &mode);
  EXPECT_EQ(mode, ThresholdMode::kFixed);
  EXPECT_EQ(t, 12.5);
  for (const char* bad : {"autox", "Auto", "nan", "", "auto=3"}) {
    try {
      ParseThreshold(bad, "--threshold", &t, &mode);
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where(), "--threshold");
      EXPECT_NE(std::string(e.what()).find("expected a finite number or 'auto', got '" + std::string(bad) + "'"),
                std::string::npos)
          << e.what();
    }
  }
  // A high threshold below a fixed threshold is refused; with auto it is
  // raised to each frame's threshold instead.
  ExtractionOptions o = AutoOptions(ExtractionMethod::kSteger);
  o.high_threshold = 1;
  EXPECT_NO_THROW(o.Check());
}

}  // namespace
}  // namespace lt::test
