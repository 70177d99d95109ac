// LED flood light and pattern projector: power, sampling and intensity against
// closed forms, and parsing of the pattern image.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "core/image_io.h"
#include "core/random.h"
#include "sensor/led.h"
#include "sensor/pattern_projector.h"
#include "sensor/rig.h"
#include "test_util.h"

namespace lt {
namespace {

LedParams SomeLed() {
  LedParams p;
  p.width_m = 0.02;
  p.height_m = 0.01;
  p.radiance = {10.0, 20.0, 30.0};
  p.cam_from_led = Pose::Identity();
  p.cam_from_led.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();  // faces -z
  p.cam_from_led.translation() = Eigen::Vector3d(0.01, 0.02, 0.3);
  return p;
}

TEST(Led, PowerIsPiRadianceArea) {
  Led led(SomeLed());
  auto p = led.PowerW();
  EXPECT_NEAR(p[1], M_PI * 20.0 * 2e-4, 1e-15);
  EXPECT_NEAR(led.normal_in_cam().z(), -1.0, 1e-15);
  EXPECT_EQ(led.Radiance(Eigen::Vector3d(0, 0, -1))[2], 30.0);
  EXPECT_EQ(led.Radiance(Eigen::Vector3d(0, 0, 1))[2], 0.0);
}

// Irradiance at distance h on the axis of a Lambertian rectangle (parallel
// receiver) by Monte Carlo over Led::Sample against the closed form
// E = 4·(L/2)·[a/√(a²+h²)·atan(b/√(a²+h²)) + b/√(b²+h²)·atan(a/√(b²+h²))],
// a, b the half sides.
TEST(Led, SamplingIntegratesIrradianceOnAxis) {
  Led led(SomeLed());
  const double h = 0.015, a = 0.01, b = 0.005;
  Eigen::Vector3d receiver = led.center_in_cam() + h * led.normal_in_cam();
  Eigen::Vector3d receiver_normal = -led.normal_in_cam();
  Rng rng(11);
  const int n = 200000;
  double sum = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    LedSample s = led.Sample({rng.NextDouble(), rng.NextDouble()});
    mean += s.p_in_cam;
    Eigen::Vector3d d = receiver - s.p_in_cam;
    double r2 = d.squaredNorm();
    Eigen::Vector3d w = d / std::sqrt(r2);
    sum += led.Radiance(w)[0] * w.dot(s.normal_in_cam) * (-w).dot(receiver_normal) / r2 / s.pdf_area;
  }
  double L = 10.0;
  double ra = std::sqrt(a * a + h * h), rb = std::sqrt(b * b + h * h);
  double exact = 2 * L * (a / ra * std::atan(b / ra) + b / rb * std::atan(a / rb));
  // Relative standard deviation of the estimator is ~0.5 here, /sqrt(2e5) = 0.1%; allow 1%.
  EXPECT_NEAR(sum / n, exact, 0.01 * exact);
  EXPECT_LT((mean / n - led.center_in_cam()).norm(), 1e-4);
}

PatternProjectorParams SomePattern() {
  PatternProjectorParams p;
  p.pattern = Image<float>(32, 24, 1, 0.0f);
  Rng rng(5);
  for (float& v : p.pattern.pixels) v = float(rng.NextDouble() < 0.3 ? rng.NextDouble() * 255 : 0.0);
  p.horizontal_fov_rad = 50 * M_PI / 180;
  p.power_w = 3e-3;
  return p;
}

TEST(Pattern, IntensityIntegratesToPowerAndFollowsPixels) {
  PatternProjector proj(SomePattern());
  // Midpoint rule on a grid over the tangent plane (x/z, y/z) with
  // dΩ = dx dy / (1 + x² + y²)^{3/2}; the grid is not aligned with the pattern
  // pixels, so each pixel edge costs up to half a cell: ~0.3% overall.
  const double tx = std::tan(25 * M_PI / 180) * 1.05, ty = tx * 24 / 32 * 1.05;
  const int n = 1500;
  double sum = 0, dx = 2 * tx / n, dy = 2 * ty / n;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      double x = -tx + (i + 0.5) * dx, y = -ty + (j + 0.5) * dy;
      sum += proj.RadiantIntensity(Eigen::Vector3d(x, y, 1)) * dx * dy / std::pow(1 + x * x + y * y, 1.5);
    }
  }
  EXPECT_NEAR(sum, 3e-3, 0.005 * 3e-3);
  // Centre of pattern pixel (i, j): I = P·w_j/(Σw·Ω_j).
  double total = 0;
  for (float v : proj.params().pattern.pixels) total += v;
  for (auto [i, j] : {std::pair{0, 0}, std::pair{17, 9}, std::pair{31, 23}}) {
    Eigen::Vector3d d((i - 15.5) / proj.fx(), (j - 11.5) / proj.fy(), 1.0);
    double w = proj.params().pattern.At(i, j);
    EXPECT_NEAR(proj.RadiantIntensity(d), 3e-3 * w / (total * proj.PixelSolidAngle(i, j)), 1e-6 * proj.RadiantIntensity(d) + 1e-12);
  }
  EXPECT_EQ(proj.RadiantIntensity(Eigen::Vector3d(0, 0, -1)), 0.0);
  EXPECT_EQ(proj.RadiantIntensity(Eigen::Vector3d(1, 0, 1)), 0.0);  // 45° is outside the 25° half field
}

TEST(Pattern, ParsedFromImageFile) {
  auto dir = std::filesystem::path(LT_BINARY_DIR) / "sensor_test_pattern";
  std::filesystem::create_directories(dir);
  Image<uint8_t> img(8, 4, 1, 0);
  img.At(2, 1) = 200;
  img.At(5, 3) = 100;
  WriteImage(dir / "dots.png", img);
  auto doc = json::Document::Parse(
      R"({"image": "dots.png", "fov_deg": [40, 20], "power_mw": 2, "wavelength_nm": 830,
          "cam_from_projector": {"translation_m": [0.05, 0, 0]}})",
      "scene.json", dir);
  PatternProjector proj = ParsePatternProjector(doc.Root().AsObject());
  EXPECT_EQ(proj.width(), 8);
  EXPECT_EQ(proj.height(), 4);
  EXPECT_NEAR(proj.wavelength_m(), 830e-9, 1e-18);
  EXPECT_NEAR(proj.fx(), 8 / (2 * std::tan(20 * M_PI / 180)), 1e-12);
  EXPECT_NEAR(proj.fy(), 4 / (2 * std::tan(10 * M_PI / 180)), 1e-12);
  // Power splits 2:1 between the two lit pixels.
  double i1 = proj.RadiantIntensity(Eigen::Vector3d((2 - 3.5) / proj.fx(), (1 - 1.5) / proj.fy(), 1));
  double i2 = proj.RadiantIntensity(Eigen::Vector3d((5 - 3.5) / proj.fx(), (3 - 1.5) / proj.fy(), 1));
  EXPECT_NEAR(i1 * proj.PixelSolidAngle(2, 1) + i2 * proj.PixelSolidAngle(5, 3), 2e-3, 1e-9);
  EXPECT_NEAR(i1 * proj.PixelSolidAngle(2, 1) / (i2 * proj.PixelSolidAngle(5, 3)), 2.0, 1e-6);

  auto missing = json::Document::Parse(
      R"({"image": "nope.png", "fov_deg": 40, "power_mw": 2, "wavelength_nm": 830, "cam_from_projector": {}})",
      "scene.json", dir);
  std::string msg = test::ErrorOf([&] { ParsePatternProjector(missing.Root().AsObject()); });
  EXPECT_NE(msg.find("nope.png"), std::string::npos) << msg;
}

}  // namespace
}  // namespace lt
