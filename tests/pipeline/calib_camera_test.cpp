// Camera calibration (Zhang + LM) on synthetic corner observations of a known
// camera (src/sensor Camera, the same model the renderer uses).
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "pipeline/calib_camera.h"
#include "pipeline/calib_lm.h"
#include "sensor/param_error.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The default rig's camera (1280x1024, 4.8 um pixels, 8.889 mm lens) with a
// mild barrel distortion.
CameraParams TrueCamera() {
  CameraParams p;
  p.width = 1280;
  p.height = 1024;
  p.fx = 1851.9;
  p.fy = 1853.2;
  p.cx = 642.3;
  p.cy = 508.1;
  p.pixel_pitch_m = 4.8e-6;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.12, 0.08, 3e-4, -2e-4, -0.02};
  return p;
}

// 7 x 10 inner corners, 3 mm squares (27 x 18 mm).
std::vector<Eigen::Vector3d> TargetPoints(int rows = 7, int cols = 10, double s = 3e-3) {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) pts.emplace_back(j * s, i * s, 0.0);
  return pts;
}

// cam_from_target: the target's centre at (ox, oy, z) in the camera frame,
// tilted by `tilt` about an axis in the image plane at angle `axis`, turned by
// `spin` about the optical axis.
Pose ViewPose(double ox, double oy, double z, double tilt, double axis, double spin) {
  const Eigen::Vector3d centre(4.5 * 3e-3, 3 * 3e-3, 0);
  Eigen::Matrix3d r = (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)) *
                       Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                          .toRotationMatrix();
  Pose p = Pose::Identity();
  p.linear() = r;
  p.translation() = Eigen::Vector3d(ox, oy, z) - r * centre;
  return p;
}

std::vector<Pose> StandardPoses() {
  return {ViewPose(0.000, 0.000, 0.080, 25 * kDeg, 0 * kDeg, 0),
          ViewPose(0.004, -0.003, 0.075, 30 * kDeg, 90 * kDeg, 10 * kDeg),
          ViewPose(-0.005, 0.004, 0.085, 28 * kDeg, 45 * kDeg, -15 * kDeg),
          ViewPose(0.005, 0.003, 0.072, 20 * kDeg, 135 * kDeg, 30 * kDeg),
          ViewPose(-0.006, -0.005, 0.090, 35 * kDeg, 200 * kDeg, -5 * kDeg),
          ViewPose(0.008, 0.000, 0.080, 15 * kDeg, 270 * kDeg, 90 * kDeg),
          ViewPose(-0.008, 0.002, 0.078, 32 * kDeg, 315 * kDeg, 180 * kDeg),
          ViewPose(0.000, 0.004, 0.082, 22 * kDeg, 160 * kDeg, -60 * kDeg),
          ViewPose(0.002, -0.003, 0.074, 10 * kDeg, 20 * kDeg, 45 * kDeg),
          ViewPose(0.000, 0.000, 0.060, 5 * kDeg, 60 * kDeg, 0)};
}

std::vector<CalibrationView> Observe(const Camera& cam, const std::vector<Pose>& poses, double noise_px,
                                     uint64_t seed = 7) {
  std::vector<CalibrationView> views;
  const auto pts = TargetPoints();
  for (size_t v = 0; v < poses.size(); ++v) {
    CalibrationView view;
    for (size_t k = 0; k < pts.size(); ++k) {
      auto px = cam.Project(poses[v] * pts[k]);
      if (!px || !cam.InImage(*px)) continue;  // the fisheye views leave some corners out
      Rng rng = Rng::For(seed, v, k, 0, 1);
      view.target_points.push_back(pts[k]);
      view.pixels.push_back(*px + noise_px * Eigen::Vector2d(rng.NextGaussian(), rng.NextGaussian()));
    }
    views.push_back(view);
  }
  return views;
}

TEST(CalibCamera, NoiseFreeRecoversTheCameraExactly) {
  const Camera cam(TrueCamera());
  const auto poses = StandardPoses();
  const auto views = Observe(cam, poses, 0.0);
  for (const auto& v : views) ASSERT_EQ(v.pixels.size(), 70u);  // every corner in the image
  const auto res = CalibrateCamera(views, 1280, 1024);
  ASSERT_TRUE(res.ok) << res.reason;
  const CameraParams& t = cam.params();
  EXPECT_NEAR(res.camera.fx, t.fx, 1e-6 * t.fx);
  EXPECT_NEAR(res.camera.fy, t.fy, 1e-6 * t.fy);
  EXPECT_NEAR(res.camera.cx, t.cx, 1e-6 * t.cx);
  EXPECT_NEAR(res.camera.cy, t.cy, 1e-6 * t.cy);
  EXPECT_NEAR(res.camera.brown_conrady.k1, t.brown_conrady.k1, 1e-6 * std::abs(t.brown_conrady.k1));
  EXPECT_NEAR(res.camera.brown_conrady.k2, t.brown_conrady.k2, 1e-5 * std::abs(t.brown_conrady.k2));
  EXPECT_NEAR(res.camera.brown_conrady.p1, t.brown_conrady.p1, 1e-8);
  EXPECT_NEAR(res.camera.brown_conrady.p2, t.brown_conrady.p2, 1e-8);
  EXPECT_LT(res.rms_px, 1e-7);
  for (size_t v = 0; v < poses.size(); ++v) {
    const PoseError e = ComparePoses(res.cam_from_target[v], poses[v]);
    EXPECT_LT(e.rotation_rad, 1e-8);
    EXPECT_LT(e.translation_m, 1e-9);
  }
  // The closed form (no distortion model) is already close.
  EXPECT_NEAR(res.closed_form_fx, t.fx, 0.05 * t.fx);
}

TEST(CalibCamera, NoisyCornersWithinToleranceAndHonestUncertainty) {
  const Camera cam(TrueCamera());
  const double noise = 0.1;
  const auto res = CalibrateCamera(Observe(cam, StandardPoses(), noise), 1280, 1024);
  ASSERT_TRUE(res.ok) << res.reason;
  const CameraParams& t = cam.params();
  EXPECT_NEAR(res.camera.fx, t.fx, 0.005 * t.fx);
  EXPECT_NEAR(res.camera.fy, t.fy, 0.005 * t.fy);
  EXPECT_NEAR(res.camera.cx, t.cx, 2.0);
  EXPECT_NEAR(res.camera.cy, t.cy, 2.0);
  EXPECT_NEAR(res.camera.brown_conrady.k1, t.brown_conrady.k1, 0.01);
  // The a-posteriori σ estimates the corner noise: 1400 residuals, 69
  // parameters, so its relative standard error is about 1/sqrt(2·1330) ≈ 2%.
  EXPECT_NEAR(res.sigma_px, noise, 0.1 * noise);
  // Errors stay inside 4 of the reported standard deviations.
  const double truth[] = {t.fx, t.fy, t.cx, t.cy, t.brown_conrady.k1, t.brown_conrady.k2,
                          t.brown_conrady.p1, t.brown_conrady.p2, t.brown_conrady.k3};
  ASSERT_EQ(res.params.size(), 9);
  for (int i = 0; i < 9; ++i) {
    EXPECT_GT(res.param_std[i], 0) << res.param_names[size_t(i)];
    EXPECT_LT(std::abs(res.params[i] - truth[i]), 4 * res.param_std[i]) << res.param_names[size_t(i)];
  }
  EXPECT_LT(res.param_std[0], 0.002 * t.fx);
}

// Over independent noise draws the reported standard deviation of fx matches
// the observed scatter of fx (within the sampling error of 24 draws: the
// sample standard deviation of 24 normal values is within ±35% of the truth
// with probability above 99%).
TEST(CalibCamera, ReportedStdMatchesScatter) {
  const Camera cam(TrueCamera());
  std::vector<double> fx, std_fx, cx, std_cx;
  auto poses = StandardPoses();
  poses.resize(6);  // six views keep the 24 calibrations quick
  for (uint64_t seed = 1; seed <= 24; ++seed) {
    const auto res = CalibrateCamera(Observe(cam, poses, 0.2, seed), 1280, 1024);
    ASSERT_TRUE(res.ok) << res.reason;
    fx.push_back(res.camera.fx);
    std_fx.push_back(res.param_std[0]);
    cx.push_back(res.camera.cx);
    std_cx.push_back(res.param_std[2]);
  }
  auto scatter = [](const std::vector<double>& v, double truth) {
    double s = 0;
    for (double x : v) s += (x - truth) * (x - truth);
    return std::sqrt(s / double(v.size()));
  };
  auto mean = [](const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / double(v.size());
  };
  EXPECT_NEAR(scatter(fx, cam.fx()) / mean(std_fx), 1.0, 0.35);
  EXPECT_NEAR(scatter(cx, cam.cx()) / mean(std_cx), 1.0, 0.35);
}

// Over 120 noise draws (iid 0.2 px, eight views) the intrinsics are unbiased
// and their reported σ is honest: per parameter, the errors normalised by
// the reported σ, z = (estimate − truth) / σ, have mean within ±0.35 and RMS
// within [0.75, 1.25]. For normal z the mean of 120 has a standard error of
// 0.09 and the RMS of about 0.065, so both bounds are about 4 standard
// errors. The draws are fixed, so the test is deterministic: they give
// |mean z| <= 0.05 and RMS z 0.98-1.13 (1000 draws: 0.96-1.00). One
// calibration with its principal point 2σ off (docs/calibration.md, "Is the
// principal point biased?") is chance, not bias.
TEST(CalibCamera, IntrinsicsUnbiasedWithHonestStd) {
  const Camera cam(TrueCamera());
  const CameraParams& t = cam.params();
  const double truth[] = {t.fx, t.fy, t.cx, t.cy, t.brown_conrady.k1};
  auto poses = StandardPoses();
  poses.resize(8);
  constexpr int kDraws = 120;
  double z_sum[5] = {}, z2_sum[5] = {};
  for (int d = 0; d < kDraws; ++d) {
    const auto res = CalibrateCamera(Observe(cam, poses, 0.2, 1000 + uint64_t(d)), 1280, 1024);
    ASSERT_TRUE(res.ok) << res.reason;
    for (int i = 0; i < 5; ++i) {
      const double z = (res.params[i] - truth[i]) / res.param_std[i];
      z_sum[i] += z;
      z2_sum[i] += z * z;
    }
  }
  const char* names[] = {"fx", "fy", "cx", "cy", "k1"};
  for (int i = 0; i < 5; ++i) {
    const double mean = z_sum[i] / kDraws, rms = std::sqrt(z2_sum[i] / kDraws);
    EXPECT_NEAR(mean, 0.0, 0.35) << names[i];
    EXPECT_NEAR(rms, 1.0, 0.25) << names[i];
  }
}

TEST(CalibCamera, ModelsWithoutDistortionAndFixedCoefficients) {
  CameraParams p = TrueCamera();
  p.distortion = DistortionModel::kNone;
  const Camera pinhole(p);
  CameraCalibrationOptions o;
  o.model = DistortionModel::kNone;
  auto res = CalibrateCamera(Observe(pinhole, StandardPoses(), 0.0), 1280, 1024, o);
  ASSERT_TRUE(res.ok) << res.reason;
  EXPECT_NEAR(res.camera.fx, p.fx, 1e-6 * p.fx);
  EXPECT_EQ(res.params.size(), 4);

  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.1, 0.05, 0, 0, 0};
  o = {};
  o.fix_k3 = true;
  o.fix_tangential = true;
  res = CalibrateCamera(Observe(Camera(p), StandardPoses(), 0.05), 1280, 1024, o);
  ASSERT_TRUE(res.ok) << res.reason;
  EXPECT_EQ(res.camera.brown_conrady.p1, 0.0);
  EXPECT_EQ(res.camera.brown_conrady.p2, 0.0);
  EXPECT_EQ(res.camera.brown_conrady.k3, 0.0);
  EXPECT_EQ(res.param_std[6], 0.0);
  EXPECT_EQ(res.param_std[8], 0.0);
  EXPECT_NEAR(res.camera.brown_conrady.k1, -0.1, 0.005);
}

// Views that stay near the image's centre do not determine k3 (the r^6 term)
// out at the corners: the standard views at 1.8 times their distance (corners
// out to 0.17 of the focal length from the axis, the image's corners at 0.44)
// with 0.3 px of noise. With this seed the free fit's k3 folds the distortion
// inside the image (most seeds give a valid k3 between -8 and +21); the fit is
// then made again with k3 held at 0, and says so. Asked to hold k3, it gives
// the same camera and says nothing. Holding k3 or the tangential pair is
// refused for a model without them.
TEST(CalibCamera, DistortionThatFoldsIsFitAgainWithoutK3) {
  std::vector<Pose> poses;
  for (Pose pose : StandardPoses()) {
    pose.translation() *= 1.8;
    poses.push_back(pose);
  }
  const auto views = Observe(Camera(TrueCamera()), poses, 0.3, 7);
  const auto res = CalibrateCamera(views, 1280, 1024);
  ASSERT_TRUE(res.ok) << res.reason;
  EXPECT_NE(res.note.find("k3 held at 0: with k3 free"), std::string::npos) << res.note;
  EXPECT_NE(res.note.find("folds inside the image"), std::string::npos) << res.note;
  EXPECT_EQ(res.camera.brown_conrady.k3, 0.0);
  EXPECT_EQ(res.param_std[8], 0.0);
  EXPECT_NO_THROW(Camera{res.camera});
  CameraCalibrationOptions o;
  o.fix_k3 = true;
  const auto held = CalibrateCamera(views, 1280, 1024, o);
  ASSERT_TRUE(held.ok) << held.reason;
  EXPECT_TRUE(held.note.empty());
  EXPECT_EQ(held.camera.fx, res.camera.fx);
  EXPECT_EQ(held.camera.brown_conrady.k1, res.camera.brown_conrady.k1);
  o.model = DistortionModel::kFisheye;
  EXPECT_THROW(CalibrateCamera(views, 1280, 1024, o), InputError);
  o.fix_k3 = false;
  o.fix_tangential = true;
  EXPECT_THROW(CalibrateCamera(views, 1280, 1024, o), InputError);
}

// Fisheye (Kannala–Brandt) from the pinhole closed-form start: a 600 px
// focal length, corners out to 53 degrees from the axis.
TEST(CalibCamera, FisheyeModel) {
  CameraParams p = TrueCamera();
  p.fx = 600;
  p.fy = 601;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {0.02, -0.01, 0.003, -0.001};
  const Camera cam(p);
  std::vector<Pose> poses;
  for (int v = 0; v < 12; ++v) {
    const double a = v * 30 * kDeg;
    poses.push_back(ViewPose(0.02 * std::cos(a) * (v % 3), 0.016 * std::sin(a) * (v % 3), 0.04 + 0.004 * (v % 4),
                             (20 + 3 * (v % 5)) * kDeg, a + 0.5, 0.3 * v));
  }
  CameraCalibrationOptions o;
  o.model = DistortionModel::kFisheye;
  auto exact = CalibrateCamera(Observe(cam, poses, 0.0), 1280, 1024, o);
  ASSERT_TRUE(exact.ok) << exact.reason;
  ASSERT_EQ(exact.params.size(), 8);
  const double truth[] = {p.fx, p.fy, p.cx, p.cy, p.fisheye.k1, p.fisheye.k2, p.fisheye.k3, p.fisheye.k4};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(exact.params[i], truth[i], 1e-6 * truth[i]) << exact.param_names[size_t(i)];
  for (int i = 4; i < 8; ++i) EXPECT_NEAR(exact.params[i], truth[i], 1e-7) << exact.param_names[size_t(i)];
  const auto noisy = CalibrateCamera(Observe(cam, poses, 0.1), 1280, 1024, o);
  ASSERT_TRUE(noisy.ok) << noisy.reason;
  EXPECT_EQ(noisy.camera.distortion, DistortionModel::kFisheye);
  EXPECT_NEAR(noisy.camera.fx, p.fx, 0.005 * p.fx);
  EXPECT_NEAR(noisy.camera.cx, p.cx, 2.0);
  for (int i = 0; i < 8; ++i) {
    EXPECT_LT(std::abs(noisy.params[i] - truth[i]), 4 * noisy.param_std[i]) << noisy.param_names[size_t(i)];
  }
}

// A wide fisheye (f 290 px on 640x512: 81 degrees from the axis at the image
// corner; Kannala-Brandt k1 -0.02, k2 0.003) and a 7 x 10 board of 3 mm
// squares at 24 to 32 mm, spread over the field (corners outside the image
// left out): a board spans tens of degrees of the field, far from a
// homography of the plane, and Zhang's closed form on the pixels has no
// solution ("the image of the absolute conic is not positive definite"). The
// equidistant start (calib_camera.cpp, FisheyeStart) gives one.
TEST(CalibCamera, WideFisheyeStartsFromAnEquidistantLens) {
  CameraParams p;
  p.width = 640;
  p.height = 512;
  p.fx = p.fy = 290;
  p.cx = 319.5;
  p.cy = 255.5;
  p.pixel_pitch_m = 9.6e-6;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {-0.02, 0.003, 0, 0};
  const Camera cam(p);
  std::vector<Pose> poses;
  for (int v = 0; v < 12; ++v) {
    const double a = v * 137.5 * kDeg, r = v == 0 ? 0.0 : 1.2 * std::sqrt(v / 12.0);
    const double z = 0.024 + 0.008 * ((v * 5) % 12) / 11.0;
    poses.push_back(ViewPose(r * z * std::cos(a), r * z * std::sin(a), z, (18 + 2.5 * (v % 10)) * kDeg, a + 1.0, 0.7 * v));
  }
  CameraCalibrationOptions o;
  o.model = DistortionModel::kFisheye;
  const std::vector<CalibrationView> views = Observe(cam, poses, 0.1);  // corners in the image
  const auto res = CalibrateCamera(views, p.width, p.height, o);
  ASSERT_TRUE(res.ok) << res.reason;
  // The equidistant start is within a few percent of the focal length.
  EXPECT_NEAR(res.closed_form_fx, p.fx, 0.05 * p.fx);
  // 0.1 px corner noise: within 4 reported standard deviations.
  const double truth[] = {p.fx, p.fy, p.cx, p.cy, p.fisheye.k1, p.fisheye.k2, p.fisheye.k3, p.fisheye.k4};
  for (int i = 0; i < 8; ++i) {
    EXPECT_LT(std::abs(res.params[i] - truth[i]), 4 * res.param_std[i]) << res.param_names[size_t(i)];
  }
}

// A wide fisheye (f 208 px on 640x512, 113 degrees at the image corner for an
// equidistant lens) whose Kannala-Brandt polynomial folds at 100 degrees from
// the axis, inside the image (k4 = -0.001236), seen by boards only out to
// about 70 degrees. The views determine the lens there and nothing beyond;
// the fit used to be refused because its fold lay inside the image. Now
// only the observed field (plus 10 degrees) must be free of a fold: the fit
// is made again with k4, then k3 held at 0, whose distortion does not fold in
// the image, and matches the lens over the observed field. A margin reaching
// past the fold keeps the refusal.
TEST(CalibCamera, FisheyeFoldBeyondTheObservedFieldIsFitAgainWithFewerCoefficients) {
  CameraParams p;
  p.width = 640;
  p.height = 512;
  p.fx = p.fy = 208;
  p.cx = 319.5;
  p.cy = 255.5;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {-0.02, 0.003, 0, -0.001236};
  EXPECT_THROW(Camera{p}, ParamError);  // the sensor refuses the lens itself: it folds inside the image
  std::vector<CalibrationView> views;
  double seen = 0;
  for (int v = 0; v < 12; ++v) {
    const double a = v * 137.5 * kDeg, r = v == 0 ? 0.0 : 1.2 * std::sqrt(v / 12.0);
    const double z = 0.024 + 0.008 * ((v * 5) % 12) / 11.0;
    const Pose pose = ViewPose(r * z * std::cos(a), r * z * std::sin(a), z, (18 + 2.5 * (v % 10)) * kDeg, a + 1.0, 0.7 * v);
    CalibrationView view;
    for (const Eigen::Vector3d& t : TargetPoints()) {
      const Eigen::Vector3d q = pose * t;
      Eigen::Vector2d px;
      if (!ProjectWithModel(p, q, &px)) continue;
      if (px.x() < 0 || px.y() < 0 || px.x() > p.width - 1 || px.y() > p.height - 1) continue;
      seen = std::max(seen, std::atan2(q.head<2>().norm(), q.z()));
      view.target_points.push_back(t);
      view.pixels.push_back(px);
    }
    views.push_back(view);
  }
  ASSERT_LT(seen, 75 * kDeg);
  CameraCalibrationOptions o;
  o.model = DistortionModel::kFisheye;
  const auto res = CalibrateCamera(views, p.width, p.height, o);
  ASSERT_TRUE(res.ok) << res.reason;
  EXPECT_NEAR(res.observed_field_rad, seen, 1e-3);
  // With k4 held the fit still folds in the image (at 110 degrees, measured), so k3 is held too.
  EXPECT_NE(res.note.find("k3..k4 held at 0: with k3 free"), std::string::npos) << res.note;
  EXPECT_NE(res.note.find("beyond the field the boards observed (corners up to"), std::string::npos) << res.note;
  EXPECT_EQ(res.camera.fisheye.k3, 0.0);
  EXPECT_EQ(res.camera.fisheye.k4, 0.0);
  EXPECT_LT(res.rms_px, 0.05);  // noise-free corners: measured 0.009 px
  const Camera fitted(res.camera);  // a camera of the sensor's model: no fold in the image
  // Over the observed field the fit follows the lens.
  double worst = 0;
  for (double theta = 0; theta <= seen; theta += 0.5 * kDeg) {
    for (double phi = 0; phi < 2 * M_PI; phi += 30 * kDeg) {
      const Eigen::Vector3d ray(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      Eigen::Vector2d truth;
      ASSERT_TRUE(ProjectWithModel(p, ray, &truth));
      const auto px = fitted.Project(ray);
      ASSERT_TRUE(px);
      worst = std::max(worst, (*px - truth).norm());
    }
  }
  EXPECT_LT(worst, 0.5);
  // Checked out to 45 degrees beyond the observed field, the fold at 100 degrees is within: refused.
  o.fisheye_field_margin_deg = 45;
  const auto refused = CalibrateCamera(views, p.width, p.height, o);
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.reason.find("the fisheye distortion folds at 100"), std::string::npos) << refused.reason;
  EXPECT_NE(refused.reason.find("deg from the axis, within the field the boards observed"), std::string::npos)
      << refused.reason;
}

TEST(CalibCamera, RefusesTooFewViews) {
  const Camera cam(TrueCamera());
  auto poses = StandardPoses();
  poses.resize(2);
  const auto res = CalibrateCamera(Observe(cam, poses, 0.1), 1280, 1024);
  EXPECT_FALSE(res.ok);
  EXPECT_NE(res.reason.find("too few views"), std::string::npos) << res.reason;
}

TEST(CalibCamera, RefusesViewsParallelToTheImagePlane) {
  const Camera cam(TrueCamera());
  std::vector<Pose> poses;
  for (int v = 0; v < 6; ++v) poses.push_back(ViewPose(0.002 * v - 0.005, 0.001 * v, 0.07 + 0.004 * v, 0, 0, 0.5 * v));
  for (double noise : {0.0, 0.1}) {
    const auto res = CalibrateCamera(Observe(cam, poses, noise), 1280, 1024);
    EXPECT_FALSE(res.ok) << "noise " << noise << ": fx " << res.camera.fx;
    EXPECT_FALSE(res.reason.empty());
  }
  // Slight tilts (1 degree) with noise: the focal length is undetermined to
  // more than 2%, which is refused with the figures.
  poses.clear();
  for (int v = 0; v < 6; ++v) {
    poses.push_back(ViewPose(0.002 * v - 0.005, 0.001 * v, 0.07 + 0.004 * v, 1 * kDeg, v * 60 * kDeg, 0.5 * v));
  }
  const auto res = CalibrateCamera(Observe(cam, poses, 0.1), 1280, 1024);
  EXPECT_FALSE(res.ok);
  EXPECT_NE(res.reason.find("poorly determined"), std::string::npos) << res.reason;
}

TEST(CalibCamera, RefusesDegenerateViews) {
  const Camera cam(TrueCamera());
  auto views = Observe(cam, StandardPoses(), 0.1);
  {
    auto v = views;
    v[3].target_points.resize(3);
    v[3].pixels.resize(3);
    const auto res = CalibrateCamera(v, 1280, 1024);
    EXPECT_FALSE(res.ok);
    EXPECT_NE(res.reason.find("view 3 has too few corners"), std::string::npos) << res.reason;
  }
  {
    auto v = views;  // the first row only: collinear
    v[2].target_points.resize(10);
    v[2].pixels.resize(10);
    const auto res = CalibrateCamera(v, 1280, 1024);
    EXPECT_FALSE(res.ok);
    EXPECT_NE(res.reason.find("collinear"), std::string::npos) << res.reason;
  }
  {
    auto v = views;
    v[1].target_points[5].z() = 1e-3;
    const auto res = CalibrateCamera(v, 1280, 1024);
    EXPECT_FALSE(res.ok);
    EXPECT_NE(res.reason.find("not planar"), std::string::npos) << res.reason;
  }
  {
    auto v = views;
    v[0].pixels[0].x() = NAN;
    EXPECT_FALSE(CalibrateCamera(v, 1280, 1024).ok);
  }
  {
    auto v = views;
    v[0].pixels.pop_back();
    EXPECT_THROW(CalibrateCamera(v, 1280, 1024), InputError);
  }
  CameraCalibrationOptions o;
  o.min_views = 2;
  EXPECT_THROW(CalibrateCamera(views, 1280, 1024, o), InputError);
}

TEST(CalibCamera, HomographyIsExactForAPinhole) {
  Eigen::Matrix3d h;
  h << 900, 30, 400, -20, 880, 300, 0.05, -0.02, 1;
  std::vector<Eigen::Vector2d> from, to;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) {
      Eigen::Vector2d p(0.1 * i, 0.13 * j);
      from.push_back(p);
      to.push_back((h * p.homogeneous()).hnormalized());
    }
  Eigen::Matrix3d e;
  ASSERT_TRUE(EstimateHomography(from, to, &e));
  EXPECT_LT((e - h).norm() / h.norm(), 1e-12);
  from.resize(3);
  to.resize(3);
  EXPECT_FALSE(EstimateHomography(from, to, &e));
}

// The LM solver on a problem with a closed-form answer: a line fit.
TEST(CalibLm, FitsALineAndItsCovariance) {
  std::vector<double> xs, ys;
  for (int i = 0; i < 50; ++i) {
    Rng rng = Rng::For(3, i, 0, 0);
    xs.push_back(i * 0.1);
    ys.push_back(2.0 + 0.5 * xs.back() + 0.01 * rng.NextGaussian());
  }
  LmProblem p;
  p.num_params = 2;
  p.num_residuals = 50;
  p.residuals = [&](const Eigen::VectorXd& x, Eigen::VectorXd* r) {
    for (int i = 0; i < 50; ++i) (*r)[i] = x[0] + x[1] * xs[size_t(i)] - ys[size_t(i)];
    return true;
  };
  p.diff_step = Eigen::Vector2d(1e-6, 1e-6);
  const LmSummary s = SolveLevenbergMarquardt(p, Eigen::Vector2d(0, 0));
  ASSERT_TRUE(s.converged) << s.message;
  // Ordinary least squares in closed form.
  Eigen::MatrixXd a(50, 2);
  Eigen::VectorXd b(50);
  for (int i = 0; i < 50; ++i) {
    a.row(i) << 1, xs[size_t(i)];
    b[i] = ys[size_t(i)];
  }
  const Eigen::Vector2d ols = a.colPivHouseholderQr().solve(b);
  EXPECT_NEAR(s.x[0], ols[0], 1e-9);
  EXPECT_NEAR(s.x[1], ols[1], 1e-9);
  const LmCovariance c = EstimateCovariance(s, {"a", "b"});
  ASSERT_TRUE(c.ok) << c.reason;
  const double sigma2 = (a * ols - b).squaredNorm() / 48;
  const Eigen::Matrix2d expected = sigma2 * (a.transpose() * a).inverse();
  EXPECT_LT((c.covariance - expected).norm() / expected.norm(), 1e-6);

  // A parameter with no effect is named.
  p.num_params = 3;
  p.diff_step = Eigen::Vector3d(1e-6, 1e-6, 1e-6);
  const LmSummary s3 = SolveLevenbergMarquardt(p, Eigen::Vector3d(0, 0, 0));
  const LmCovariance c3 = EstimateCovariance(s3, {"a", "b", "c"});
  EXPECT_FALSE(c3.ok);
  EXPECT_NE(c3.reason.find("c has no effect"), std::string::npos) << c3.reason;
}

}  // namespace
}  // namespace lt
