// Bilinear demosaicing against closed forms, and stripe extraction on raw Bayer
// mosaics (docs/extraction.md, "Bayer mosaics").
#include "pipeline/demosaic.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"
#include "pipeline/stripe_extractor.h"
#include "stripe_test_util.h"

namespace lt {
namespace {

constexpr ColorFilter kPatterns[] = {ColorFilter::kRGGB, ColorFilter::kBGGR, ColorFilter::kGRBG, ColorFilter::kGBRG};

// The mosaic a sensor with filter `filter` records of the colour image `rgb`.
Image<float> Mosaic(const Image<float>& rgb, ColorFilter filter) {
  Image<float> m(rgb.width, rgb.height, 1);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x) m.At(x, y) = rgb.At(x, y, FilterChannel(filter, x, y));
  return m;
}

// Smooth colour planes A_c + B sin(kx x + ky y + phi_c).
constexpr double kB = 40, kKx = 0.3, kKy = 0.2;
double Smooth(int c, double x, double y) { return 100 + 30 * c + kB * std::sin(kKx * x + kKy * y + 1.1 * c); }

// A smooth image comes back within the Taylor bound of demosaic.h:
// (1/2)(|f_xx| + 2|f_xy| + |f_yy|) <= (1/2) B (|kx| + |ky|)^2 = 2.5 here, and a
// pixel's own colour is its own value.
TEST(Demosaic, SmoothImageComesBackWithinTheTaylorBound) {
  const double bound = 0.5 * kB * (kKx + kKy) * (kKx + kKy) + 1e-3;
  Image<float> rgb(37, 29, 3);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x)
      for (int c = 0; c < 3; ++c) rgb.At(x, y, c) = float(Smooth(c, x, y));
  for (ColorFilter f : kPatterns) {
    Image<float> back = DemosaicBilinear(Mosaic(rgb, f).View(), f);
    ASSERT_EQ(back.channels, 3);
    double worst = 0;
    for (int y = 1; y < rgb.height - 1; ++y)
      for (int x = 1; x < rgb.width - 1; ++x)
        for (int c = 0; c < 3; ++c) {
          const double e = std::abs(back.At(x, y, c) - rgb.At(x, y, c));
          if (c == FilterChannel(f, x, y)) {
            EXPECT_EQ(back.At(x, y, c), rgb.At(x, y, c));
          }
          worst = std::max(worst, e);
        }
    EXPECT_LE(worst, bound) << BayerPatternName(f);
    EXPECT_GT(worst, 0.2 * bound) << BayerPatternName(f);  // the bound is not loose by orders of magnitude
  }
}

// A linear image is reproduced exactly inside; a crop demosaiced with its phase
// equals the whole image's demosaic away from the crop's border.
TEST(Demosaic, LinearImageIsExactAndCropsKeepThePhase) {
  Image<float> rgb(20, 16, 3);
  for (int y = 0; y < rgb.height; ++y)
    for (int x = 0; x < rgb.width; ++x)
      for (int c = 0; c < 3; ++c) rgb.At(x, y, c) = float(10 + 3 * c + (1.5 + c) * x - (0.5 * c) * y);
  for (ColorFilter f : kPatterns) {
    const Image<float> mosaic = Mosaic(rgb, f);
    Image<float> back = DemosaicBilinear(mosaic.View(), f);
    for (int y = 1; y < rgb.height - 1; ++y)
      for (int x = 1; x < rgb.width - 1; ++x)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.At(x, y, c), rgb.At(x, y, c), 1e-4) << x << "," << y;
    Image<float> crop = DemosaicBilinear(mosaic.View().Crop(3, 5, 10, 8), f, 3, 5);
    for (int y = 1; y < crop.height - 1; ++y)
      for (int x = 1; x < crop.width - 1; ++x)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(crop.At(x, y, c), back.At(x + 3, y + 5, c));
  }
}

// A view one pixel wide or high has no mirror across its border: its colours come
// from the neighbours it has, else the pixel's own value, and nothing outside it is
// read (before, the mirror of -1 was 1, past a 1-pixel view: ASan's heap overflow).
TEST(Demosaic, OnePixelWideViewsReadOnlyThemselves) {
  for (const auto& [w, h] : {std::pair{1, 1}, std::pair{1, 4}, std::pair{4, 1}}) {
    Image<float> m(w, h, 1);
    for (size_t i = 0; i < m.pixels.size(); ++i) m.pixels[i] = float(10 * (i + 1));
    const Image<float> rgb = DemosaicBilinear(m.View(), ColorFilter::kRGGB);
    ASSERT_EQ(rgb.pixels.size(), size_t(3 * w * h));
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        // Each channel is the pixel's own value or a mean of its neighbours in the view.
        const float lo = *std::min_element(m.pixels.begin(), m.pixels.end());
        const float hi = *std::max_element(m.pixels.begin(), m.pixels.end());
        for (int c = 0; c < 3; ++c) {
          EXPECT_GE(rgb.At(x, y, c), lo) << w << "x" << h << " " << x << "," << y << " c" << c;
          EXPECT_LE(rgb.At(x, y, c), hi) << w << "x" << h << " " << x << "," << y << " c" << c;
        }
      }
    }
  }
  Image<float> one(1, 1, 1, 42.0f);
  const Image<float> rgb = DemosaicBilinear(one.View(), ColorFilter::kGBRG);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(rgb.At(0, 0, c), 42.0f);
}

TEST(Demosaic, ParsesPatternNames) {
  EXPECT_EQ(ParseBayerPattern("gbrg", "--bayer"), ColorFilter::kGBRG);
  EXPECT_EQ(ParseBayerPattern("none", "--bayer"), ColorFilter::kMono);
  EXPECT_THROW(ParseBayerPattern("RGGB", "--bayer"), InputError);
  for (ColorFilter f : kPatterns) EXPECT_EQ(ParseBayerPattern(BayerPatternName(f), "x"), f);
}

// A red laser on a raw Bayer mosaic (R 1.0, G 0.25, B 0.05): on the raw mosaic
// a peak's neighbours are dim green pixels, so com rejects it as narrower than
// --min-width; demosaiced, com finds every row within 0.05 px of the exact
// centre line (measured: rms 0.004, max 0.03 px, the largest in the border row
// without red pixels, for sigma 1.25..3). A stripe of sigma 1 (FWHM 2.4 px) is
// undersampled by the red pixels, every second column: rms 0.017-0.023, max
// 0.07 px.
TEST(Demosaic, GaussianStripeOnAMosaicWithUnequalGains) {
  for (double sigma : {1.0, 1.25, 2.0, 3.0}) {
    const double tolerance = sigma < 1.2 ? 0.08 : 0.05;
    SyntheticFrame frame;
    frame.width = 120;
    frame.height = 80;
    frame.stripes.push_back(test::LineStripe(60.3, 0, std::atan(0.037) * 180 / M_PI, sigma, 3000));
    const Image<float> scene = RenderSyntheticFrame(frame);
    for (ColorFilter f : kPatterns) {
      const double gain[3] = {1.0, 0.25, 0.05};
      Image<float> raw(scene.width, scene.height, 1);
      for (int y = 0; y < raw.height; ++y)
        for (int x = 0; x < raw.width; ++x) raw.At(x, y) = float(scene.At(x, y) * gain[FilterChannel(f, x, y)]);
      const Image<uint16_t> mosaic = QuantizeImage<uint16_t>(raw);
      ExtractionOptions o;
      o.method = ExtractionMethod::kCom;
      o.threshold = 200;
      if (f == ColorFilter::kRGGB) {
        // Without demosaicing (the old behaviour): rows lost to the width check.
        const auto raw_points = StripeExtractor(o).Extract(mosaic.View());
        EXPECT_LT(raw_points.size(), size_t(frame.height) / 2) << "sigma " << sigma;
      }
      o.bayer = f;
      const auto points = StripeExtractor(o).Extract(mosaic.View());
      const test::ErrorStats e = test::RowErrors(points, frame);
      EXPECT_EQ(e.points, frame.height) << BayerPatternName(f) << " sigma " << sigma;
      EXPECT_EQ(e.unmatched, 0);
      EXPECT_LT(e.rms, tolerance / 2) << BayerPatternName(f) << " sigma " << sigma;
      EXPECT_LT(e.max_abs, tolerance) << BayerPatternName(f) << " sigma " << sigma << " rms " << e.rms;
      // The laser's own channel of the demosaiced image, and an ROI at an odd
      // offset (the mosaic's phase follows the crop), work as well.
      o.channel = 0;
      o.roi = PixelRect{7, 3, 100, 70};
      const auto red = StripeExtractor(o).Extract(mosaic.View());
      const test::ErrorStats er = test::RowErrors(red, frame);
      EXPECT_EQ(er.points, 70);
      EXPECT_LT(er.max_abs, tolerance) << BayerPatternName(f) << " sigma " << sigma << " rms " << er.rms;
    }
  }
}

TEST(Demosaic, ABayerOptionNeedsAOneChannelImage) {
  ExtractionOptions o;
  o.bayer = ColorFilter::kRGGB;
  Image<uint8_t> rgb(8, 8, 3, 0);
  try {
    StripeExtractor(o).Extract(rgb.View());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has one channel but the image has 3"), std::string::npos) << e.what();
  }
  o.channel = 3;
  EXPECT_THROW(StripeExtractor{o}, InputError);
  o.channel = -1;
  o.channel_weights = {1, 0};
  EXPECT_THROW(StripeExtractor{o}, InputError);
}

}  // namespace
}  // namespace lt
