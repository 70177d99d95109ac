// Extraction behaviour other than accuracy: empty rows, noise, borders, ROI,
// column search, sample types, colour input, threads, buffer reuse, bad input.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "core/error.h"
#include "core/image_io.h"
#include <filesystem>
#include "stripe_test_util.h"

namespace lt::test {
namespace {

const ExtractionMethod kAll[] = {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom,
                                 ExtractionMethod::kSteger};

ExtractionOptions Options(ExtractionMethod m) {
  ExtractionOptions o;
  o.method = m;
  o.threshold = 50;
  o.expected_width = 4.7;
  return o;
}

SyntheticFrame Frame(double u0 = 60.4, double angle_deg = 8) {
  SyntheticFrame f;
  f.width = 128;
  f.height = 64;
  f.stripes.push_back(LineStripe(u0, 32, angle_deg, 2, 200));
  return f;
}

TEST(ExtractionBehaviour, RowsWithoutStripeGiveNoPoint) {
  SyntheticFrame f = Frame();
  f.stripes[0].visible_rows = {{0, 20}, {40, 64}};
  for (auto m : kAll) {
    auto pts = ExtractFrom<uint8_t>(f, Options(m));
    SCOPED_TRACE(MethodName(m));
    ASSERT_FALSE(pts.empty());
    for (const auto& p : pts) {
      // Steger's filter reaches a few rows into the gap; nothing is reported
      // in the middle of it.
      EXPECT_FALSE(p.v >= 25 && p.v < 35) << p.v;
      EXPECT_NEAR(p.u, f.stripes[0].CentreU(p.v), 0.6);
    }
  }
}

TEST(ExtractionBehaviour, NoiseOnlyFrameGivesNoPoints) {
  // Noise sigma 8 DN on a 20 DN background (threshold 50): peaks of ~4 sigma
  // occur in a 128x64 frame but are single pixels, rejected by the width
  // check (max/com/multicom; the background is given so that the half-maximum
  // level sits between the spike and its neighbours) or by the
  // second-derivative threshold (steger).
  SyntheticFrame f = Frame();
  f.stripes.clear();
  f.background = 20;
  f.noise_sigma = 8;
  for (auto m : kAll) {
    SCOPED_TRACE(MethodName(m));
    ExtractionOptions o = Options(m);
    o.background = 20;
    EXPECT_TRUE(ExtractFrom<uint8_t>(f, o).empty());
  }
}

TEST(ExtractionBehaviour, StripeAtTheBorderGivesNoPoints) {
  // Centre half a pixel inside the left border: the peak runs into the border.
  for (double u0 : {0.5, 126.8}) {
    SyntheticFrame f = Frame(u0, 0);
    for (auto m : kAll) {
      SCOPED_TRACE(std::string(MethodName(m)) + " at " + std::to_string(u0));
      EXPECT_TRUE(ExtractFrom<uint8_t>(f, Options(m)).empty());
    }
  }
}

TEST(ExtractionBehaviour, RoiKeepsWholeImageCoordinates) {
  SyntheticFrame f = Frame();
  f.stripes.push_back(LineStripe(20.3, 32, 0, 2, 250));  // brighter distractor outside the ROI
  for (auto m : kAll) {
    ExtractionOptions o = Options(m);
    o.roi = PixelRect{36, 5, 70, 50};
    auto pts = ExtractFrom<uint8_t>(f, o);
    SCOPED_TRACE(MethodName(m));
    ASSERT_GT(pts.size(), 30u);
    for (const auto& p : pts) {
      EXPECT_GE(p.v, 5);
      EXPECT_LT(p.v, 55);
      EXPECT_NEAR(p.u, f.stripes[0].CentreU(p.v), 0.6);
    }
  }
}

TEST(ExtractionBehaviour, ColumnSearchFindsHorizontalStripes) {
  // A stripe running left to right: v = CentreV(u) for a line at 80 degrees
  // from the v axis, i.e. 10 degrees from horizontal.
  SyntheticFrame f;
  f.width = 128;
  f.height = 64;
  f.stripes.push_back(LineStripe(64, 30.6, 80, 2, 200));
  for (auto m : kAll) {
    ExtractionOptions o = Options(m);
    o.axis = SearchAxis::kCols;
    auto pts = ExtractFrom<float>(f, o);
    SCOPED_TRACE(MethodName(m));
    ASSERT_GT(pts.size(), 100u);
    double tol = m == ExtractionMethod::kMax ? 0.5 + 1e-9 : 0.02;
    for (const auto& p : pts) {
      EXPECT_EQ(p.u, std::round(p.u));
      EXPECT_NEAR(p.v, f.stripes[0].CentreV(p.u), tol);
    }
  }
}

TEST(ExtractionBehaviour, SampleTypesAgree) {
  // The same frame as 8-bit, 16-bit (x 257) and float gives the same points
  // within the 8-bit rounding (float and 16-bit see the unrounded profile).
  SyntheticFrame f = Frame();
  Image<float> radiance = RenderSyntheticFrame(f);
  Image<float> scaled = radiance;
  for (auto& v : scaled.pixels) v *= 257.0f;
  for (auto m : kAll) {
    ExtractionOptions o8 = Options(m), o16 = Options(m);
    o16.threshold = 50 * 257.0;
    auto p8 = StripeExtractor(o8).Extract(QuantizeImage<uint8_t>(radiance).View());
    auto p16 = StripeExtractor(o16).Extract(QuantizeImage<uint16_t>(scaled).View());
    auto pf = StripeExtractor(o8).Extract(radiance.View());
    SCOPED_TRACE(MethodName(m));
    ASSERT_EQ(p16.size(), pf.size());
    ASSERT_NEAR(double(p8.size()), double(pf.size()), 2);
    for (size_t i = 0; i < pf.size(); ++i) {
      EXPECT_NEAR(p16[i].u, pf[i].u, 0.005);
      EXPECT_NEAR(p16[i].strength / 257.0, pf[i].strength, 0.01 * pf[i].strength + 1);
    }
  }
}

TEST(ExtractionBehaviour, ColourChannelAndWeights) {
  // Red laser in channel 0, a brighter green line in channel 1.
  SyntheticFrame red = Frame(), green = Frame(90.2, 0);
  green.stripes[0].amplitude = 250;
  Image<uint8_t> r = QuantizeImage<uint8_t>(RenderSyntheticFrame(red));
  Image<uint8_t> g = QuantizeImage<uint8_t>(RenderSyntheticFrame(green));
  Image<uint8_t> rgb(r.width, r.height, 3);
  for (int y = 0; y < r.height; ++y)
    for (int x = 0; x < r.width; ++x) rgb.At(x, y, 0) = r.At(x, y), rgb.At(x, y, 1) = g.At(x, y);
  for (auto m : kAll) {
    SCOPED_TRACE(MethodName(m));
    ExtractionOptions o = Options(m);
    EXPECT_THROW(StripeExtractor(o).Extract(rgb.View()), InputError);  // no channel chosen
    o.channel = 0;
    auto by_channel = StripeExtractor(o).Extract(rgb.View());
    auto mono = StripeExtractor(Options(m)).Extract(r.View());
    ASSERT_EQ(by_channel.size(), mono.size());
    for (size_t i = 0; i < mono.size(); ++i) EXPECT_DOUBLE_EQ(by_channel[i].u, mono[i].u);
    o.channel = -1;
    o.channel_weights = {1, 0, 0};
    auto weighted = StripeExtractor(o).Extract(rgb.View());
    ASSERT_EQ(weighted.size(), mono.size());
    for (size_t i = 0; i < mono.size(); ++i) EXPECT_NEAR(weighted[i].u, mono[i].u, 1e-4);
    o.channel_weights = {1, 0};
    EXPECT_THROW(StripeExtractor(o).Extract(rgb.View()), InputError);  // 2 weights, 3 channels
    o.channel_weights.clear();
    o.channel = 3;
    EXPECT_THROW(StripeExtractor(o).Extract(rgb.View()), InputError);
  }
}

// The automatic threshold is 10% of the weighted image's full scale: the
// sample type's times the sum of the positive weights. A red stripe of peak 20
// (under 25.5, 10% of 255) is found neither with weights 1,0,0 nor 2,0,0 (peak
// 40, threshold 51); one of peak 200 gives the same points with both.
TEST(ExtractionBehaviour, AutomaticThresholdFollowsTheWeights) {
  for (double peak : {20.0, 200.0}) {
    SyntheticFrame red = Frame();
    red.stripes[0].amplitude = peak;
    Image<uint8_t> r = QuantizeImage<uint8_t>(RenderSyntheticFrame(red));
    Image<uint8_t> rgb(r.width, r.height, 3);
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x) rgb.At(x, y, 0) = r.At(x, y);
    for (auto m : kAll) {
      SCOPED_TRACE(std::string(MethodName(m)) + " peak " + std::to_string(peak));
      ExtractionOptions o = Options(m);
      o.threshold = ExtractionOptions::kAuto;
      o.high_threshold = ExtractionOptions::kAuto;
      o.channel_weights = {1, 0, 0};
      const auto one = StripeExtractor(o).Extract(rgb.View());
      o.channel_weights = {2, 0, 0};
      EXPECT_DOUBLE_EQ(o.WeightedFullScale(), 2.0);
      const auto two = StripeExtractor(o).Extract(rgb.View());
      ASSERT_EQ(one.size(), two.size());
      if (peak < 25.5) {
        EXPECT_TRUE(one.empty());
      }
      if (peak > 100) {
        EXPECT_GT(one.size(), 50u);
      }
      for (size_t i = 0; i < one.size(); ++i) EXPECT_NEAR(one[i].u, two[i].u, 1e-4);
    }
  }
}

TEST(ExtractionBehaviour, ThreadCountAndReuseDoNotChangeResults) {
  SyntheticFrame f = Frame();
  f.width = 300;
  f.height = 200;
  f.stripes.push_back(LineStripe(200.7, 100, -20, 3, 180));
  f.noise_sigma = 2;
  Image<uint8_t> img = QuantizeImage<uint8_t>(RenderSyntheticFrame(f));
  Image<uint8_t> small = QuantizeImage<uint8_t>(RenderSyntheticFrame(Frame()));
  for (auto m : {ExtractionMethod::kMultiCom, ExtractionMethod::kSteger}) {
    ExtractionOptions o = Options(m);
    o.threads = 1;
    StripeExtractor one(o);
    o.threads = 2;
    StripeExtractor two(o);
    auto a = one.Extract(img.View());
    two.Extract(small.View());  // a different size first: buffers are resized, not stale
    auto b = two.Extract(img.View());
    auto c = two.Extract(img.View());
    SCOPED_TRACE(MethodName(m));
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(b.size(), c.size());
    EXPECT_GT(a.size(), 300u);
    for (size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].u, b[i].u);
      EXPECT_EQ(a[i].v, b[i].v);
      EXPECT_EQ(b[i].u, c[i].u);
    }
  }
}

TEST(ExtractionBehaviour, BrighterRejectedPeakDoesNotHideTheStripe) {
  // Hot pixels (one pixel, 5x the stripe) beside the stripe in some rows: max
  // and com measure one peak per row and used to take the row maximum, reject
  // it as narrower than --min-width and lose the row. The brightest peak that
  // passes the width check is the stripe. Likewise a 3-pixel glint (FWHM
  // ~1.8 px) brighter than the stripe is passed over with --min-width 3.
  SyntheticFrame f = Frame();
  Image<float> img = RenderSyntheticFrame(f);
  for (int y = 3; y < f.height; y += 5) img.At(y % 2 ? 15 : 110, y) = 1000;
  Image<float> glint = RenderSyntheticFrame(f);
  for (int y = 3; y < f.height; y += 5) {
    glint.At(19, y) = 300, glint.At(20, y) = 900, glint.At(21, y) = 300;
  }
  for (auto m : kAll) {
    ExtractionOptions o = Options(m);
    SCOPED_TRACE(MethodName(m));
    auto pts = StripeExtractor(o).Extract(img.View());
    o.min_width = 3;
    auto beside_glint = StripeExtractor(o).Extract(glint.View());
    for (const auto* points : {&pts, &beside_glint}) {
      // Steger gives no points within 3 filter sigmas of the top and bottom.
      const int margin = o.EdgeLinesWithoutPoints();
      EXPECT_EQ(int(points->size()), f.height - 2 * margin);
      // max: pixel accuracy; the others are within a few hundredths here.
      for (const auto& p : *points) EXPECT_NEAR(p.u, f.stripes[0].CentreU(p.v), 0.5 + 1e-9) << p.v;
    }
  }
}

// Narrow peaks (pipeline/narrow_peak.h): a stripe of sigma 0.4 px (FWHM 1.1 px
// along the row where its centre is on a pixel centre, up to 2 px where it is
// between two) continues on the adjacent rows and is found in every row with
// the default options, at 0 to 30 degrees, with one background level or the
// local background, and searching columns; the rows where it is narrower than
// the default --min-width 1.5 (a third or more) used to be rejected.
SyntheticFrame NarrowFrame(double angle_deg) {
  SyntheticFrame f;
  f.width = 128;
  f.height = 64;
  f.stripes.push_back(LineStripe(60.3, 32, angle_deg, 0.4, 200));
  return f;
}

const ExtractionMethod kPeakMethods[] = {ExtractionMethod::kMax, ExtractionMethod::kCom, ExtractionMethod::kMultiCom};

// Pixel accuracy for max; on a stripe this undersampled the subpixel methods
// are biased by the pixel grid: measured at most 0.013 px (com) and 0.128 px
// (multicom: the centroid above the threshold of a linearly interpolated
// profile).
double NarrowTolerance(ExtractionMethod m) {
  return m == ExtractionMethod::kMax ? 0.5 + 1e-9 : m == ExtractionMethod::kCom ? 0.02 : 0.15;
}

TEST(NarrowPeaks, NarrowStripeFoundInEveryRowByDefault) {
  for (double angle : {0.0, 7.0, 30.0}) {
    SyntheticFrame f = NarrowFrame(angle);
    const Image<float> img = RenderSyntheticFrame(f);
    for (auto m : kPeakMethods) {
      for (auto mode : {BackgroundMode::kLevel, BackgroundMode::kLocal}) {
        SCOPED_TRACE(std::string(MethodName(m)) + " at " + std::to_string(angle) + " deg" +
                     (mode == BackgroundMode::kLocal ? ", local background" : ""));
        ExtractionOptions o = Options(m);
        o.background_mode = mode;
        ASSERT_EQ(o.min_width, 1.5);  // the default
        StripeExtractor e(o);
        const auto pts = e.Extract(img.View());
        EXPECT_EQ(int(pts.size()), f.height);
        EXPECT_EQ(e.last_rejections().narrow, 0);
        int narrow = 0;  // rows the width alone would reject
        for (const auto& p : pts) {
          narrow += p.width < 1.5;
          EXPECT_NEAR(p.u, f.stripes[0].CentreU(p.v), NarrowTolerance(m)) << p.v;
        }
        EXPECT_GE(narrow, f.height / 3);
      }
    }
  }
  // Searching columns: the same stripe turned to run left to right.
  SyntheticFrame f;
  f.width = 128;
  f.height = 64;
  f.stripes.push_back(LineStripe(64, 30.6, 84, 0.4, 200));
  const Image<float> img = RenderSyntheticFrame(f);
  for (auto m : kPeakMethods) {
    SCOPED_TRACE(std::string(MethodName(m)) + ", columns");
    ExtractionOptions o = Options(m);
    o.axis = SearchAxis::kCols;
    const auto pts = StripeExtractor(o).Extract(img.View());
    EXPECT_EQ(int(pts.size()), f.width);
    for (const auto& p : pts) EXPECT_NEAR(p.v, f.stripes[0].CentreV(p.u), NarrowTolerance(m)) << p.u;
  }
}

// Hot pixels beside the narrow stripe (3 and 25 px away, one pixel each, on
// rows whose neighbours there are dark; 5x the stripe, or as bright as it)
// are still rejected: max and com take the stripe in every row, multicom gives
// no other point, and the brighter hot pixels (the row maxima) are counted.
// A vertical pair of hot pixels (two adjacent rows, the same column, a cluster
// defect or a particle's short track) continues on one line only and is
// rejected too: the light must cross three lines. Three lines are a stripe
// piece (kept), which is the rule's limit.
TEST(NarrowPeaks, IsolatedHotPixelsAndVerticalPairsAreRejected) {
  SyntheticFrame f = NarrowFrame(7);
  for (float hot : {1000.0f, 200.0f}) {
    Image<float> img = RenderSyntheticFrame(f);
    int bright_rows = 0;  // rows whose maximum is a hot pixel (the stripe's pixels reach 160)
    for (int y = 2; y < f.height - 2; y += 6) {
      const int c = int(std::lround(f.stripes[0].CentreU(y)));
      img.At(c + (y % 4 ? 3 : -3), y) = hot;   // 3 px beside the stripe
      img.At(c + 25, y + 2) = hot;             // an isolated one further away
      img.At(c - 20, y + 3) = hot;             // a vertical pair
      img.At(c - 20, y + 4) = hot;
      bright_rows += 4;
    }
    for (auto m : kPeakMethods) {
      SCOPED_TRACE(std::string(MethodName(m)) + " hot " + std::to_string(hot));
      StripeExtractor e(Options(m));
      const auto pts = e.Extract(img.View());
      EXPECT_EQ(int(pts.size()), f.height);
      for (const auto& p : pts) EXPECT_NEAR(p.u, f.stripes[0].CentreU(p.v), NarrowTolerance(m)) << p.v;
      EXPECT_EQ(e.last_rejections().narrow, bright_rows);
    }
    // The same next to a sigma-2 stripe (FWHM 4.7 px, not narrow).
    SyntheticFrame wide = Frame();
    Image<float> wimg = RenderSyntheticFrame(wide);
    for (int y = 2; y < wide.height - 2; y += 6) {
      const int c = int(std::lround(wide.stripes[0].CentreU(y)));
      wimg.At(c + 25, y + 2) = hot;
      wimg.At(c - 20, y + 3) = hot;
      wimg.At(c - 20, y + 4) = hot;
    }
    for (auto m : kPeakMethods) {
      SCOPED_TRACE(std::string(MethodName(m)) + " beside a sigma-2 stripe, hot " + std::to_string(hot));
      const auto pts = StripeExtractor(Options(m)).Extract(wimg.View());
      EXPECT_EQ(int(pts.size()), wide.height);
      for (const auto& p : pts) EXPECT_NEAR(p.u, wide.stripes[0].CentreU(p.v), 0.5 + 1e-9) << p.v;
    }
  }
  // Three hot pixels in a column are a 3-line stripe piece: multicom keeps it.
  Image<float> three = RenderSyntheticFrame(f);
  for (int y = 20; y < 23; ++y) three.At(20, y) = 1000;
  int at_piece = 0;
  for (const auto& p : StripeExtractor(Options(ExtractionMethod::kMultiCom)).Extract(three.View())) {
    at_piece += std::abs(p.u - 20) < 0.01;
  }
  EXPECT_EQ(at_piece, 3);
}

// The raw frame of a colour sensor (RGGB, without --bayer) is not a thin
// stripe: every peak of a sigma-2 stripe is one pixel between dim ones, but a
// red laser's green lines peak at a quarter of the red pixel right next to
// them, and a green laser's green pixels form a comb along the line and a
// quincunx across lines. The narrow-peak rule keeps none of them (max, com and
// multicom give only the points they gave before, peaks at least --min-width
// wide); demosaiced (--bayer) the stripe is found (demosaic_test.cpp).
TEST(NarrowPeaks, RawBayerMosaicIsNotAThinStripe) {
  SyntheticFrame f = Frame();
  const Image<float> scene = RenderSyntheticFrame(f);
  const double red[2][2] = {{1.0, 0.25}, {0.25, 0.05}};   // R G / G B
  const double green[2][2] = {{0.1, 1.0}, {1.0, 0.1}};
  for (const auto* gain : {red, green}) {
    Image<float> raw(scene.width, scene.height, 1);
    for (int y = 0; y < raw.height; ++y)
      for (int x = 0; x < raw.width; ++x) raw.At(x, y) = float(scene.At(x, y) * gain[y & 1][x & 1]);
    for (auto m : kPeakMethods) {
      SCOPED_TRACE(std::string(MethodName(m)) + (gain == red ? " red" : " green"));
      StripeExtractor e(Options(m));
      // Only peaks at least --min-width wide pass (a red pixel in the stripe's
      // tail, whose green neighbours are above its half maximum: as before).
      for (const auto& p : e.Extract(raw.View())) EXPECT_GE(p.width, 1.5) << p.u << ", " << p.v;
      EXPECT_GT(e.last_rejections().narrow, 0);
    }
  }
}

// --min-width 0 keeps every narrow peak (the check is off); a narrow peak is
// checked only below --min-width.
TEST(NarrowPeaks, MinWidthZeroKeepsIsolatedPeaks) {
  Image<float> img(40, 12, 1, 0.0f);
  img.At(10, 5) = 200;
  ExtractionOptions o = Options(ExtractionMethod::kMultiCom);
  EXPECT_TRUE(StripeExtractor(o).Extract(img.View()).empty());
  o.min_width = 0;
  EXPECT_EQ(StripeExtractor(o).Extract(img.View()).size(), 1u);
}

TEST(ExtractionBehaviour, WidthAndStrengthEstimates) {
  // FWHM of a sigma-2 Gaussian is 4.71 px; along a row of a stripe tilted by
  // 8 degrees it is 4.71 / cos(8) = 4.76 px (max/com/multicom measure along the
  // row, Steger across the stripe). Strength ~ peak (200 less pixel averaging).
  SyntheticFrame f = Frame();
  for (auto m : kAll) {
    ExtractionOptions o = Options(m);
    auto pts = ExtractFrom<float>(f, o);
    SCOPED_TRACE(MethodName(m));
    ASSERT_FALSE(pts.empty());
    const double expected = m == ExtractionMethod::kSteger ? 4.71 : 4.71 / std::cos(8 * M_PI / 180);
    // Linear interpolation of half-maximum crossings errs by up to ~0.15 px.
    for (const auto& p : pts) EXPECT_NEAR(p.width, expected, m == ExtractionMethod::kSteger ? 0.02 : 0.2);
    for (const auto& p : pts) EXPECT_NEAR(p.strength, 200, 12);
  }
}

TEST(ExtractionBehaviour, ImageFilesGiveTheSamePoints) {
  // A 16-bit PNG written and read back (ReadImage keeps the sample type)
  // gives exactly the points of the in-memory image.
  SyntheticFrame f = Frame();
  Image<float> scaled = RenderSyntheticFrame(f);
  for (auto& v : scaled.pixels) v *= 257.0f;
  Image<uint16_t> img = QuantizeImage<uint16_t>(scaled);
  auto path = std::filesystem::temp_directory_path() / "lt_extraction_behaviour_16bit.png";
  WriteImage(path, img);
  AnyImage back = ReadImage(path);
  ASSERT_TRUE(std::holds_alternative<Image<uint16_t>>(back));
  ExtractionOptions o = Options(ExtractionMethod::kSteger);
  o.threshold = 50 * 257.0;
  StripeExtractor ex(o);
  auto from_file = ex.Extract(back);
  auto in_memory = ex.Extract(img.View());
  ASSERT_GT(in_memory.size(), 40u);
  ASSERT_EQ(from_file.size(), in_memory.size());
  for (size_t i = 0; i < in_memory.size(); ++i) EXPECT_EQ(from_file[i].u, in_memory[i].u);
  std::filesystem::remove(path);
}

TEST(ExtractionBehaviour, CentreOfMassDoesNotJumpWhenTheMaximumMoves) {
  // A stripe centred between pixels 20 and 21 with exponential tails (like
  // subsurface glow): when pixel 20 or 21 is raised by 1e-6 the maximum moves
  // by a pixel. A window placed on the maximum pixel cuts the tails unevenly
  // and its centroid jumps by about 0.2 px; the self-centred window does not
  // move, and cuts the symmetric stripe symmetrically.
  std::array<double, 2> u{};
  for (int side = 0; side < 2; ++side) {
    Image<float> img(48, 1, 1, 0.0f);
    for (int x = 0; x < img.width; ++x) {
      const double d = x - 20.5;
      img.At(x, 0) = float(std::exp(-0.5 * d * d / 2.25) + 0.3 * std::exp(-std::abs(d) / 2));
    }
    img.At(20 + side, 0) += 1e-6f;
    ExtractionOptions o;
    o.method = ExtractionMethod::kCom;
    o.threshold = 0.1;
    auto pts = StripeExtractor(o).Extract(img.View());
    ASSERT_EQ(pts.size(), 1u);
    u[size_t(side)] = pts[0].u;
    EXPECT_NEAR(pts[0].u, 20.5, 1e-3);
  }
  EXPECT_NEAR(u[0], u[1], 1e-4);
}

TEST(ExtractionBadInput, EmptyImageRoiAndValues) {
  StripeExtractor ex(Options(ExtractionMethod::kCom));
  Image<uint8_t> empty;
  EXPECT_THROW(ex.Extract(empty.View()), InputError);
  Image<uint8_t> img(40, 30, 1, 0);
  ExtractionOptions o = Options(ExtractionMethod::kCom);
  o.roi = PixelRect{30, 0, 20, 10};  // leaves the image on the right
  try {
    StripeExtractor(o).Extract(img.View());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not inside the 40x30 image"), std::string::npos) << e.what();
  }
  Image<float> bad(10, 10, 1, 0.0f);
  bad.At(3, 4) = std::nanf("");
  EXPECT_THROW(StripeExtractor(Options(ExtractionMethod::kSteger)).Extract(bad.View()), InputError);
  bad.At(3, 4) = INFINITY;
  EXPECT_THROW(StripeExtractor(Options(ExtractionMethod::kMax)).Extract(bad.View()), InputError);
  // A 1x1 image is valid and has no stripe.
  Image<uint16_t> tiny(1, 1, 1, 60000);
  for (auto m : kAll) EXPECT_TRUE(StripeExtractor(Options(m)).Extract(tiny.View()).empty());
}

TEST(ExtractionBadInput, OptionsAreChecked) {
  auto expect_bad = [](auto mutate, const char* what) {
    ExtractionOptions o;
    mutate(o);
    try {
      o.Check();
      ADD_FAILURE() << "expected InputError for " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_bad([](ExtractionOptions& o) { o.threshold = -1; }, "threshold");
  expect_bad([](ExtractionOptions& o) { o.threshold = 10, o.high_threshold = 5; }, "high_threshold");
  expect_bad([](ExtractionOptions& o) { o.expected_width = 0; }, "expected_width");
  expect_bad([](ExtractionOptions& o) { o.min_width = 5, o.max_width = 2; }, "max_width");
  expect_bad([](ExtractionOptions& o) { o.roi = PixelRect{0, 0, 0, 5}; }, "roi");
  expect_bad([](ExtractionOptions& o) { o.channel = 0, o.channel_weights = {1}; }, "channel");
  expect_bad([](ExtractionOptions& o) { o.channel_weights = {0, 0}; }, "channel_weights");
  expect_bad([](ExtractionOptions& o) { o.sigma = 0.2; }, "sigma");
  expect_bad([](ExtractionOptions& o) { o.threads = -1; }, "threads");
  EXPECT_THROW(ParseMethod("gauss", "--method"), InputError);
  EXPECT_EQ(ParseMethod("multicom", "--method"), ExtractionMethod::kMultiCom);
  EXPECT_THROW(ParseAxis("diagonal", "--axis"), InputError);
}

// Candidate peaks dropped by the width checks are counted, and the notes name
// the counts and the option; steger's "nothing found" note names --width.
TEST(ExtractionRejections, CountedAndNamedInNotes) {
  Image<uint8_t> img(40, 10, 1, 0);
  // One-pixel peaks on lines whose neighbours are dark there: hot pixels (a
  // column of them on every row would be a thin stripe).
  for (int y = 0; y < 10; ++y) img.At(y % 2 ? 11 : 7, y) = 200;
  ExtractionOptions o;
  o.method = ExtractionMethod::kMultiCom;
  StripeExtractor e(o);
  EXPECT_TRUE(e.Extract(img.View()).empty());
  EXPECT_EQ(e.last_rejections().narrow, 10);
  EXPECT_EQ(e.last_rejections().wide, 0);
  auto notes = WidthRejectionNotes(e.last_rejections(), o);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_EQ(notes[0], "10 candidate peaks were narrower than --min-width 1.5 px without continuing on the adjacent "
                      "search lines and rejected (hot pixels or noise spikes; lower --min-width to keep them)");
  // A wide plateau with --max-width (com, one candidate per row).
  for (int y = 0; y < 10; ++y)
    for (int x = 15; x < 30; ++x) img.At(x, y) = 250;
  o.method = ExtractionMethod::kCom;
  o.max_width = 8;
  StripeExtractor wide(o);
  EXPECT_TRUE(wide.Extract(img.View()).empty());
  EXPECT_EQ(wide.last_rejections().wide, 10);
  EXPECT_EQ(wide.last_rejections().narrow, 0);
  notes = WidthRejectionNotes(wide.last_rejections(), o);
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("10 candidate peaks were wider than --max-width 8 px"), std::string::npos) << notes[0];
  // Counts are per call.
  Image<uint8_t> dark(40, 10, 1, 0);
  wide.Extract(dark.View());
  EXPECT_EQ(wide.last_rejections().wide, 0);
  o.method = ExtractionMethod::kSteger;
  EXPECT_EQ(NoStripePointsNote(o).find("--width"), std::string::npos);  // measured on each frame
  o.expected_width = 5;
  EXPECT_NE(NoStripePointsNote(o).find("--width (5 px)"), std::string::npos);
}

// --background local (BackgroundMode::kLocal). Ambient light under a stripe
// (sigma 2 px, peak 1000, threshold 100, 7 degrees, float image): a ramp of
// 4 DN/px (50 + 4 u) and a broad blob (500 exp(-((u-95)^2 + ((v-24)/3)^2) / 800),
// 15 px right of the stripe, sigma 20 px). Each case shows the failure with one
// background level first (so the test fails when the local background stops
// helping), then the local background's errors.
struct AmbientCase {
  const char* name;
  double (*ambient)(double u, double v);
};
const AmbientCase kAmbient[] = {
    {"ramp", [](double u, double) { return 50 + 4.0 * u; }},
    {"blob", [](double u, double v) { return 500 * std::exp(-((u - 95) * (u - 95) + (v - 24) * (v - 24) / 9) / 800); }},
};

Image<float> AmbientImage(const SyntheticFrame& f, double (*ambient)(double, double)) {
  Image<float> img = RenderSyntheticFrame(f);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.At(x, y) += float(ambient(x, y));
  return img;
}

ErrorStats ExtractAmbient(const SyntheticFrame& f, const Image<float>& img, ExtractionMethod m, BackgroundMode mode,
                          double max_width = 0) {
  ExtractionOptions o;
  o.method = m;
  o.threshold = 100;
  o.background_mode = mode;
  o.max_width = max_width;
  StripeExtractor e(o);
  return RowErrors(e.Extract(img.View()), f);
}

TEST(LocalBackground, AmbientRampAndBlob) {
  SyntheticFrame f;
  f.width = 160;
  f.height = 48;
  f.stripes.push_back(LineStripe(80.37, 24, 7, 2, 1000));
  for (const AmbientCase& a : kAmbient) {
    SCOPED_TRACE(a.name);
    const Image<float> img = AmbientImage(f, a.ambient);
    // One level: com is pulled towards the brighter side (0.31 px on the ramp,
    // 0.85 px on the blob), multicom finds no point while the ambient is above
    // the threshold (its run reaches the line's end), or none right on the blob.
    const ErrorStats com_level = ExtractAmbient(f, img, ExtractionMethod::kCom, BackgroundMode::kLevel);
    EXPECT_GT(std::abs(com_level.mean), 0.25);
    const ErrorStats mc_level = ExtractAmbient(f, img, ExtractionMethod::kMultiCom, BackgroundMode::kLevel);
    EXPECT_TRUE(mc_level.points < f.height / 2 || mc_level.max_abs > 0.5) << mc_level.points << " " << mc_level.max_abs;
    // Local background: every row, all points on the stripe. On the ramp the
    // line through the flanks is the ambient itself, leaving each method's
    // noise-free bias (< 0.005 px). The blob curves under the stripe; the chord
    // between the flanks (about +-8 px) misses it by a few DN there and that
    // leaves 0.04 px (com) and 0.02 px (multicom). The blob is itself a peak
    // above its local background (FWHM 47 px): --max-width 15 passes over it.
    const double tol = a.name[0] == 'r' ? 0.005 : 0.05;
    for (auto m : {ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
      SCOPED_TRACE(MethodName(m));
      const ErrorStats e = ExtractAmbient(f, img, m, BackgroundMode::kLocal, 15);
      EXPECT_EQ(e.points, f.height);
      EXPECT_EQ(e.unmatched, 0);
      EXPECT_LT(e.max_abs, tol);
    }
    // max: pixel accuracy, as without ambient.
    const ErrorStats mx = ExtractAmbient(f, img, ExtractionMethod::kMax, BackgroundMode::kLocal, 15);
    EXPECT_EQ(mx.points, f.height);
    EXPECT_LE(mx.max_abs, 0.51);
  }
}

// With 1% noise (10 DN) on the ramp the errors are noise, about as without
// ambient (rms 0.03 com, 0.02 multicom measured on 96 rows).
TEST(LocalBackground, NoisyRamp) {
  SyntheticFrame f;
  f.width = 160;
  f.height = 48;
  f.noise_sigma = 10;
  f.stripes.push_back(LineStripe(80.37, 24, 7, 2, 1000));
  const Image<float> img = AmbientImage(f, kAmbient[0].ambient);
  for (auto m : {ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
    SCOPED_TRACE(MethodName(m));
    const ErrorStats e = ExtractAmbient(f, img, m, BackgroundMode::kLocal);
    EXPECT_EQ(e.points, f.height);
    EXPECT_EQ(e.unmatched, 0);
    EXPECT_LT(e.rms, 0.06);
  }
}

// Two sigma-1.5 stripes 10 px apart on the ramp: multicom finds both in every
// row. A flank that would pass the valley between them sits at the valley (its
// level the valley pixel), so each stripe's background line rises by the
// other's tail there (about 8 DN): 0.01 px measured (0.0015 px without ramp and
// with one level). com finds one of them, 0.025 px.
TEST(LocalBackground, TwoStripesTenPixelsApart) {
  SyntheticFrame f;
  f.width = 160;
  f.height = 48;
  f.stripes.push_back(LineStripe(70.37, 24, 5, 1.5, 1000));
  f.stripes.push_back(LineStripe(80.37, 24, 5, 1.5, 1000));
  const Image<float> img = AmbientImage(f, kAmbient[0].ambient);
  const ErrorStats mc = ExtractAmbient(f, img, ExtractionMethod::kMultiCom, BackgroundMode::kLocal);
  EXPECT_EQ(mc.points, 2 * f.height);
  EXPECT_EQ(mc.unmatched, 0);
  EXPECT_LT(mc.max_abs, 0.02);
  const ErrorStats com = ExtractAmbient(f, img, ExtractionMethod::kCom, BackgroundMode::kLocal);
  EXPECT_EQ(com.points, f.height);
  EXPECT_LT(com.max_abs, 0.04);
}

// steger ignores the local background (its second derivative is blind to a
// linear one): the same points either way.
TEST(LocalBackground, StegerIgnoresIt) {
  SyntheticFrame f = Frame();
  Image<float> img = RenderSyntheticFrame(f);
  ExtractionOptions o = Options(ExtractionMethod::kSteger);
  const auto level = StripeExtractor(o).Extract(img.View());
  o.background_mode = BackgroundMode::kLocal;
  const auto local = StripeExtractor(o).Extract(img.View());
  ASSERT_FALSE(level.empty());
  ASSERT_EQ(level.size(), local.size());
  for (size_t i = 0; i < level.size(); ++i) EXPECT_EQ(level[i].u, local[i].u);
}

TEST(LocalBackground, ParseBackground) {
  double level = 7;
  BackgroundMode mode = BackgroundMode::kLevel;
  ParseBackground("local", "--background", &level, &mode);
  EXPECT_EQ(mode, BackgroundMode::kLocal);
  EXPECT_EQ(level, 7);
  ParseBackground("12.5", "--background", &level, &mode);
  EXPECT_EQ(mode, BackgroundMode::kLevel);
  EXPECT_EQ(level, 12.5);
  EXPECT_THROW(ParseBackground("lokal", "--background", &level, &mode), InputError);
  EXPECT_THROW(ParseBackground("", "--background", &level, &mode), InputError);
}

}  // namespace
}  // namespace lt::test
