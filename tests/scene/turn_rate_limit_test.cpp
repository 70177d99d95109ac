// Tests of scene/turn_rate_limit.h and of orientation rules held to a turn rate:
// closed forms for a step, a ramp, a reversal and a turn across +-180 degrees.
#include "scene/turn_rate_limit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "orientation_test_util.h"

namespace lt {
namespace {

using namespace orientation_test;

constexpr double kDeg = M_PI / 180;
// The slew starts at most one 1 ms step late: its heading is then up to rate x 1 ms behind.
constexpr double kStepS = 1e-3;

double AngleDiff(double a, double b) { return std::abs(std::remainder(a - b, 2 * M_PI)); }

TEST(TurnRateLimit, StepIsTurnedAtTheLimitThenFollowed) {
  auto followed = [](double t) { return t < 1.0 ? 0.0 : 90 * kDeg; };
  const double rate = 90 * kDeg;  // the 90 degree step takes 1 s
  TurnRateLimit limit(followed, 0, 4, rate);
  EXPECT_EQ(limit.HeadingAt(0.5, followed), 0.0);
  EXPECT_NEAR(limit.HeadingAt(1.5, followed), 45 * kDeg, rate * kStepS + 1e-12);
  EXPECT_TRUE(limit.SlewingAt(1.5));
  EXPECT_FALSE(limit.SlewingAt(2.1));
  EXPECT_EQ(limit.HeadingAt(2.5, followed), 90 * kDeg);  // following exactly
  EXPECT_EQ(limit.slews(), 1u);
  EXPECT_NEAR(limit.longest_slew_s(), 1.0, kStepS + 1e-8);
  EXPECT_NEAR(limit.longest_slew_start_s(), 1.0, kStepS + 1e-12);
  EXPECT_EQ(limit.max_rate_rad_s(), rate);
}

TEST(TurnRateLimit, SlowerHeadingIsFollowedExactly) {
  auto followed = [](double t) { return std::remainder(0.5 * t * t, 2 * M_PI); };  // rate t, up to 3 rad/s
  TurnRateLimit limit(followed, 0, 3, 3.5);
  for (double t : {0.0, 0.7, 1.9, 2.999}) EXPECT_EQ(limit.HeadingAt(t, followed), followed(t)) << t;
  EXPECT_EQ(limit.slews(), 0u);
  EXPECT_NEAR(limit.max_rate_rad_s(), 3.0, 1e-3);  // the largest step at its end: (3 - dt/2) rad/s
  EXPECT_NEAR(limit.max_rate_time_s(), 3.0, 2 * kStepS);
}

TEST(TurnRateLimit, FastRampIsCaughtUpWhereTheLimitMeetsIt) {
  // The rule turns at a = 2 rad/s for T = 0.5 s, then holds 1 rad; the limit w = 0.8 rad/s
  // slews from t = 0 and meets it at a T / w = 1.25 s.
  const double a = 2, T = 0.5, w = 0.8;
  auto followed = [&](double t) { return a * std::min(t, T); };
  TurnRateLimit limit(followed, 0, 2, w);
  EXPECT_NEAR(limit.HeadingAt(0.25, followed), w * 0.25, w * kStepS + 1e-12);
  EXPECT_NEAR(limit.HeadingAt(1.2, followed), w * 1.2, w * kStepS + 1e-12);
  EXPECT_EQ(limit.HeadingAt(1.3, followed), a * T);
  EXPECT_NEAR(limit.longest_slew_s(), a * T / w, kStepS + 1e-8);
  // Continuous where the slew ends.
  const double end = limit.longest_slew_start_s() + limit.longest_slew_s();
  EXPECT_NEAR(limit.HeadingAt(end - 1e-7, followed), limit.HeadingAt(end + 1e-7, followed), 1e-6);
}

TEST(TurnRateLimit, TurnsTheShortWayAcrossTheWrap) {
  // 170 -> -170 degrees is 20 degrees counter-clockwise, through 180.
  auto followed = [](double t) { return t < 0.1 ? 170 * kDeg : -170 * kDeg; };
  TurnRateLimit limit(followed, 0, 1, 100 * kDeg);
  const double mid = limit.HeadingAt(0.2, followed);
  EXPECT_NEAR(AngleDiff(mid, 180 * kDeg), 0.0, 100 * kDeg * kStepS + 1e-9);
  EXPECT_NEAR(limit.longest_slew_s(), 0.2, kStepS + 1e-8);
  EXPECT_EQ(limit.HeadingAt(0.5, followed), -170 * kDeg);
}

TEST(TurnRateLimit, SlewEndsWhereItMeetsTheRuleEvenWhereTheRuleCrossesTheWrap) {
  // The rule steps to a at t1 = 1.0005 s (inside a step, so the 2 rad/s slew starts at the
  // step's start s0) and turns on at 0.5 rad/s: the slew meets it at
  // T = (a + 2 s0 - 0.5 t1) / 1.5, and a is chosen so that the rule crosses +-pi d later,
  // within the same 1 ms step. The meeting, not the crossing, ends the slew.
  const double t1 = 1.0005;
  for (double d : {1e-6, 1e-5}) {
    const double a = (2 * t1 + 3 * M_PI - 2 - 1.5 * d) / 4;  // cross - meet = d with s0 = 1
    auto followed = [&](double t) { return t < t1 ? 0.0 : std::remainder(a + 0.5 * (t - t1), 2 * M_PI); };
    TurnRateLimit limit(followed, 0, 5, 2.0);
    const double s0 = limit.longest_slew_start_s();
    ASSERT_NEAR(s0, 1.0, 1e-9);
    const double meet = (a + 2 * s0 - 0.5 * t1) / 1.5;
    const double cross = t1 + 2 * (M_PI - a);
    ASSERT_NEAR(cross - meet, d, 1e-9);  // the case meant
    EXPECT_NEAR(s0 + limit.longest_slew_s(), meet, 1e-8) << d;
  }
}

TEST(TurnRateLimit, ReversalTakesHalfATurnAtTheLimit) {
  auto followed = [](double t) { return t < 1 ? 0.0 : M_PI; };
  TurnRateLimit limit(followed, 0, 5, M_PI / 2);
  EXPECT_NEAR(limit.longest_slew_s(), 2.0, kStepS + 1e-8);
  EXPECT_NEAR(AngleDiff(limit.HeadingAt(2, followed), M_PI / 2), 0.0, M_PI / 2 * kStepS + 1e-9);
  EXPECT_EQ(limit.HeadingAt(3.5, followed), M_PI);
}

TEST(TurnRateLimit, WindingLimitUnwindsAWholeTurnTheOtherWay) {
  // The rule turns at 1 rad/s for ever; held to 4 rad/s and 270 degrees of winding the
  // scanner follows until it has wound 270 degrees, then turns back at 4 rad/s to the
  // rule's heading a turn lower, which it meets after 2 pi / (4 + 1) s, and so on.
  auto followed = [](double t) { return std::remainder(t, 2 * M_PI); };
  const double rate = 4, winding = 1.5 * M_PI;
  TurnRateLimit limit(followed, 0, 20, rate, winding);
  const double t_unwind = winding;  // the rule reaches 270 degrees at t = 3 pi / 2
  EXPECT_EQ(limit.HeadingAt(t_unwind - 0.01, followed), followed(t_unwind - 0.01));
  EXPECT_TRUE(limit.SlewingAt(t_unwind + 0.5));
  EXPECT_NEAR(AngleDiff(limit.HeadingAt(t_unwind + 0.5, followed), winding - rate * 0.5), 0.0, rate * kStepS + 1e-9);
  EXPECT_NEAR(limit.longest_slew_s(), 2 * M_PI / (rate + 1), kStepS + 1e-8);
  EXPECT_FALSE(limit.SlewingAt(t_unwind + 2 * M_PI / (rate + 1) + 0.01));
  // Every 2 pi of the rule's turning (after the first 3 pi / 2) costs one unwind.
  EXPECT_EQ(limit.unwinds(), 3u);  // at t = 4.71, 11.0, 17.3
  EXPECT_LE(limit.max_winding_rad(), winding + 1e-12);
  EXPECT_GT(limit.max_winding_rad(), winding - 1e-2);
  // Without the winding limit it follows all the way.
  TurnRateLimit free(followed, 0, 20, rate);
  EXPECT_EQ(free.slews(), 0u);
  EXPECT_NEAR(free.max_winding_rad(), 20, 1e-9);
}

TEST(TurnRateLimit, UnwindsEarlyWhereItCostsLeastAndFinishesTheTurn) {
  // As above, but unwinding costs least in t = [4, 4.5] s (a travel move): wound 4 rad
  // (229 degrees, over half a turn) there, the scanner unwinds at once, and keeps turning
  // the same way after the window closes until it has caught up, 2 pi / 5 s later.
  auto followed = [](double t) { return std::remainder(t, 2 * M_PI); };
  auto travel = [](double t) { return t >= 4.0 && t <= 4.5; };
  const double rate = 4, winding = 1.5 * M_PI;
  TurnRateLimit limit(followed, 0, 6, rate, winding, travel);
  EXPECT_EQ(limit.HeadingAt(3.99, followed), followed(3.99));
  EXPECT_TRUE(limit.SlewingAt(4.8));  // past the window, still unwinding
  EXPECT_NEAR(AngleDiff(limit.HeadingAt(4.8, followed), 4.0 - rate * 0.8), 0.0, rate * kStepS + 1e-9);
  EXPECT_NEAR(limit.longest_slew_start_s(), 4.0, kStepS + 1e-12);
  EXPECT_NEAR(limit.longest_slew_s(), 2 * M_PI / (rate + 1), kStepS + 1e-8);
  EXPECT_EQ(limit.HeadingAt(5.5, followed), followed(5.5));
  EXPECT_EQ(limit.unwinds(), 1u);  // and none at 3 pi / 2 = 4.71 s, where the limit alone would
  EXPECT_NEAR(limit.max_winding_rad(), 4.0, kStepS + 1e-9);
  // Under half a turn a travel move does not unwind.
  TurnRateLimit early(followed, 0, 3, rate, winding, [](double) { return true; });
  EXPECT_EQ(early.unwinds(), 0u);
}

TEST(TurnRateLimit, BadLimitsAreRefused) {
  auto followed = [](double) { return 0.0; };
  EXPECT_THROW(TurnRateLimit(followed, 0, 1, 0), std::invalid_argument);
  EXPECT_THROW(TurnRateLimit(followed, 0, 1, -1), std::invalid_argument);
  EXPECT_THROW(TurnRateLimit(followed, 0, 1, NAN), std::invalid_argument);
  EXPECT_THROW(TurnRateLimit(followed, 1, 0, 1), std::invalid_argument);
  EXPECT_THROW(TurnRateLimit(followed, 0, 1, 1, 3.0), std::invalid_argument);  // under 180 degrees
  OrientationOptions o;
  o.max_turn_rad_s = -1;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.max_turn_rad_s = 0;
  o.max_winding_rad = 2 * M_PI;
  EXPECT_THROW(o.Check(), std::invalid_argument);  // nothing to unwind at
}

// A 40 mm square at 20 mm/s: corners at t = 2, 4 and 6 s.
constexpr const char* kSquare = "G0 F1200 X0 Y0\nG1 X40\nG1 Y40\nG1 X0\nG1 Y0\n";

TEST(TurnRateLimit, EveryRuleHeldToTheLimit) {
  for (OrientationMode mode : {OrientationMode::kHeading, OrientationMode::kCaster}) {
    OrientationOptions o;
    o.mode = mode;
    o.max_turn_rad_s = 90 * kDeg;
    ToolpathOrientation limited(Path(kSquare), o);
    ToolpathOrientation rule = Orientation(Path(kSquare), mode);
    const TurnRates r = limited.ComputeTurnRates();
    EXPECT_EQ(r.max_rate_rad_s, o.max_turn_rad_s) << OrientationModeName(mode);
    EXPECT_EQ(r.jumps, 0u);
    EXPECT_EQ(r.slews, 3u);
    // Sampled at 0.1 ms: no step turns faster than the limit.
    double worst = 0, prev = limited.HeadingAt(0);
    for (double t = 1e-4; t <= 8; t += 1e-4) {
      const double h = limited.HeadingAt(t);
      worst = std::max(worst, AngleDiff(h, prev) / 1e-4);
      prev = h;
    }
    EXPECT_LE(worst, o.max_turn_rad_s * (1 + 1e-6)) << OrientationModeName(mode);
    // Between corners, once caught up, the rule's heading itself.
    EXPECT_EQ(limited.HeadingAt(3.9), rule.HeadingAt(3.9)) << OrientationModeName(mode);
  }
  // Heading mode: each 90 degree corner takes 1 s at 90 deg/s.
  OrientationOptions o;
  o.mode = OrientationMode::kHeading;
  o.max_turn_rad_s = 90 * kDeg;
  const ToolpathOrientation limited(Path(kSquare), o);
  EXPECT_NEAR(limited.ComputeTurnRates().longest_slew_s, 1.0, kStepS + 1e-8);
  EXPECT_NEAR(limited.HeadingAt(2.5), 45 * kDeg, 90 * kDeg * kStepS + 1e-12);
}

}  // namespace
}  // namespace lt
