// Extraction of many stripes close together (a diffractive element's sheets):
// saturated stripes a few pixels apart with light between them.
#include <gtest/gtest.h>

#include "stripe_test_util.h"

namespace lt::test {
namespace {

// Five stripes 6.5 px apart, clipped at saturation (peak 460 in an 8-bit frame,
// sigma 1.8 px): between two of them the line stays at 73-80% of full scale
// (186-203), above half of the clipped peak's height over the threshold, so
// multicom took all five for one stripe and gave one point in the middle. Two
// plateaus at the run's top with a valley a quarter of its height lower are
// two stripes.
TEST(ExtractionDense, MultiComSplitsSaturatedStripesAtTheirValleys) {
  SyntheticFrame f;
  f.width = 100;
  f.height = 40;
  f.noise_sigma = 1.5;
  f.seed = 11;
  const double spacing = 6.5;
  for (int k = 0; k < 5; ++k) f.stripes.push_back(LineStripe(30.3 + spacing * k, 20, 4, 1.8, 460));
  ExtractionOptions o;
  o.threshold = 100;
  o.method = ExtractionMethod::kMultiCom;
  const auto points = ExtractFrom<uint8_t>(f, o);
  const ErrorStats e = RowErrors(points, f, 1.0);
  EXPECT_EQ(e.unmatched, 0);              // no point between two stripes
  EXPECT_EQ(e.points, 5 * f.height);      // every stripe on every row
  EXPECT_LT(e.rms, 0.5);                  // clipped plateaus: the centroid of the part above the valley
}

}  // namespace
}  // namespace lt::test
