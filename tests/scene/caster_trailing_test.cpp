// The trailing-wheel orientation: its closed-form flow against a numerical
// integration of d psi / ds = -sin(psi) / w - kappa, its headings against the
// tractrix's closed form after a corner, and its turn rate bounded by v / w where the
// virtual caster swings round at once (reversals).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "orientation_test_util.h"
#include "scene/caster.h"
#include "scene/motion.h"
#include "scene/motion_gcode.h"
#include "scene/trailing_wheel.h"
#include "test_util.h"

namespace lt {
namespace {

using namespace orientation_test;

// Classical RK4 on d psi / ds = -sin(psi) / w - kappa, 2e4 steps of at most 2.5 um
// (h / w <= 2.5e-4: local error ~(h / w)^5, far below the 1e-9 asked).
double IntegrateAngle(double psi, double s, double w, double kappa) {
  const int n = 20000;
  const double h = s / n;
  auto f = [&](double p) { return -std::sin(p) / w - kappa; };
  for (int i = 0; i < n; ++i) {
    const double k1 = f(psi), k2 = f(psi + 0.5 * h * k1), k3 = f(psi + 0.5 * h * k2), k4 = f(psi + h * k3);
    psi += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return psi;
}

TEST(TrailingWheel, FlowMatchesNumericalIntegration) {
  const double w = 0.01;
  // Lines (kappa 0), gentle arcs (r > w: the wheel settles at an angle), the limit
  // r = w, and tight arcs (r < w: the wheel keeps turning relative to the path).
  for (double kappa : {0.0, 25.0, -60.0, 100.0, -100.0, 180.0, -400.0}) {
    for (double psi0 : {0.0, 0.4, -1.3, 2.9, -3.1}) {
      for (double s : {0.001, 0.013, 0.05}) {
        const double expected = IntegrateAngle(psi0, s, w, kappa);
        const double got = WheelAngle(TrailAlong(WheelHalfAngle(psi0), s, w, kappa));
        EXPECT_NEAR(std::remainder(got - expected, 2 * M_PI), 0.0, 1e-9)
            << "kappa " << kappa << " psi0 " << psi0 << " s " << s;
      }
    }
  }
}

TEST(TrailingWheel, LongMovesStayFiniteAndSettle) {
  // 10 m of line behind a 1 mm trail (s / w = 1e4: exp overflows without rescaling).
  const double psi = WheelAngle(TrailAlong(WheelHalfAngle(3.0), 10.0, 0.001, 0.0));
  EXPECT_EQ(psi, 0.0);
  // Pointing exactly backwards on a line is a balance the flow keeps (no NaN); a
  // hair off it, the wheel swings round.
  EXPECT_EQ(std::abs(WheelAngle(TrailAlong(Eigen::Vector2d(1, 0), 1.0, 0.001, 0.0))), M_PI);
  EXPECT_EQ(WheelAngle(TrailAlong(WheelHalfAngle(M_PI), 1.0, 0.001, 0.0)), 0.0);
  // On an arc of radius r > w the wheel settles where sin(psi) = -kappa w.
  const double kappa = 50.0, w = 0.01;
  EXPECT_NEAR(WheelAngle(TrailAlong(WheelHalfAngle(2.0), 1.0, w, kappa)), -std::asin(kappa * w), 1e-12);
}

TEST(TrailingOrientation, CornerFollowsTheTractrix) {
  // A 90 degree corner at (40, 0) at 20 mm/s: s past the corner, tan(psi / 2) =
  // tan(-pi / 4) exp(-s / w), so the heading is pi / 2 - 2 atan(exp(-s / w)).
  auto path = Path("G1 F1200 X40 Y0\nG1 X40 Y40\n");
  const double v = 0.02, w = 0.01;
  ToolpathOrientation o = Orientation(path, OrientationMode::kTrailing);
  EXPECT_NEAR(o.HeadingAt(1.0), 0.0, 1e-15);
  for (double s : {0.0, 0.001, 0.005, 0.01, 0.03}) {
    EXPECT_NEAR(o.HeadingAt(2.0 + s / v), M_PI / 2 - 2 * std::atan(std::exp(-s / w)), 1e-12) << s;
  }
  TurnRates r = o.ComputeTurnRates();
  EXPECT_NEAR(r.max_rate_rad_s, v / w, 1e-12);  // at the corner, 90 degrees off the path
  EXPECT_NEAR(r.max_rate_time_s, 2.0, 1e-12);
  EXPECT_EQ(r.jumps, 0u);
}

// A zig-zag of hairpins (infill turning back by 180 degrees, travel back along a
// line): the caster swings round at once; the wheel never turns faster than v / w.
TEST(TrailingOrientation, ReversalsTurnAtMostSpeedOverTrail) {
  std::ostringstream g;
  g << "G1 F1200 X30 Y0\nG1 X0 Y0\nG1 X30 Y0\n";  // straight back, and back again
  for (int k = 1; k <= 6; ++k) g << "G1 Y" << 0.4 * k << "\nG1 X" << (k % 2 ? 0 : 30) << "\n";
  auto path = Path(g.str());
  const double v = 0.02, w = 0.01;
  ToolpathOrientation trailing = Orientation(path, OrientationMode::kTrailing);
  TurnRates r = trailing.ComputeTurnRates();
  EXPECT_LE(r.max_rate_rad_s, v / w * (1 + 1e-12));
  EXPECT_GE(r.max_rate_rad_s, v / w * (1 - 1e-12));
  // Only the first reversal finds the wheel exactly in line and leaves it pointing
  // straight back: one jump of the 1 degree offset. After 30 mm (3 w) back the wheel
  // is still swinging round (not in line), and the hairpins' 0.4 mm steps turn it
  // by more than a degree before each reversal.
  EXPECT_EQ(r.jumps, 1u);
  EXPECT_NEAR(r.MaxJumpDeg(), 1.0, 1e-9);
  EXPECT_EQ(r.max_jump_line, 2);
  // Finite differences of the heading agree with the reported peak (never above it,
  // besides the one jump).
  double max_fd = 0;
  const double dt = 1e-4;
  for (double t = 0; t + dt < path->Duration(); t += dt) {
    if (std::abs(t - r.max_jump_time_s) < 2 * dt) continue;
    const double d = std::remainder(trailing.HeadingAt(t + dt) - trailing.HeadingAt(t), 2 * M_PI);
    max_fd = std::max(max_fd, std::abs(d) / dt);
  }
  EXPECT_LE(max_fd, r.max_rate_rad_s * (1 + 1e-6));
  EXPECT_GE(max_fd, r.max_rate_rad_s * 0.99);
  // The caster on the same path flips by 180 degrees at the reversal and turns 50
  // times faster at the hairpins (v over half the 0.4 mm step).
  TurnRates caster = Orientation(path, OrientationMode::kCaster).ComputeTurnRates();
  EXPECT_NEAR(caster.MaxJumpDeg(), 180.0, 1e-9);
  EXPECT_NEAR(caster.max_rate_rad_s, 50 * v / w, 1e-6 * v / w);
  // After the last hairpin the wheel swings round and trails again: the last move is
  // 30 mm, 3 w, long enough for it to come within a few degrees.
  const Eigen::Vector2d last = path->segments.back().TangentXy(1);
  const double off = std::remainder(trailing.HeadingAt(path->Duration()) - std::atan2(last.y(), last.x()), 2 * M_PI);
  EXPECT_LT(std::abs(off), 0.2);
}

TEST(TrailingOrientation, SettlesOnCirclesAndMatchesFiniteDifferences) {
  // Three full circles of radius 20 mm (r > w), counter-clockwise from (20, 0) about
  // (20, 20): the wheel settles 30 degrees inside the path (sin(psi) = -w / r) and
  // then turns with it at v / r; the path's tangent at the end is +x.
  const double v = 0.02, w = 0.01, r = 0.02;
  auto path = Path("G1 F1200 X20 Y0\nG3 X20 Y0 I0 J20\nG3 X20 Y0 I0 J20\nG3 X20 Y0 I0 J20\n");
  ToolpathOrientation o = Orientation(path, OrientationMode::kTrailing);
  const double t_end = path->Duration();
  const double heading_end = o.HeadingAt(t_end);
  EXPECT_NEAR(std::remainder(heading_end + std::asin(w / r), 2 * M_PI), 0.0, 1e-9);
  const double dt = 1e-3;
  EXPECT_NEAR(std::remainder(heading_end - o.HeadingAt(t_end - dt), 2 * M_PI) / dt, v / r, 1e-9);
  TurnRates rates = o.ComputeTurnRates();
  EXPECT_LE(rates.max_rate_rad_s, v / w * (1 + 1e-12));
  double max_fd = 0;
  for (double t = 0; t + dt < t_end; t += dt) {
    max_fd = std::max(max_fd, std::abs(std::remainder(o.HeadingAt(t + dt) - o.HeadingAt(t), 2 * M_PI)) / dt);
  }
  EXPECT_LE(max_fd, rates.max_rate_rad_s * (1 + 1e-6));
  EXPECT_GE(max_fd, rates.max_rate_rad_s * 0.99);
  EXPECT_EQ(rates.jumps, 0u);
}

TEST(TrailingOrientation, NamesAndOptions) {
  EXPECT_EQ(ParseOrientationMode("trailing"), OrientationMode::kTrailing);
  EXPECT_EQ(OrientationModeName(OrientationMode::kTrailing), "trailing");
  OrientationOptions o;
  o.trail_m = 0;
  EXPECT_THROW(o.Check(), std::invalid_argument);
  // Moves without plane motion keep the heading; a path without any has heading 0.
  auto path = Path("G1 F600 X10 Y0\nG1 Z1\nG1 X10 Y10\n");
  ToolpathOrientation t = Orientation(path, OrientationMode::kTrailing);
  EXPECT_NEAR(t.HeadingAt(0.5 * (path->segments[1].t_start_s + path->segments[1].t_end_s)), 0.0, 1e-15);
  EXPECT_EQ(Orientation(Path("G1 F600 Z5\n"), OrientationMode::kTrailing).HeadingAt(0.1), 0.0);
}

TEST(TrailingOrientation, SceneFileKeys) {
  test::TempDir dir;
  test::WriteText(dir / "square.gcode", "G1 F1200 X40 Y0\nG1 X40 Y40\n");
  auto parse = [&](const std::string& text) {
    json::Document doc = json::Document::Parse(text, "scene.json", dir.path());
    return std::get<GcodeMotion>(ParseMotion(doc.Root()));
  };
  GcodeMotion m = parse(R"({"type": "gcode", "file": "square.gcode", "orientation": "trailing", "trail_mm": 5})");
  EXPECT_EQ(m.orientation.mode, OrientationMode::kTrailing);
  EXPECT_NEAR(m.orientation.trail_m, 0.005, 1e-15);
  // 5 mm past the corner: one trail, tan(psi / 2) = -1 / e.
  EXPECT_NEAR(m.toolpath->HeadingAt(2.25), M_PI / 2 - 2 * std::atan(std::exp(-1.0)), 1e-12);
  // The resolved JSON names the rule and its trail; a trail of 0 is refused at its key.
  EXPECT_EQ(GcodeMotionToJson(m)["orientation"], "trailing");
  EXPECT_EQ(GcodeMotionToJson(m)["trail_mm"], 5.0);
  EXPECT_THAT(test::ErrorOf([&] { parse(R"({"type": "gcode", "file": "square.gcode", "trail_mm": 0})"); }),
              ::testing::HasSubstr("/trail_mm: must be > 0"));
}

}  // namespace
}  // namespace lt
