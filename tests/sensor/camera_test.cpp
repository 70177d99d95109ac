// Camera geometry: projection, iterative inverse, fold detection, thin lens and
// radiometry, against closed forms.
#include "sensor/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "sensor/param_error.h"

namespace lt {
namespace {

CameraParams Base(int w = 640, int h = 480, double f = 500) {
  CameraParams p;
  p.width = w;
  p.height = h;
  p.fx = f;
  p.fy = f * 1.01;
  p.cx = 0.5 * (w - 1) + 3.25;
  p.cy = 0.5 * (h - 1) - 2.5;
  p.pixel_pitch_m = 5e-6;
  p.f_number = 2.8;
  return p;
}

// Unproject then Project over a dense grid covering the image edges and corners;
// returns the worst round-trip error in pixels (fails when a pixel has no ray).
double WorstRoundTrip(const Camera& cam, int step, bool require_all = true, int* missing = nullptr) {
  double worst = 0;
  int none = 0;
  for (double v = -0.5; v <= cam.height() - 0.5; v += step) {
    for (double u = -0.5; u <= cam.width() - 0.5; u += step) {
      for (Eigen::Vector2d px : {Eigen::Vector2d(u, v), Eigen::Vector2d(cam.width() - 0.5, v),
                                 Eigen::Vector2d(u, cam.height() - 0.5)}) {
        auto ray = cam.Unproject(px);
        if (!ray) {
          ++none;
          EXPECT_FALSE(require_all) << "no ray at " << px.transpose();
          continue;
        }
        EXPECT_NEAR(ray->norm(), 1.0, 1e-12);
        auto back = cam.Project(*ray * 3.7);
        if (!back) {
          ADD_FAILURE() << "ray of pixel " << px.transpose() << " does not project back";
          continue;
        }
        worst = std::max(worst, (*back - px).norm());
      }
    }
  }
  if (missing) *missing = none;
  return worst;
}

TEST(Camera, PinholeProjectsWithCameraMatrix) {
  Camera cam(Base());
  Eigen::Vector3d p(0.1, -0.2, 2.0);
  auto px = cam.Project(p);
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), cam.fx() * 0.05 + cam.cx(), 1e-12);
  EXPECT_NEAR(px->y(), cam.fy() * -0.1 + cam.cy(), 1e-12);
  EXPECT_FALSE(cam.Project(Eigen::Vector3d(0.1, 0.1, -1.0)));
  EXPECT_FALSE(cam.Project(Eigen::Vector3d(0.1, 0.1, 0.0)));
  EXPECT_LT(WorstRoundTrip(cam, 16), 1e-9);
}

TEST(Camera, BrownConradyRoundTripModerate) {
  CameraParams p = Base();
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.28, 0.09, 0.0012, -0.0009, -0.01};
  Camera cam(p);
  EXPECT_LT(WorstRoundTrip(cam, 4), 1e-9);
}

TEST(Camera, BrownConradyForwardMatchesOpenCvFormula) {
  CameraParams p = Base();
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.2, 0.05, 0.001, 0.002, 0.01};
  Camera cam(p);
  // OpenCV's projectPoints written out for one point.
  double x = 0.3, y = -0.2, r2 = x * x + y * y;
  double radial = 1 - 0.2 * r2 + 0.05 * r2 * r2 + 0.01 * r2 * r2 * r2;
  double xd = x * radial + 2 * 0.001 * x * y + 0.002 * (r2 + 2 * x * x);
  double yd = y * radial + 0.001 * (r2 + 2 * y * y) + 2 * 0.002 * x * y;
  auto px = cam.Project(Eigen::Vector3d(x, y, 1) * 2.5);
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), p.fx * xd + p.cx, 1e-10);
  EXPECT_NEAR(px->y(), p.fy * yd + p.cy, 1e-10);
}

// Extreme but valid sets: strong barrel whose fold lies just outside the image
// corners, strong pincushion, strong tangential, and higher-order terms fighting.
TEST(Camera, BrownConradyRoundTripExtremeCoefficients) {
  const BrownConradyCoeffs sets[] = {
      {-0.22, 0.0, 0.0, 0.0, 0.0},       // fold maps to radius 0.821, the farthest corner is at 0.805
      {0.9, 0.6, 0.0, 0.0, 0.4},         // strong pincushion
      {-0.3, 0.1, 0.02, -0.025, -0.01},  // strong tangential
      {-0.6, 0.45, 0.0, 0.0, -0.12},     // fisheye-like barrel with higher orders
  };
  for (const auto& c : sets) {
    CameraParams p = Base();
    p.distortion = DistortionModel::kBrownConrady;
    p.brown_conrady = c;
    Camera cam(p);
    double worst = WorstRoundTrip(cam, 6);
    EXPECT_LT(worst, 1e-9) << "k1 " << c.k1 << " k2 " << c.k2 << " p1 " << c.p1;
    std::printf("brown_conrady k1=%g k2=%g p1=%g p2=%g k3=%g: worst round trip %.3g px\n", c.k1, c.k2, c.p1, c.p2,
                c.k3, worst);
  }
}

TEST(Camera, DistortionThatFoldsInsideTheImageIsRejected) {
  CameraParams p = Base();
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.8, 0.0, 0.0, 0.0, 0.0};  // fold at r = 0.645 -> distorted 0.43 < corner radius 0.80
  try {
    Camera cam(p);
    FAIL() << "folding distortion accepted";
  } catch (const ParamError& e) {
    EXPECT_EQ(e.key(), "distortion");
    EXPECT_NE(std::string(e.what()).find("folds inside the image"), std::string::npos) << e.what();
  }
}

TEST(Camera, ProjectRejectsPointsBeyondTheFold) {
  CameraParams p = Base(200, 150, 500);  // narrow image: the fold of k1 = -0.5 is outside it
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.5, 0.0, 0.0, 0.0, 0.0};
  Camera cam(p);
  double r_fold = 1.0 / std::sqrt(1.5);  // d/dr [r(1 - 0.5 r²)] = 0
  EXPECT_TRUE(cam.Project(Eigen::Vector3d(0.98 * r_fold, 0, 1)));
  EXPECT_FALSE(cam.Project(Eigen::Vector3d(1.02 * r_fold, 0, 1)));
  // Beyond the fold the forward model comes back toward the centre; Unproject
  // must not return such a ray for a pixel near the centre.
  auto ray = cam.Unproject(Eigen::Vector2d(cam.cx() + 60, cam.cy()));
  ASSERT_TRUE(ray);
  EXPECT_LT(ray->x() / ray->z(), r_fold);
}

TEST(Camera, UnprojectReportsPixelsWithoutRay) {
  CameraParams p = Base(200, 150, 500);
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.5, 0.0, 0.0, 0.0, 0.0};
  Camera cam(p);
  // The largest distorted radius is r(1 - 0.5 r²) at the fold = 0.544; beyond it no ray exists.
  EXPECT_FALSE(cam.Unproject(Eigen::Vector2d(cam.cx() + 0.6 * cam.fx(), cam.cy())));
  EXPECT_FALSE(cam.Unproject(Eigen::Vector2d(NAN, 3)));
}

TEST(Camera, FisheyeForwardMatchesOpenCvForZPositive) {
  CameraParams p = Base(800, 800, 250);
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {0.05, -0.01, 0.002, -0.0003};
  Camera cam(p);
  Eigen::Vector3d X(0.4, -0.3, 0.8);
  double a = X.x() / X.z(), b = X.y() / X.z(), r = std::hypot(a, b), th = std::atan(r);
  double th2 = th * th;
  double thd = th * (1 + 0.05 * th2 - 0.01 * th2 * th2 + 0.002 * std::pow(th2, 3) - 0.0003 * std::pow(th2, 4));
  auto px = cam.Project(X);
  ASSERT_TRUE(px);
  EXPECT_NEAR(px->x(), p.fx * thd / r * a + p.cx, 1e-10);
  EXPECT_NEAR(px->y(), p.fy * thd / r * b + p.cy, 1e-10);
}

TEST(Camera, FisheyeBeyondNinetyDegrees) {
  // Full-sphere lens: θ_d(180°) = 0.90π, i.e. an image circle of 566 px radius,
  // so the corners (707 px from the centre) see nothing.
  CameraParams p = Base(1000, 1000, 200);
  p.fy = p.fx;
  p.cx = 499.5;
  p.cy = 499.5;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {-0.02, 0.001, 0.0, 0.0};
  Camera cam(p);
  for (double deg : {95.0, 100.0, 120.0, 150.0}) {
    double th = deg * M_PI / 180;
    Eigen::Vector3d ray(std::sin(th) * std::cos(0.7), std::sin(th) * std::sin(0.7), std::cos(th));
    auto px = cam.Project(ray);
    ASSERT_TRUE(px) << deg;
    auto back = cam.Unproject(*px);
    ASSERT_TRUE(back) << deg;
    EXPECT_LT(back->z(), 0.0) << deg;
    EXPECT_LT((*back - ray).norm(), 1e-12) << deg;
  }
  int missing = 0;
  EXPECT_LT(WorstRoundTrip(cam, 7, false, &missing), 1e-9);
  EXPECT_GT(missing, 0);  // the corners lie outside the image circle (θ_d(π) reached)
}

TEST(Camera, FisheyeRoundTripStrongCoefficients) {
  const KannalaBrandtCoeffs sets[] = {{0.3, -0.1, 0.02, -0.001}, {-0.1, 0.02, -0.002, 0.0001}, {0.0, 0.0, 0.0, 0.0}};
  for (const auto& c : sets) {
    CameraParams p = Base(640, 480, 200);
    p.distortion = DistortionModel::kFisheye;
    p.fisheye = c;
    Camera cam(p);
    int missing = 0;
    double worst = WorstRoundTrip(cam, 5, false, &missing);
    EXPECT_LT(worst, 1e-9) << c.k1;
    std::printf("fisheye k1=%g k2=%g k3=%g k4=%g: worst round trip %.3g px\n", c.k1, c.k2, c.k3, c.k4, worst);
  }
}

TEST(Camera, FisheyeFoldInsideImageIsRejected) {
  CameraParams p = Base(640, 480, 200);
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {-0.6, 0.0, 0.0, 0.0};  // dθ_d/dθ = 1 - 1.8 θ² = 0 at θ = 0.745, θ_d = 0.497 < corner 2.0
  EXPECT_THROW(Camera cam(p), ParamError);
}

TEST(Camera, ParamsCheckNamesKeys) {
  auto key_of = [](CameraParams p) {
    try {
      p.Check();
    } catch (const ParamError& e) {
      return e.key();
    }
    return std::string();
  };
  CameraParams p = Base();
  p.f_number = 0;
  EXPECT_EQ(key_of(p), "f_number");
  p = Base();
  p.pixel_pitch_m = -1;
  EXPECT_EQ(key_of(p), "pixel_pitch_um");
  p = Base();
  p.width = 0;
  EXPECT_EQ(key_of(p), "resolution");
  p = Base();
  p.focus_distance_m = 0.0;
  EXPECT_EQ(key_of(p), "focus_distance_m");
}

}  // namespace
}  // namespace lt
