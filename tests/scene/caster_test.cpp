// Scanner orientation along a toolpath: fixed, heading and virtual caster. The
// caster is the mean of unit tangents over a path-length window (checked against a
// numerical mean), safe across the +-180 degree wrap; turn rates are checked against
// closed forms (v / r on an arc, 2 v / w for the caster at a sharp corner) and
// against finite differences of the heading itself.
#include "scene/caster.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "orientation_test_util.h"

namespace lt {
namespace {

using namespace orientation_test;

// A 40 mm square at 20 mm/s, sharp corners.
const char* kSharpSquare = "G1 F1200 X40 Y0\nG1 X40 Y40\nG1 X0 Y40\nG1 X0 Y0\n";

// The same square with its corners rounded to radius r (mm) by G3 arcs.
std::string RoundedSquare(double r) {
  std::ostringstream g;
  g << "G0 F1200 X" << r << " Y0\n"
    << "G1 X" << 40 - r << " Y0\nG3 X40 Y" << r << " I0 J" << r << "\n"
    << "G1 X40 Y" << 40 - r << "\nG3 X" << 40 - r << " Y40 I" << -r << " J0\n"
    << "G1 X" << r << " Y40\nG3 X0 Y" << 40 - r << " I0 J" << -r << "\n"
    << "G1 X0 Y" << r << "\nG3 X" << r << " Y0 I" << r << " J0\n";
  return g.str();
}

TEST(Caster, SharpCornerClosedForms) {
  auto path = Path(kSharpSquare);
  const double v = 0.02, w = 0.01;
  // Heading: straight moves never turn; the three corners are jumps of 90 degrees.
  TurnRates heading = Orientation(path, OrientationMode::kHeading).ComputeTurnRates();
  EXPECT_EQ(heading.max_rate_rad_s, 0.0);
  EXPECT_EQ(heading.jumps, 3u);
  EXPECT_NEAR(heading.MaxJumpDeg(), 90.0, 1e-9);
  EXPECT_NEAR(std::remainder(heading.max_jump_time_s, 2.0), 0.0, 1e-12);  // t = 2, 4 or 6 s
  // Caster: with the nozzle a past a corner and the tail w - a before it, the heading
  // is atan2(a, w - a), turning at w v / ((w - a)^2 + a^2): 2 v / w at a = w / 2.
  ToolpathOrientation caster = Orientation(path, OrientationMode::kCaster);
  TurnRates c = caster.ComputeTurnRates();
  EXPECT_NEAR(c.max_rate_rad_s, 2 * v / w, 1e-9);
  EXPECT_NEAR(c.MaxRateDegS(), 2 * v / w * 180 / M_PI, 1e-6);
  EXPECT_EQ(c.jumps, 0u);
  double t_peak = 2.0 + (w / 2) / v;  // one of the corners (all three peak equally)
  EXPECT_NEAR(std::remainder(c.max_rate_time_s - t_peak, 2.0), 0.0, 1e-9);
  for (double a : {0.001, 0.004, 0.005, 0.009}) {
    EXPECT_NEAR(caster.HeadingAt(2.0 + a / v), std::atan2(a, w - a), 1e-12) << a;
  }
  // Fixed never turns.
  ToolpathOrientation fixed = Orientation(path, OrientationMode::kFixed);
  EXPECT_EQ(fixed.HeadingAt(3.3), 0.0);
  EXPECT_EQ(fixed.ComputeTurnRates().max_rate_rad_s, 0.0);
}

TEST(Caster, RoundedCornerTurnsFarSlowerThanTheHeading) {
  const double r = 0.5, v = 0.02, w = 0.01;
  auto path = Path(RoundedSquare(r));
  TurnRates heading = Orientation(path, OrientationMode::kHeading).ComputeTurnRates();
  EXPECT_NEAR(heading.max_rate_rad_s, v / (r * kMm), 1e-9 * v / (r * kMm));  // 40 rad/s on the arcs
  EXPECT_EQ(heading.jumps, 0u);  // lines meet the arcs tangentially
  TurnRates caster = Orientation(path, OrientationMode::kCaster).ComputeTurnRates();
  // Rounding only shortens the turn the window sees: at most the sharp corner's 2 v / w.
  EXPECT_LE(caster.max_rate_rad_s, 2 * v / w * (1 + 1e-9));
  EXPECT_GT(caster.max_rate_rad_s, 0.9 * 2 * v / w);
  EXPECT_LT(caster.max_rate_rad_s, heading.max_rate_rad_s / 5);
}

// The reported rates agree with finite differences of the heading over time.
TEST(Caster, TurnRateMatchesFiniteDifferences) {
  for (double r : {0.5, 3.0}) {
    auto path = Path(RoundedSquare(r));
    for (OrientationMode mode : {OrientationMode::kCaster, OrientationMode::kHeading}) {
      ToolpathOrientation o = Orientation(path, mode, 6);
      TurnRates reported = o.ComputeTurnRates();
      double max_fd = 0;
      const double dt = 1e-4;
      for (double t = 0; t + dt < path->Duration(); t += dt) {
        double d = std::remainder(o.HeadingAt(t + dt) - o.HeadingAt(t), 2 * M_PI);
        max_fd = std::max(max_fd, std::abs(d) / dt);
      }
      // Finite differences over 0.1 ms average the rate over 2 um of path: within 1 %
      // of the peak, never above it.
      EXPECT_LE(max_fd, reported.max_rate_rad_s * (1 + 1e-6)) << r;
      EXPECT_GE(max_fd, reported.max_rate_rad_s * 0.99) << r;
    }
  }
}

TEST(Caster, IsTheMeanOfUnitTangentsOverTheWindow) {
  // Lines, a full circle and a quarter arc: the caster direction against a numerical
  // mean of unit tangents (finite differences of the path) over the last w.
  auto path = Path("G1 F600 X20 Y0\nG2 X20 Y0 I0 J5\nG1 X25 Y5\nG3 X30 Y10 I5 J0\nG1 X30 Y30\n");
  const double w = 0.008;
  ToolpathOrientation o = Orientation(path, OrientationMode::kCaster, w / kMm);
  for (double t : {1.0, 2.5, 3.1, 4.0, 5.5, 6.2, 7.0, 8.0}) {
    double s = o.PathLengthAt(t);
    double from = std::max(0.0, s - w);
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    const int n = 20000;
    const double h = (s - from) / n;
    for (int k = 0; k < n; ++k) {
      Eigen::Vector2d d = o.PointAtLength(from + (k + 1) * h) - o.PointAtLength(from + k * h);
      if (d.norm() > 0) sum += d.normalized();
    }
    double expected = std::atan2(sum.y(), sum.x());
    EXPECT_NEAR(std::remainder(o.HeadingAt(t) - expected, 2 * M_PI), 0.0, 1e-4) << t;
  }
}

TEST(Caster, NoFlipAcrossTheAngleWrap) {
  // Heading west, zig-zagging between +170 and -170 degrees: the mean of the angles
  // would be about 0 (east); the mean of unit vectors stays west.
  std::ostringstream g;
  g.precision(17);
  g << "G1 F1200 X100 Y0\n";
  double x = 100, y = 0;
  const double dx = 10, dy = 10 * std::tan(10 * M_PI / 180);
  for (int k = 0; k < 20; ++k) {
    x -= dx;
    y = (k % 2 == 0) ? dy : 0;
    g << "G1 X" << x << " Y" << y << "\n";
  }
  auto path = Path(g.str());
  double t0 = path->segments[0].t_end_s;
  ToolpathOrientation caster = Orientation(path, OrientationMode::kCaster, 10);
  ToolpathOrientation heading = Orientation(path, OrientationMode::kHeading, 10);
  double min_west = 1;
  for (double t = t0 + 0.6; t < path->Duration(); t += 0.01) {
    min_west = std::min(min_west, -std::cos(caster.HeadingAt(t)));
    EXPECT_GT(std::abs(heading.HeadingAt(t)), 170 * M_PI / 180 - 1e-9) << t;
  }
  // Always within 10 degrees of west (exactly 10 while the window lies on one move).
  EXPECT_GT(min_west, std::cos(10 * M_PI / 180) - 1e-12);
  TurnRates th = heading.ComputeTurnRates();
  EXPECT_EQ(th.jumps, 20u);  // the first corner turns 170 degrees, then 20 each
  EXPECT_NEAR(th.MaxJumpDeg(), 170.0, 1e-9);
  EXPECT_EQ(th.max_jump_line, 2);
  EXPECT_NEAR(th.max_jump_time_s, t0, 1e-12);
  TurnRates tc = caster.ComputeTurnRates();
  EXPECT_TRUE(std::isfinite(tc.max_rate_rad_s));
  EXPECT_EQ(tc.jumps, 0u);
}

TEST(Caster, ExactReversalIsAJumpOf180Degrees) {
  // Straight back along a 30 mm line at 20 mm/s: the chord shrinks through zero on
  // its own line w / 2 after the turn, and the caster flips from +x to -x there.
  auto path = Path("G1 F1200 X30 Y0\nG1 X0 Y0\n");
  const double v = 0.02, w = 0.01;
  ToolpathOrientation caster = Orientation(path, OrientationMode::kCaster);
  const double t_flip = 1.5 + 0.5 * w / v;
  EXPECT_NEAR(caster.HeadingAt(t_flip - 0.01), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(caster.HeadingAt(t_flip + 0.01)), M_PI, 1e-12);
  TurnRates r = caster.ComputeTurnRates();
  EXPECT_EQ(r.jumps, 1u);
  EXPECT_NEAR(r.MaxJumpDeg(), 180.0, 1e-12);
  EXPECT_NEAR(r.max_jump_time_s, t_flip, 1e-12);
  EXPECT_EQ(r.max_jump_line, 2);
  // Back along a line offset by 0.1 mm it swings round continuously instead: a rate,
  // no jump.
  TurnRates near = Orientation(Path("G1 F1200 X30 Y0\nG1 X30 Y0.1\nG1 X0 Y0.1\n"), OrientationMode::kCaster)
                       .ComputeTurnRates();
  EXPECT_EQ(near.jumps, 0u);
  EXPECT_GT(near.max_rate_rad_s, 100 * v / w);
}

TEST(Caster, MovesWithoutPlaneMotionKeepTheHeading) {
  // A z move, a retraction and a dwell between two lines: the heading holds.
  auto path = Path("G1 F600 X10 Y0\nG1 Z1\nG1 E-1\nG4 P200\nG1 X10 Y10\n");
  ToolpathOrientation heading = Orientation(path, OrientationMode::kHeading);
  ToolpathOrientation caster = Orientation(path, OrientationMode::kCaster);
  const auto& s = path->segments;
  ASSERT_EQ(s.size(), 5u);
  for (size_t k = 1; k <= 3; ++k) {
    double t = 0.5 * (s[k].t_start_s + s[k].t_end_s);
    EXPECT_NEAR(heading.HeadingAt(t), 0.0, 1e-15);
    EXPECT_NEAR(caster.HeadingAt(t), 0.0, 1e-15);
    EXPECT_NEAR(caster.PathLengthAt(t), 0.010, 1e-15);
  }
  EXPECT_NEAR(heading.HeadingAt(s[4].t_start_s + 0.1), M_PI / 2, 1e-12);
  // At the very start (no chord yet) the caster takes the first move's direction.
  EXPECT_NEAR(caster.HeadingAt(0), 0.0, 1e-15);
  EXPECT_NEAR(Orientation(Path("G1 F600 X0 Y5\n"), OrientationMode::kCaster).HeadingAt(0), M_PI / 2, 1e-15);
  // A path without plane motion has heading 0.
  EXPECT_EQ(Orientation(Path("G1 F600 Z5\n"), OrientationMode::kCaster).HeadingAt(0.1), 0.0);
}

TEST(Caster, OptionsAreChecked) {
  OrientationOptions o;
  o.caster_window_m = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  o.caster_window_m = std::nan("");
  EXPECT_THROW(o.Check(), std::invalid_argument);
  EXPECT_EQ(ParseOrientationMode("heading"), OrientationMode::kHeading);
  EXPECT_EQ(OrientationModeName(OrientationMode::kCaster), "caster");
  EXPECT_THROW(ParseOrientationMode("spin"), std::invalid_argument);
}

}  // namespace
}  // namespace lt
