// Thin lens and radiometry of the camera against closed forms.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "sensor/camera.h"

namespace lt {
namespace {

CameraParams Lens(std::optional<double> focus_m) {
  CameraParams p;
  p.width = 640;
  p.height = 480;
  p.fx = p.fy = 1700;  // v = 8.5 mm with 5 um pixels
  p.cx = 319.5;
  p.cy = 239.5;
  p.pixel_pitch_m = 5e-6;
  p.f_number = 2.8;
  p.focus_distance_m = focus_m;
  return p;
}

TEST(Lens, PinholeIgnoresLensSample) {
  Camera cam(Lens(std::nullopt));
  EXPECT_TRUE(cam.is_pinhole());
  EXPECT_DOUBLE_EQ(cam.focal_length_m(), 8.5e-3);
  auto a = cam.GenerateRay({100.25, 50.5}, {0.1, 0.9});
  auto b = cam.GenerateRay({100.25, 50.5}, {0.7, 0.3});
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->origin, Eigen::Vector3d::Zero());
  EXPECT_EQ(a->direction, b->direction);
  EXPECT_EQ(a->direction, *cam.Unproject({100.25, 50.5}));
  EXPECT_EQ(cam.CircleOfConfusionM(0.3), 0.0);
}

TEST(Lens, FocalLengthFollowsTheLensEquation) {
  Camera cam(Lens(0.1));
  double v = 8.5e-3, s = 0.1;
  EXPECT_NEAR(1.0 / cam.focal_length_m(), 1.0 / v + 1.0 / s, 1e-9);
  EXPECT_NEAR(cam.aperture_diameter_m(), cam.focal_length_m() / 2.8, 1e-15);
  EXPECT_NEAR(cam.working_f_number(), 2.8 * (1 + v / s), 1e-12);  // N (1 + m)
}

TEST(Lens, RaysConvergeOnTheFocusPlaneInsideTheAperture) {
  CameraParams p = Lens(0.12);
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.1, 0.02, 0.001, 0.0005, 0.0};
  Camera cam(p);
  Rng rng(7);
  for (Eigen::Vector2d px : {Eigen::Vector2d(319.5, 239.5), Eigen::Vector2d(3.2, 470.7), Eigen::Vector2d(600, 10)}) {
    Eigen::Vector3d chief = *cam.Unproject(px);
    Eigen::Vector3d focus = chief * (0.12 / chief.z());
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    double mean_r2 = 0;
    const int n = 4000;
    for (int i = 0; i < n; ++i) {
      auto ray = cam.GenerateRay(px, {rng.NextDouble(), rng.NextDouble()});
      ASSERT_TRUE(ray);
      EXPECT_NEAR(ray->direction.norm(), 1.0, 1e-12);
      EXPECT_EQ(ray->origin.z(), 0.0);
      double r = ray->origin.head<2>().norm();
      EXPECT_LE(r, 0.5 * cam.aperture_diameter_m() * (1 + 1e-12));
      mean += ray->origin.head<2>();
      mean_r2 += r * r;
      double t = (0.12 - ray->origin.z()) / ray->direction.z();
      EXPECT_LT((ray->origin + t * ray->direction - focus).norm(), 1e-13);
    }
    // Uniform on the disc of radius R: mean 0, E[r²] = R²/2. 4000 samples: the
    // standard error of E[r²] is R²/sqrt(12·4000) = 0.5% of R²; allow 2%.
    double R = 0.5 * cam.aperture_diameter_m();
    EXPECT_LT(mean.norm() / n, 0.03 * R);
    EXPECT_NEAR(mean_r2 / n, 0.5 * R * R, 0.02 * R * R);
  }
}

TEST(Lens, FisheyeThinLensFocusesOnASphereBeyondNinetyDegrees) {
  CameraParams p = Lens(0.2);
  p.width = p.height = 1000;
  p.fx = p.fy = 200;
  p.cx = p.cy = 499.5;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {-0.02, 0.001, 0.0, 0.0};
  Camera cam(p);
  Eigen::Vector2d px(499.5 + 200 * 2.0, 499.5);  // θ_d = 2.0 rad: θ > 90°
  Eigen::Vector3d chief = *cam.Unproject(px);
  ASSERT_LT(chief.z(), 0.0);
  Rng rng(9);
  for (int i = 0; i < 200; ++i) {
    auto ray = cam.GenerateRay(px, {rng.NextDouble(), rng.NextDouble()});
    ASSERT_TRUE(ray);
    EXPECT_NEAR(ray->origin.dot(chief), 0.0, 1e-15);  // aperture disc faces the chief ray
    EXPECT_LE(ray->origin.norm(), 0.5 * cam.aperture_diameter_m() * (1 + 1e-12));
    // The ray passes through the focus point S·chief.
    Eigen::Vector3d to_focus = 0.2 * chief - ray->origin;
    EXPECT_LT((to_focus.normalized() - ray->direction).norm(), 1e-12);
  }
}

TEST(Lens, CircleOfConfusionMatchesClosedForm) {
  Camera cam(Lens(0.1));
  const double v = 8.5e-3, s = 0.1, n = 2.8;
  const double f = 1.0 / (1.0 / v + 1.0 / s);
  const double a = f / n;
  for (double d : {0.05, 0.08, 0.1, 0.15, 0.5, 3.0}) {
    double textbook = a * f * std::abs(d - s) / (d * (s - f));
    EXPECT_NEAR(cam.CircleOfConfusionM(d), textbook, 1e-15) << d;
    // Geometry of the generated rays: for one pixel they cover, at depth d, a disc
    // of diameter a·|d − s|/s; seen from the sensor (scale v/d) that is the blur circle.
    Eigen::Vector2d px(400.3, 100.8);
    double lo = 1e9, hi = -1e9;
    for (Eigen::Vector2d u : {Eigen::Vector2d(1.0 - 1e-16, 0.5), Eigen::Vector2d(0.0, 0.5)}) {  // x = ±R
      auto ray = cam.GenerateRay(px, u);
      double t = d / ray->direction.z();
      double x = (ray->origin + t * ray->direction).x();
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
    EXPECT_NEAR((hi - lo) * v / d, textbook, 1e-12 + 1e-9 * textbook) << d;
    EXPECT_NEAR(cam.CircleOfConfusionPx(d), textbook / 5e-6, 1e-9);
  }
}

TEST(Radiometry, PinholeIrradianceIsCosFourthLaw) {
  Camera cam(Lens(std::nullopt));
  for (Eigen::Vector2d px : {Eigen::Vector2d(319.5, 239.5), Eigen::Vector2d(0, 0), Eigen::Vector2d(639, 479),
                             Eigen::Vector2d(100.5, 400.25)}) {
    Eigen::Vector3d ray = *cam.Unproject(px);
    double cos_theta = ray.z();
    double expected = M_PI / (4 * 2.8 * 2.8) * std::pow(cos_theta, 4);
    EXPECT_NEAR(cam.RadianceToIrradiance(px), expected, 1e-12 * expected) << px.transpose();
  }
}

TEST(Radiometry, ThinLensUsesWorkingFNumber) {
  Camera cam(Lens(0.1));
  double nw = 2.8 * (1 + 8.5e-3 / 0.1);
  Eigen::Vector2d px(50, 60);
  double c = cam.Unproject(px)->z();
  double expected = M_PI / (4 * nw * nw) * std::pow(c, 4);
  EXPECT_NEAR(cam.RadianceToIrradiance(px), expected, 1e-12 * expected);
}

// Solid angle of the rectangle [x1, x2] x [y1, y2] on the plane z = 1.
double RectSolidAngle(double x1, double x2, double y1, double y2) {
  auto F = [](double x, double y) { return std::atan(x * y / std::sqrt(1 + x * x + y * y)); };
  return F(x2, y2) - F(x1, y2) - F(x2, y1) + F(x1, y1);
}

TEST(Radiometry, PixelSolidAnglesAddUpToTheFieldOfView) {
  Camera cam(Lens(std::nullopt));
  double sum = 0;
  for (int y = 0; y < cam.height(); ++y) {
    for (int x = 0; x < cam.width(); ++x) sum += cam.PixelSolidAngle(Eigen::Vector2d(x, y));
  }
  double exact = RectSolidAngle(-320 / 1700.0, 320 / 1700.0, -240 / 1700.0, 240 / 1700.0);
  // Midpoint rule over 1-pixel cells of a smooth density: relative error ~1e-8.
  EXPECT_NEAR(sum, exact, 1e-7 * exact);
  // Single pixel at the corner against its exact rectangle.
  EXPECT_NEAR(cam.PixelSolidAngle({0, 0}),
              RectSolidAngle(-320 / 1700.0, -319 / 1700.0, -240 / 1700.0, -239 / 1700.0), 1e-6 * cam.PixelSolidAngle({0, 0}));
}

TEST(Radiometry, DistortedPixelSolidAngleMatchesRayDifferences) {
  CameraParams p = Lens(std::nullopt);
  p.fx = p.fy = 500;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.25, 0.08, 0.002, -0.001, -0.01};
  Camera cam(p);
  for (Eigen::Vector2d px : {Eigen::Vector2d(319.5, 239.5), Eigen::Vector2d(2, 3), Eigen::Vector2d(630, 470)}) {
    const double h = 1e-3;
    Eigen::Vector3d du = (*cam.Unproject(px + Eigen::Vector2d(h, 0)) - *cam.Unproject(px - Eigen::Vector2d(h, 0))) / (2 * h);
    Eigen::Vector3d dv = (*cam.Unproject(px + Eigen::Vector2d(0, h)) - *cam.Unproject(px - Eigen::Vector2d(0, h))) / (2 * h);
    double numeric = std::abs(cam.Unproject(px)->dot(du.cross(dv)));
    EXPECT_NEAR(cam.PixelSolidAngle(px), numeric, 1e-6 * numeric) << px.transpose();
  }
}

TEST(Radiometry, FullSphereFisheyeSeesFourPi) {
  CameraParams p = Lens(std::nullopt);
  p.width = p.height = 1000;
  p.fx = p.fy = 150;
  p.cx = p.cy = 499.5;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {-0.02, 0.001, 0.0, 0.0};  // image circle radius 150·0.90π = 424 px
  Camera cam(p);
  double sum = 0;
  for (int y = 0; y < cam.height(); ++y) {
    for (int x = 0; x < cam.width(); ++x) sum += cam.PixelSolidAngle(Eigen::Vector2d(x, y));
  }
  // The density falls to 0 at θ = π, so the circle's edge costs little: 1e-4.
  EXPECT_NEAR(sum, 4 * M_PI, 1e-4 * 4 * M_PI);
}

TEST(Lens, ConcentricDiskIsUniform) {
  Rng rng(3);
  double mean_r2 = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector2d d = ConcentricDisk({rng.NextDouble(), rng.NextDouble()});
    EXPECT_LE(d.norm(), 1.0 + 1e-12);
    mean_r2 += d.squaredNorm();
  }
  // E[r²] = 1/2 for the uniform disc; standard error 1/sqrt(12 n) = 0.002.
  EXPECT_NEAR(mean_r2 / n, 0.5, 0.01);
}

}  // namespace
}  // namespace lt
