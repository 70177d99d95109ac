// Extraction on encoded frames (docs/extraction.md, "Encoded images"): an 8-bit
// sRGB frame, linearized by ExtractionOptions::transfer, gives the centres and
// widths of the same light stored linearly; without it the curve widens the
// stripe, pulls com and multicom towards an asymmetric tail and lifts dim
// ambient light above the threshold. Also the tables and the option's checks.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "pipeline/extract_transfer.h"
#include "stripe_test_util.h"

namespace lt::test {
namespace {

// The light (0..255 linear) stored through the sRGB curve, 8-bit.
Image<uint8_t> EncodeSrgb(const Image<float>& light) {
  Image<uint8_t> out(light.width, light.height, 1, 0);
  for (size_t i = 0; i < light.pixels.size(); ++i) {
    const double e = std::clamp(double(light.pixels[i]) / 255.0, 0.0, 1.0);
    const double c = e <= 0.0031308 ? 12.92 * e : 1.055 * std::pow(e, 1 / 2.4) - 0.055;
    out.pixels[i] = uint8_t(std::lround(255 * c));
  }
  return out;
}

// A stripe with a subsurface-like tail on its right: a sigma-1.5 core and a
// wider, dimmer Gaussian 3 px to its right (light in 0..255).
SyntheticFrame TailFrame() {
  SyntheticFrame f;
  f.width = 96;
  f.height = 40;
  f.stripes = {LineStripe(40.3, 20, 5, 1.5, 200), LineStripe(43.3, 20, 5, 4, 60)};
  return f;
}

std::vector<StripePoint> ExtractAs(ExtractionMethod method, Transfer transfer, const Image<uint8_t>& img) {
  ExtractionOptions o;
  o.method = method;
  o.transfer = transfer;
  StripeExtractor extractor(o);
  return extractor.Extract(img.View());
}

struct Shift {
  int pairs = 0;
  double mean_du = 0, rms_du = 0, max_du = 0, mean_width_ratio = 0;
};

// Points of `a` against those of `b` on the same rows.
Shift Compare(const std::vector<StripePoint>& a, const std::vector<StripePoint>& b) {
  Shift s;
  for (const StripePoint& p : a)
    for (const StripePoint& q : b) {
      if (p.v != q.v) continue;
      ++s.pairs;
      s.mean_du += p.u - q.u;
      s.rms_du += (p.u - q.u) * (p.u - q.u);
      s.max_du = std::max(s.max_du, std::abs(p.u - q.u));
      s.mean_width_ratio += p.width / q.width;
    }
  if (s.pairs) s.mean_du /= s.pairs, s.rms_du = std::sqrt(s.rms_du / s.pairs), s.mean_width_ratio /= s.pairs;
  return s;
}

TEST(ExtractionEncoding, SrgbFrameLinearizedGivesTheLinearFramesCentresAndWidths) {
  const SyntheticFrame f = TailFrame();
  const Image<float> light = RenderSyntheticFrame(f);
  const Image<uint8_t> linear = QuantizeImage<uint8_t>(light), srgb = EncodeSrgb(light);
  for (auto m : {ExtractionMethod::kCom, ExtractionMethod::kMultiCom, ExtractionMethod::kSteger}) {
    SCOPED_TRACE(MethodName(m));
    const std::vector<StripePoint> reference = ExtractAs(m, Transfer::kLinear, linear);
    ASSERT_GE(reference.size(), 28u);
    const Shift as_delivered = Compare(ExtractAs(m, Transfer::kLinear, srgb), reference);
    const Shift linearized = Compare(ExtractAs(m, Transfer::kSrgb, srgb), reference);
    EXPECT_EQ(linearized.pairs, int(reference.size()));
    // (com's window, a whole number of pixels, takes one pixel more of the
    // tail on a row or two of either frame: 0.10 px there.)
    EXPECT_LT(linearized.rms_du, 0.02);
    EXPECT_LT(linearized.max_du, 0.12);
    EXPECT_NEAR(linearized.mean_width_ratio, 1.0, 0.03);
    // As delivered: the curve doubles the stripe's FWHM and draws every
    // centre towards the tail (measured: com 1.27, multicom 1.21, steger
    // 0.41 px; steger's wider filter also drops 8 more rows at the ends).
    EXPECT_GT(as_delivered.mean_width_ratio, 1.5);
    EXPECT_GT(as_delivered.mean_du, 0.3);
  }
}

// 10% of the 8-bit range is 1% of the light through the sRGB curve: ambient
// light at 3% is encoded as 48 DN, above the default threshold, and multicom's
// run above it reaches the line's ends. Linearized, it is 7.7 DN.
TEST(ExtractionEncoding, AmbientUnderTheThresholdInLightIsAboveItInSrgb) {
  SyntheticFrame f;
  f.width = 96;
  f.height = 32;
  f.background = 0.03 * 255;
  f.stripes = {LineStripe(40.3, 16, 5, 2, 0.3 * 255)};
  const Image<uint8_t> srgb = EncodeSrgb(RenderSyntheticFrame(f));
  EXPECT_EQ(ExtractAs(ExtractionMethod::kMultiCom, Transfer::kLinear, srgb).size(), 0u);
  const std::vector<StripePoint> points = ExtractAs(ExtractionMethod::kMultiCom, Transfer::kSrgb, srgb);
  const ErrorStats e = RowErrors(points, f);
  EXPECT_EQ(e.points, f.height);
  EXPECT_EQ(e.unmatched, 0);
  EXPECT_LT(e.max_abs, 0.05);
}

// Each channel is linearized before the channel weights are applied: a red
// stripe with a tenth of it in green, each channel through sRGB, weighted
// 1,0.5,0, gives the points of the linear R, G, B weighted alike.
TEST(ExtractionEncoding, ChannelsAreLinearizedBeforeTheirWeights) {
  const SyntheticFrame f = TailFrame();
  const Image<float> light = RenderSyntheticFrame(f);
  Image<uint8_t> linear(light.width, light.height, 3, 0), srgb(light.width, light.height, 3, 0);
  const Image<uint8_t> red = EncodeSrgb(light);
  Image<float> green_light = light;
  for (float& v : green_light.pixels) v *= 0.1f;
  const Image<uint8_t> green = EncodeSrgb(green_light);
  for (int y = 0; y < light.height; ++y)
    for (int x = 0; x < light.width; ++x) {
      linear.At(x, y, 0) = uint8_t(std::lround(light.At(x, y)));
      linear.At(x, y, 1) = uint8_t(std::lround(green_light.At(x, y)));
      srgb.At(x, y, 0) = red.At(x, y);
      srgb.At(x, y, 1) = green.At(x, y);
    }
  ExtractionOptions o;
  o.method = ExtractionMethod::kMultiCom;
  o.channel_weights = {1, 0.5, 0};
  const std::vector<StripePoint> reference = StripeExtractor(o).Extract(linear.View());
  o.transfer = Transfer::kSrgb;
  const Shift s = Compare(StripeExtractor(o).Extract(srgb.View()), reference);
  ASSERT_GE(reference.size(), 38u);
  EXPECT_EQ(s.pairs, int(reference.size()));
  EXPECT_LT(s.rms_du, 0.02);
  EXPECT_NEAR(s.mean_width_ratio, 1.0, 0.03);
}

TEST(ExtractionEncoding, TransferTables) {
  std::vector<float> table, out;
  const std::vector<uint8_t> codes = {0, 10, 128, 255};
  ImageView<float> lin = LinearizeImage(ImageView<uint8_t>{codes.data(), 4, 1, 1, 4}, Transfer::kSrgb, 2.2, &table, &out);
  EXPECT_EQ(lin.At(0, 0), 0.0f);
  EXPECT_NEAR(lin.At(1, 0), 255 * (10 / 255.0) / 12.92, 1e-4);         // linear segment
  EXPECT_NEAR(lin.At(2, 0), 255 * 0.2158605, 1e-3);                    // sRGB 128 -> 0.2159
  EXPECT_EQ(lin.At(3, 0), 255.0f);
  // The table follows a change of transfer and of sample type.
  lin = LinearizeImage(ImageView<uint8_t>{codes.data(), 4, 1, 1, 4}, Transfer::kGamma, 2.0, &table, &out);
  EXPECT_NEAR(lin.At(2, 0), 255 * std::pow(128 / 255.0, 2.0), 1e-3);
  const std::vector<uint16_t> words = {32768, 65535};
  lin = LinearizeImage(ImageView<uint16_t>{words.data(), 2, 1, 1, 2}, Transfer::kGamma, 2.0, &table, &out);
  EXPECT_NEAR(lin.At(0, 0), 65535 * std::pow(32768 / 65535.0, 2.0), 0.02);
  EXPECT_EQ(lin.At(1, 0), 65535.0f);
}

TEST(ExtractionEncoding, TransferOptionIsCheckedAndFloatImagesRefuseIt) {
  Transfer t = Transfer::kLinear;
  double g = 0;
  ParseTransfer("gamma=2.4", "--transfer", &t, &g);
  EXPECT_EQ(t, Transfer::kGamma);
  EXPECT_EQ(g, 2.4);
  ParseTransfer("srgb", "--transfer", &t, &g);
  EXPECT_EQ(t, Transfer::kSrgb);
  for (const char* bad : {"gamma=0.45", "gamma=", "gamma", "rec709", "gamma=2.2x"}) {
    EXPECT_THROW(ParseTransfer(bad, "--transfer", &t, &g), InputError) << bad;
  }
  try {
    ParseTransfer("gamma=0.45", "--transfer", &t, &g);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("gamma=G with G in [1, 4]"), std::string::npos) << e.what();
  }
  ExtractionOptions o;
  o.transfer = Transfer::kGamma;
  o.gamma = 0.5;
  EXPECT_THROW(o.Check(), InputError);
  o.gamma = 2.2;
  StripeExtractor extractor(o);
  Image<float> img(8, 4, 1, 0.0f);
  try {
    extractor.Extract(img.View());
    ADD_FAILURE() << "a float image was linearized";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a float image holds linear values"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace lt::test
