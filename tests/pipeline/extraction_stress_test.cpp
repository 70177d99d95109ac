// Stripe shapes of the stress pass (docs/extraction.md, "Stress pass";
// tools/experiments/exp_stripe_stress.cpp): what each method must give on
// shapes a scanner produces beyond the Gaussian ones it was tuned on.
#include <gtest/gtest.h>

#include <cmath>

#include "stripe_test_util.h"

namespace lt::test {
namespace {

ExtractionOptions Options(ExtractionMethod m, double threshold) {
  ExtractionOptions o;
  o.method = m;
  o.threshold = threshold;
  return o;
}

TEST(StripeStress, ComOnAWideSaturatedStripeAtASteepAngle) {
  // An 8-bit sigma-10 stripe clipped at 20x its peak, at 60 degrees to the
  // rows of a 320-px frame: a plateau of ~98 px and a FWHM of ~108 px along
  // each row, light above the threshold 65 px either side of the centre, whose
  // row crossings lie 124-196 px from the left. com's border rule asked for a
  // FWHM of room beyond the plateau, counting the plateau twice (157 px either
  // side): 2 of 96 rows had a point, max and multicom every row. Now 96, within
  // 0.16 px (measured 0.052 rms, 0.161 max).
  SyntheticFrame f;
  f.width = 320;
  f.height = 96;
  f.noise_sigma = 2;
  f.seed = 3;
  f.stripes.push_back(LineStripe(160.3, 48, 60, 10, 20 * 255));
  for (ExtractionMethod m : {ExtractionMethod::kCom, ExtractionMethod::kMultiCom}) {
    SCOPED_TRACE(MethodName(m));
    ErrorStats e = RowErrors(ExtractFrom<uint8_t>(f, Options(m, 25.5)), f, 5);
    EXPECT_EQ(e.unmatched, 0);
    EXPECT_EQ(e.points, f.height);  // com before: 2
    EXPECT_LT(e.rms, 0.1);
    EXPECT_LT(e.max_abs, 0.25);
  }
}

TEST(StripeStress, ComBesideTheBorderOnASaturatedStripe) {
  // The same stripe upright. With the plateau's centre 33.3 px from the left
  // edge (plateau 24.5 px either side, half-maximum crossings ~27 px, light
  // above the threshold 32.6 px) the window shrinks symmetrically to the
  // border and the centre is exact; at 20.3 px the plateau reaches the border
  // and no row gives a point.
  for (double u : {33.3, 20.3}) {
    SyntheticFrame f;
    f.width = 160;
    f.height = 48;
    f.noise_sigma = 2;
    f.stripes.push_back(LineStripe(u, 24, 0, 10, 20 * 255));
    SCOPED_TRACE(testing::Message() << "centre " << u);
    const std::vector<StripePoint> points = ExtractFrom<uint8_t>(f, Options(ExtractionMethod::kCom, 25.5));
    if (u < 30) {
      EXPECT_TRUE(points.empty());
      continue;
    }
    ErrorStats e = RowErrors(points, f, 5);
    EXPECT_EQ(e.points, f.height);
    EXPECT_LT(e.max_abs, 0.1);
  }
}

}  // namespace
}  // namespace lt::test
