// Hand-eye calibration (AX = XB) on a synthetic robot cell: a scanner camera
// on a robot flange looking at a fixed checkerboard from about 0.2 m.
#include <gtest/gtest.h>

#include "calib_test_util.h"

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "pipeline/calib_hand_eye.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

Pose TrueToolFromCam() {
  Pose x = Pose::Identity();
  x.linear() = (Eigen::AngleAxisd(90 * kDeg, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-2 * kDeg, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(3 * kDeg, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  x.translation() = Eigen::Vector3d(0.05, -0.02, 0.08);
  return x;
}

Pose TrueBaseFromTarget() {
  Pose y = Pose::Identity();
  y.linear() = Eigen::AngleAxisd(20 * kDeg, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  y.translation() = Eigen::Vector3d(0.5, 0.1, 0.0);
  return y;
}

// 7 x 10 inner corners, 8 mm squares, centred on the target origin.
std::vector<Eigen::Vector3d> Corners() {
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 10; ++j) pts.emplace_back((j - 4.5) * 8e-3, (i - 3) * 8e-3, 0.0);
  return pts;
}

// Camera positions above the target (azimuth, elevation from the bed plane,
// distance) and a roll of the camera about its view axis.
struct Station {
  double azimuth_deg, elevation_deg, distance_m, roll_deg;
};

std::vector<Station> StandardStations() {
  return {{0, 80, 0.20, 0},    {60, 60, 0.22, 20},   {130, 65, 0.19, -30}, {200, 55, 0.21, 45},
          {270, 70, 0.20, -10}, {320, 58, 0.23, 90}, {30, 75, 0.18, -60},  {170, 62, 0.20, 150}};
}

Pose CameraPoseInBase(const Station& s) {
  const Pose y = TrueBaseFromTarget();
  const double az = s.azimuth_deg * kDeg, el = s.elevation_deg * kDeg;
  const Eigen::Vector3d target = y.translation();
  const Eigen::Vector3d eye =
      target + s.distance_m * Eigen::Vector3d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  Pose base_from_cam = LookAt(eye, target, Eigen::Vector3d(0, 0, 1));
  base_from_cam.linear() = base_from_cam.linear() * Eigen::AngleAxisd(s.roll_deg * kDeg, Eigen::Vector3d::UnitZ());
  return base_from_cam;
}

Pose Perturb(const Pose& p, double rot_sigma_rad, double trans_sigma_m, Rng& rng) {
  Vector6d d;
  for (int k = 0; k < 3; ++k) d[k] = rot_sigma_rad * rng.NextGaussian();
  for (int k = 3; k < 6; ++k) d[k] = trans_sigma_m * rng.NextGaussian();
  return PosePlus(p, d);
}

struct Noise {
  double robot_rot_deg = 0, robot_trans_m = 0;  // on base_from_tool
  double view_rot_deg = 0, view_trans_m = 0;    // on cam_from_target
  double corner_px = 0;
};

std::vector<HandEyeObservation> Observe(const std::vector<Station>& stations, const Noise& noise, bool corners,
                                        uint64_t seed = 11) {
  const Camera cam = RigCamera();
  const Pose x = TrueToolFromCam(), y = TrueBaseFromTarget();
  std::vector<HandEyeObservation> obs;
  for (size_t i = 0; i < stations.size(); ++i) {
    Rng rng = Rng::For(seed, i, 0, 0, 3);
    const Pose base_from_cam = CameraPoseInBase(stations[i]);
    const Pose cam_from_target = base_from_cam.inverse() * y;
    HandEyeObservation o;
    o.base_from_tool = Perturb(base_from_cam * x.inverse(), noise.robot_rot_deg * kDeg, noise.robot_trans_m, rng);
    o.cam_from_target = Perturb(cam_from_target, noise.view_rot_deg * kDeg, noise.view_trans_m, rng);
    if (corners) {
      for (const auto& p : Corners()) {
        const auto px = cam.Project(cam_from_target * p);
        EXPECT_TRUE(px && cam.InImage(*px)) << "station " << i;
        if (!px) continue;
        o.target_points.push_back(p);
        o.pixels.push_back(*px + noise.corner_px * Eigen::Vector2d(rng.NextGaussian(), rng.NextGaussian()));
      }
    }
    obs.push_back(o);
  }
  return obs;
}

TEST(CalibHandEye, NoiseFreeClosedFormAndRefinementAreExact) {
  const auto obs = Observe(StandardStations(), {}, true);
  for (int mode = 0; mode < 4; ++mode) {
    const bool with_camera = mode & 1;
    HandEyeOptions o;  // robot poses refined (with priors) or held fixed
    if (mode & 2) o.robot_rotation_sigma_deg = o.robot_translation_sigma_m = 0;
    const Camera cam = RigCamera();
    const HandEyeResult r = CalibrateHandEye(obs, o, with_camera ? &cam : nullptr);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_EQ(r.used_reprojection, with_camera);
    const PoseError cf = ComparePoses(r.closed_form_tool_from_cam, TrueToolFromCam());
    EXPECT_LT(cf.rotation_rad, 1e-9);
    EXPECT_LT(cf.translation_m, 1e-9);
    const PoseError e = ComparePoses(r.tool_from_cam, TrueToolFromCam());
    EXPECT_LT(e.rotation_rad, 1e-9);
    EXPECT_LT(e.translation_m, 1e-9);
    const PoseError ey = ComparePoses(r.base_from_target, TrueBaseFromTarget());
    EXPECT_LT(ey.translation_m, 1e-9);
  }
}

TEST(CalibHandEye, NoisyPosesRefinedOnPoseResiduals) {
  Noise noise;
  noise.robot_rot_deg = 0.005;
  noise.robot_trans_m = 0.02e-3;
  noise.view_rot_deg = 0.02;
  noise.view_trans_m = 0.05e-3;
  const HandEyeResult r = CalibrateHandEye(Observe(StandardStations(), noise, false));
  ASSERT_TRUE(r.ok) << r.reason;
  const PoseError e = ComparePoses(r.tool_from_cam, TrueToolFromCam());
  EXPECT_LT(e.rotation_rad, 0.05 * kDeg);
  EXPECT_LT(e.translation_m, 0.3e-3);
  // The reported uncertainty covers the error (4 standard deviations of the
  // three-component error, whose norm has a chi(3) spread).
  EXPECT_LT(e.rotation_rad, 4 * r.rotation_std_rad);
  EXPECT_LT(e.translation_m, 4 * r.translation_std_m);
  EXPECT_GT(r.rotation_std_rad, 0);
  // The noise levels match the defaults of the noise model: the variance
  // factor is near 1 (48 + 48 residuals for 60 parameters: its relative
  // standard error is about sqrt(2/36) = 24%).
  EXPECT_NEAR(r.variance_factor, 1.0, 0.6);
}

TEST(CalibHandEye, NoisyCornersRefinedOnReprojection) {
  Noise noise;
  noise.robot_rot_deg = 0.005;
  noise.robot_trans_m = 0.02e-3;
  noise.view_rot_deg = 0.05;  // the starting cam_from_target (PnP) is rougher
  noise.view_trans_m = 0.1e-3;
  noise.corner_px = 0.1;
  const Camera cam = RigCamera();
  const HandEyeResult r = CalibrateHandEye(Observe(StandardStations(), noise, true), {}, &cam);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_TRUE(r.used_reprojection);
  const PoseError e = ComparePoses(r.tool_from_cam, TrueToolFromCam());
  const PoseError cf = ComparePoses(r.closed_form_tool_from_cam, TrueToolFromCam());
  EXPECT_LT(e.rotation_rad, 0.05 * kDeg);
  EXPECT_LT(e.translation_m, 0.3e-3);
  EXPECT_LT(e.rotation_rad, 4 * r.rotation_std_rad);
  EXPECT_LT(e.translation_m, 4 * r.translation_std_m);
  // Corners at 0.1 px pin the poses better than the rough starting views.
  EXPECT_LT(e.translation_m, cf.translation_m);
  // The robot's pose errors go into the robot pose corrections, leaving the
  // corner noise (560 residuals for 60 parameters: σ₀² within ±20%).
  EXPECT_NEAR(r.reprojection_rms_px, 0.1, 0.015);
  EXPECT_NEAR(r.variance_factor, 1.0, 0.2);

  // Holding the robot poses fixed forces their errors into X, and the
  // residuals show it (the corners no longer fit to their noise).
  HandEyeOptions fixed;
  fixed.robot_rotation_sigma_deg = fixed.robot_translation_sigma_m = 0;
  const HandEyeResult f = CalibrateHandEye(Observe(StandardStations(), noise, true), fixed, &cam);
  ASSERT_TRUE(f.ok) << f.reason;
  EXPECT_GT(f.variance_factor, 2.0);
}

TEST(CalibHandEye, RefusesTooFewViews) {
  auto st = StandardStations();
  st.resize(2);
  const HandEyeResult r = CalibrateHandEye(Observe(st, {}, false));
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("too few views"), std::string::npos) << r.reason;
}

TEST(CalibHandEye, RefusesSmallRotations) {
  // The camera moves around the target but keeps (nearly) its orientation.
  std::vector<HandEyeObservation> obs = Observe(StandardStations(), {}, false);
  const Pose x = TrueToolFromCam(), y = TrueBaseFromTarget();
  const Pose base_from_cam0 = CameraPoseInBase(StandardStations()[0]);
  for (size_t i = 0; i < obs.size(); ++i) {
    Pose base_from_cam = base_from_cam0;
    base_from_cam.linear() = base_from_cam.linear() * Eigen::AngleAxisd(0.3 * kDeg * double(i),
                                                                        Eigen::Vector3d(1, double(i % 3), 0.5).normalized());
    base_from_cam.translation() += Eigen::Vector3d(0.01 * double(i), -0.005 * double(i), 0.002 * double(i));
    obs[i].base_from_tool = base_from_cam * x.inverse();
    obs[i].cam_from_target = base_from_cam.inverse() * y;
  }
  const HandEyeResult r = CalibrateHandEye(obs);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("rotations are too small"), std::string::npos) << r.reason;
  EXPECT_LT(r.largest_rotation_deg, 5.0);
}

TEST(CalibHandEye, RefusesRotationsAboutParallelAxes) {
  // The robot turns the scanner about the vertical axis through the target only.
  std::vector<Station> st;
  for (int i = 0; i < 6; ++i) st.push_back({60.0 * i, 65, 0.2, 0});
  for (double noise_deg : {0.0, 0.01}) {
    Noise noise;
    noise.robot_rot_deg = noise.view_rot_deg = noise_deg;
    const HandEyeResult r = CalibrateHandEye(Observe(st, noise, false));
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.reason.find("axes are nearly parallel"), std::string::npos) << r.reason;
    EXPECT_GT(r.largest_rotation_deg, 90.0);
  }
}

TEST(CalibHandEye, BadInput) {
  auto obs = Observe(StandardStations(), {}, true);
  const Camera cam = RigCamera();
  auto o = obs;
  o[2].pixels.pop_back();
  EXPECT_THROW(CalibrateHandEye(o), InputError);
  o = obs;
  o[1].target_points.clear();
  o[1].pixels.clear();
  EXPECT_THROW(CalibrateHandEye(o, {}, &cam), InputError);
  o = obs;
  o[0].base_from_tool.translation().x() = NAN;
  EXPECT_FALSE(CalibrateHandEye(o).ok);
  HandEyeOptions bad;
  bad.min_rotation_deg = 0;
  EXPECT_THROW(CalibrateHandEye(obs, bad), InputError);
}

}  // namespace
}  // namespace lt
