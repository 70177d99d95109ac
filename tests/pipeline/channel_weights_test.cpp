// The R, G, B weights matched to the rig's lasers (pipeline/channel_weights.h)
// against their closed form w_c = N_c n_c / V_c (normalised to sum 1), and the
// rigs that cannot give them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "pipeline/channel_weights.h"
#include "pipeline/frame_extraction.h"

namespace lt {
namespace {

using ::testing::HasSubstr;

// The print scene's sensor (scenes/print): RGGB, QE tables at 450..750 nm.
RunRig PrintRig(std::vector<double> wavelengths_nm) {
  RunRig rig;
  rig.source = "rig.json";
  rig.color_filter = ColorFilter::kRGGB;
  rig.qe_wavelength_m = {450e-9, 550e-9, 650e-9, 750e-9};
  rig.qe = {{{0.05, 0.1, 0.5, 0.3}, {0.1, 0.55, 0.2, 0.1}, {0.5, 0.1, 0.05, 0.08}}};
  for (double nm : wavelengths_nm) rig.laser_wavelength_m.push_back(nm * 1e-9);
  return rig;
}

// w_c proportional to N_c q_c / (floor + q_c / max(q) * reference), summing to 1.
std::vector<double> ClosedForm(const double q[3], double floor, double reference) {
  const double N[3] = {1, 2, 1};
  const double best = std::max({q[0], q[1], q[2]});
  double w[3], sum = 0;
  for (int c = 0; c < 3; ++c) sum += w[c] = N[c] * q[c] / (floor + q[c] / best * reference);
  return {w[0] / sum, w[1] / sum, w[2] / sum};
}

TEST(ChannelWeights, MatchTheClosedForm) {
  // Without noise figures: the floor's N_c QE_c. 650 nm is a table entry.
  RunRig red = PrintRig({650});
  const double q650[3] = {0.5, 0.2, 0.05};
  LaserChannelWeights w = MatchedChannelWeights(red);
  ASSERT_TRUE(w.missing.empty()) << w.missing;
  EXPECT_EQ(w.reference_e, 0);
  const std::vector<double> floor_only = ClosedForm(q650, 1, 0);  // 0.5, 0.4, 0.05 over 0.95
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(w.weights[size_t(c)], floor_only[size_t(c)], 1e-12) << c;
  EXPECT_NEAR(w.weights[0], 0.5 / 0.95, 1e-12);
  // With the print sensor's K 0.1 DN/e-, dark noise 8 e-, 10 bits: floor 64 +
  // 1/(12 * 0.01) e-^2, reference 102.3 DN / 0.1 = 1023 e-.
  red.system_gain_dn_per_e = 0.1;
  red.dark_noise_e = 8;
  red.bit_depth = 10;
  w = MatchedChannelWeights(red);
  EXPECT_NEAR(w.reference_e, 1023, 1e-9);
  const std::vector<double> matched = ClosedForm(q650, 64 + 1 / 0.12, 1023);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(w.weights[size_t(c)], matched[size_t(c)], 1e-12) << c;
  EXPECT_THAT(w.Describe(), HasSubstr("R 0.290, G 0.528, B 0.182 (quantum efficiency 0.5, 0.2, 0.05 at 650 nm"));
  // 532 nm lies between table entries: the sensor model's linear interpolation.
  RunRig green = PrintRig({532});
  const double t = (532.0 - 450) / 100;
  const double q532[3] = {0.05 + t * 0.05, 0.1 + t * 0.45, 0.5 - t * 0.4};
  w = MatchedChannelWeights(green);
  const std::vector<double> g = ClosedForm(q532, 1, 0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(w.weights[size_t(c)], g[size_t(c)], 1e-12) << c;
  // Two lasers: their responses summed.
  RunRig both = PrintRig({650, 532});
  w = MatchedChannelWeights(both);
  const double q_sum[3] = {q650[0] + q532[0], q650[1] + q532[1], q650[2] + q532[2]};
  const std::vector<double> s = ClosedForm(q_sum, 1, 0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(w.response[size_t(c)], q_sum[c], 1e-12) << c;
    EXPECT_NEAR(w.weights[size_t(c)], s[size_t(c)], 1e-12) << c;
  }
  // Green pixels counted per tile: a GRBG mosaic gives the same weights.
  RunRig grbg = PrintRig({650});
  grbg.color_filter = ColorFilter::kGRBG;
  EXPECT_EQ(MatchedChannelWeights(grbg).weights, MatchedChannelWeights(PrintRig({650})).weights);
}

TEST(ChannelWeights, RigsThatCannotSay) {
  RunRig rig = PrintRig({650, 0});
  EXPECT_EQ(MatchedChannelWeights(rig).missing, "rig.json gives no wavelength_nm for laser 1");
  EXPECT_TRUE(MatchedChannelWeights(rig).weights.empty());
  rig = PrintRig({});
  EXPECT_EQ(MatchedChannelWeights(rig).missing, "rig.json describes no laser");
  rig = PrintRig({650});
  rig.qe_wavelength_m.clear();
  EXPECT_THAT(MatchedChannelWeights(rig).missing, HasSubstr("gives no image_sensor.quantum_efficiency"));
  rig = PrintRig({650});
  rig.color_filter = ColorFilter::kMono;
  EXPECT_THAT(MatchedChannelWeights(rig).missing, HasSubstr("mono"));
  rig = PrintRig({650});
  rig.qe = {{{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}}};
  EXPECT_THAT(MatchedChannelWeights(rig).missing, HasSubstr("quantum efficiency is 0 in every channel"));
}

// The options scan and `calibrate laser` extract a run's frame with
// (pipeline/frame_extraction.h): a mosaic demosaiced and extracted on the
// matched weights, three channels likewise, mono as it is; the default levels
// in the weighted image's units; the user's choice kept.
TEST(FrameExtraction, ColourFramesGetTheLaserChannels) {
  RunRig rig = PrintRig({650});
  rig.bit_depth = 10;
  rig.black_level_dn = 16;
  const LaserChannelWeights matched = MatchedChannelWeights(rig);
  ASSERT_TRUE(matched.missing.empty());
  RunFrame frame;
  frame.bit_depth = 10;
  frame.png_bit_depth = 16;
  ExtractionOptions given;  // threshold and background kAuto
  given.background = ExtractionOptions::kAuto;
  const AnyImage mosaic = Image<uint16_t>(8, 8, 1, 0), rgb = Image<uint16_t>(8, 8, 3, 0);
  for (const AnyImage* image : {&mosaic, &rgb}) {
    const FrameExtraction fx = RunFrameExtraction(given, frame, *image, rig, matched);
    EXPECT_TRUE(fx.matched_weights);
    EXPECT_FALSE(fx.mosaic_mean);
    EXPECT_EQ(fx.options.bayer, image == &mosaic ? ColorFilter::kRGGB : ColorFilter::kMono);
    EXPECT_EQ(fx.options.channel_weights, matched.weights);
    // Weights sum to 1 and are positive: the raw frame's 10% and black level.
    EXPECT_NEAR(fx.options.threshold, 102.3, 1e-9);
    EXPECT_NEAR(fx.options.background, 16, 1e-9);
  }
  // Given weights: kept, and the levels scaled by them.
  ExtractionOptions doubled = given;
  doubled.channel_weights = {2, 0, 0};
  FrameExtraction fx = RunFrameExtraction(doubled, frame, mosaic, rig, matched);
  EXPECT_FALSE(fx.matched_weights);
  EXPECT_EQ(fx.options.channel_weights, doubled.channel_weights);
  EXPECT_NEAR(fx.options.threshold, 204.6, 1e-9);
  EXPECT_NEAR(fx.options.background, 32, 1e-9);
  // A given channel: no weights, unscaled levels.
  ExtractionOptions red = given;
  red.channel = 0;
  fx = RunFrameExtraction(red, frame, mosaic, rig, matched);
  EXPECT_TRUE(fx.options.channel_weights.empty());
  EXPECT_NEAR(fx.options.threshold, 102.3, 1e-9);
  // A rig without the wavelength: a mosaic keeps the mean (and says so), three
  // channels get no weights (the extractor then asks for --channel).
  const RunRig unknown = PrintRig({});
  const LaserChannelWeights none = MatchedChannelWeights(unknown);
  fx = RunFrameExtraction(given, frame, mosaic, unknown, none);
  EXPECT_TRUE(fx.mosaic_mean);
  EXPECT_TRUE(fx.options.channel_weights.empty());
  fx = RunFrameExtraction(given, frame, rgb, unknown, none);
  EXPECT_FALSE(fx.mosaic_mean);
  EXPECT_TRUE(fx.options.channel_weights.empty());
  // A mono sensor: nothing changes but the levels.
  RunRig mono = rig;
  mono.color_filter = ColorFilter::kMono;
  fx = RunFrameExtraction(given, frame, mosaic, mono, MatchedChannelWeights(mono));
  EXPECT_EQ(fx.options.bayer, ColorFilter::kMono);
  EXPECT_TRUE(fx.options.channel_weights.empty());
  EXPECT_FALSE(fx.mosaic_mean);
  EXPECT_NEAR(fx.options.threshold, 102.3, 1e-9);
}

}  // namespace
}  // namespace lt
