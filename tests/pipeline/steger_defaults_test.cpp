// Steger's defaults: a stripe that the other methods find at the threshold is
// found by steger too, whatever its width. Its high threshold used to default to
// twice the threshold, so a dim stripe (the demo's dim frame: peaks 1.1 to 1.7
// times the default threshold) kept only the few chains that reached twice it;
// its expected width was 5 px, so a wider stripe read dimmer than its peak.
#include <gtest/gtest.h>

#include <set>

#include "stripe_test_util.h"

namespace lt::test {
namespace {

std::set<int> Rows(const std::vector<StripePoint>& points) {
  std::set<int> rows;
  for (const auto& p : points) rows.insert(int(p.v));
  return rows;
}

TEST(StegerDefaults, DimStripeIsFoundWhereCentreOfMassFindsIt) {
  // Peak 1.4 x the threshold, 1% noise (of the peak), FWHM from 2.5 px up to
  // the expected width (5 px); the threshold reads as the peak of a stripe of
  // the expected width, so narrower stripes read brighter, wider ones dimmer.
  for (double fwhm : {2.5, 3.6, 5.0}) {
    SCOPED_TRACE("FWHM " + std::to_string(fwhm));
    SyntheticFrame f;
    f.width = 120;
    f.height = 80;
    f.noise_sigma = 1.4;
    f.seed = 5;
    f.stripes.push_back(LineStripe(60.3, 40, 4, fwhm / 2.3548, 140));
    ExtractionOptions o;
    o.threshold = 100;
    o.method = ExtractionMethod::kCom;
    const auto com = ExtractFrom<float>(f, o);
    o.method = ExtractionMethod::kSteger;
    const auto steger = ExtractFrom<float>(f, o);
    const std::set<int> com_rows = Rows(com), steger_rows = Rows(steger);
    ASSERT_GE(com_rows.size(), 76u);  // every row
    // Steger gives no points within ceil(3 sigma) = 5 rows of the top and bottom.
    int missing = 0;
    for (int v : com_rows) missing += v >= 5 && v < f.height - 5 && !steger_rows.count(v);
    EXPECT_EQ(missing, 0);
    const ErrorStats e = RowErrors(steger, f);
    EXPECT_EQ(e.unmatched, 0);
    EXPECT_LT(e.rms, 0.05);  // 1% noise: 0.006-0.017 px in ExtractionAccuracy.StegerNoisyUnder005
  }
}

TEST(StegerDefaults, WidthIsMeasuredOnTheFrame) {
  // Stripes from 2.5 to 16 px FWHM, upright and tilted 35 degrees, peak 1.5 x the
  // threshold, 1% noise. With a fixed 5 px expected width a 12 px stripe reads
  // at 0.46 of its peak (-r'' = A s / S^3), under the threshold: no points.
  for (double fwhm : {2.5, 6.0, 12.0, 16.0}) {
    for (double angle : {0.0, 35.0}) {
      SCOPED_TRACE("FWHM " + std::to_string(fwhm) + " angle " + std::to_string(angle));
      SyntheticFrame f;
      f.width = 200;
      f.height = 100;
      f.noise_sigma = 1.5;
      f.seed = 3;
      f.stripes.push_back(LineStripe(100.3, 50, angle, fwhm / 2.3548, 150));
      ExtractionOptions o;
      o.threshold = 100;
      o.method = ExtractionMethod::kSteger;
      StripeExtractor extractor(o);
      Image<float> img = QuantizeImage<float>(RenderSyntheticFrame(f));
      const auto points = extractor.Extract(img.View());
      // The width across the stripe, from the peaks' FWHM along the rows and the
      // stripe's tilt: their 90th percentile, so at or above the FWHM by the
      // scatter of the per-row estimates (noise, the tilt read from whole-pixel
      // maxima 4 rows apart): measured 1.07 to 1.18 times it.
      EXPECT_GE(extractor.resolved_options().expected_width, 0.95 * fwhm);
      EXPECT_LE(extractor.resolved_options().expected_width, 1.25 * fwhm);
      const int margin = extractor.resolved_options().EdgeLinesWithoutPoints();
      const ErrorStats e = RowErrors(points, f);
      EXPECT_EQ(e.unmatched, 0);
      EXPECT_GE(e.points, f.height - 2 * margin - 2);
      EXPECT_LT(e.rms, 0.1);  // 1% noise on a stripe up to 16 px wide
    }
  }
  // A width that is given is used as given.
  ExtractionOptions o;
  o.method = ExtractionMethod::kSteger;
  o.expected_width = 7;
  StripeExtractor extractor(o);
  Image<float> dark(40, 30, 1, 0.f);
  extractor.Extract(dark.View());
  EXPECT_EQ(extractor.resolved_options().expected_width, 7);
}

TEST(StegerDefaults, WidthOfSaturatedStripesBesideEachOther) {
  // A diffractive element's 9 sheets, 6.5 px apart, saturated (peak 560 in an
  // 8-bit frame): between two stripes the line stays at 58-67% of full scale,
  // above half of it, so each peak's FWHM ran on past its neighbours to the
  // outer flanks of all nine (about 56 px); the filter made of that width
  // smoothed them into one (no points). The width is now bounded by the
  // valleys between them: 5.2 px.
  SyntheticFrame f;
  f.width = 140;
  f.height = 60;
  f.noise_sigma = 1.5;
  f.seed = 7;
  const double spacing = 6.5;
  for (int k = 0; k < 9; ++k) f.stripes.push_back(LineStripe(40.2 + spacing * k, 30, 3, 1.6, 560));
  ExtractionOptions o;
  o.threshold = 100;
  o.method = ExtractionMethod::kSteger;
  StripeExtractor extractor(o);
  Image<uint8_t> img = QuantizeImage<uint8_t>(RenderSyntheticFrame(f));
  const auto points = extractor.Extract(img.View());
  const double w = extractor.resolved_options().expected_width;
  EXPECT_GE(w, 0.6 * spacing);
  EXPECT_LE(w, spacing);
  // All nine on the rows beyond ceil(3 sigma) = 5 of the top and bottom (450 points).
  const ErrorStats e = RowErrors(points, f);
  EXPECT_EQ(e.unmatched, 0);
  EXPECT_GE(e.points, 9 * 48);
  EXPECT_LT(e.rms, 0.5);  // clipped plateaus
}

TEST(StegerDefaults, NoiseIsNotAStripe) {
  // Noise of 10% of the threshold (its 3-sigma tail is far below it) and no
  // stripe: no chain reaches the threshold.
  SyntheticFrame f;
  f.width = 120;
  f.height = 80;
  f.background = 20;
  f.noise_sigma = 10;
  f.seed = 9;
  ExtractionOptions o;
  o.threshold = 100;
  o.background = 20;
  o.method = ExtractionMethod::kSteger;
  EXPECT_TRUE(ExtractFrom<float>(f, o).empty());
}

}  // namespace
}  // namespace lt::test
