// A calibration session on synthetic images: boards rendered through a known
// camera, corners detected, the camera calibrated from them, then the laser
// plane from stripe pixels on the calibrated target poses.
#include <gtest/gtest.h>

#include <cmath>

#include "core/random.h"
#include "pipeline/calib_camera.h"
#include "pipeline/calib_corners.h"
#include "pipeline/calib_laser_plane.h"
#include "sensor/laser.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

CameraParams TrueCamera() {
  CameraParams p;
  p.width = 640;
  p.height = 480;
  p.fx = 805;
  p.fy = 803;
  p.cx = 323.4;
  p.cy = 236.8;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.18, 0.09, 3e-4, -2e-4, 0};
  return p;
}

CheckerboardSpec Board() {
  CheckerboardSpec b;
  b.rows = 7;
  b.cols = 10;
  b.square_m = 6e-3;
  return b;
}

Pose BoardPose(double ox, double oy, double z, double tilt, double axis, double spin) {
  const CheckerboardSpec b = Board();
  const Eigen::Vector3d centre(0.5 * (b.cols - 1) * b.square_m, 0.5 * (b.rows - 1) * b.square_m, 0);
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)) *
                Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(ox, oy, z) - p.linear() * centre;
  return p;
}

std::vector<Pose> SessionPoses() {
  return {BoardPose(0, 0, 0.20, 30 * kDeg, 0, 0),
          BoardPose(0.03, -0.02, 0.21, 35 * kDeg, 90 * kDeg, 15 * kDeg),
          BoardPose(-0.03, 0.02, 0.22, 30 * kDeg, 45 * kDeg, -20 * kDeg),
          BoardPose(0.03, 0.025, 0.19, 25 * kDeg, 135 * kDeg, 180 * kDeg),
          BoardPose(-0.035, -0.02, 0.23, 40 * kDeg, 200 * kDeg, 5 * kDeg),
          BoardPose(0.0, 0.03, 0.20, 20 * kDeg, 270 * kDeg, 90 * kDeg),
          BoardPose(-0.02, 0.0, 0.18, 35 * kDeg, 315 * kDeg, -90 * kDeg),
          BoardPose(0.0, -0.03, 0.21, 15 * kDeg, 160 * kDeg, 45 * kDeg)};
}

TEST(CalibSyntheticSession, CameraFromRenderedBoards) {
  const Camera cam(TrueCamera());
  const CheckerboardSpec board = Board();
  std::vector<CalibrationView> views;
  const auto poses = SessionPoses();
  for (size_t v = 0; v < poses.size(); ++v) {
    SyntheticBoardOptions o;
    o.noise_sigma = 0.01 * (o.white - o.black);
    o.seed = 300 + v;
    const CornerDetection d = DetectCheckerboard(RenderCheckerboard(cam, poses[v], board, o).View(), board);
    ASSERT_TRUE(d.ok) << "view " << v << ": " << d.reason;
    views.push_back({board.CornerPoints(), d.corners});
  }
  const CameraCalibrationResult r = CalibrateCamera(views, 640, 480);
  ASSERT_TRUE(r.ok) << r.reason;
  const CameraParams& t = cam.params();
  EXPECT_NEAR(r.camera.fx, t.fx, 0.005 * t.fx);
  EXPECT_NEAR(r.camera.fy, t.fy, 0.005 * t.fy);
  EXPECT_NEAR(r.camera.cx, t.cx, 2.0);
  EXPECT_NEAR(r.camera.cy, t.cy, 2.0);
  EXPECT_NEAR(r.camera.brown_conrady.k1, t.brown_conrady.k1, 0.01);
  // Detected corners are good to a few hundredths of a pixel, and so are the
  // reprojection residuals.
  EXPECT_LT(r.rms_px, 0.05);
  // The recovered board poses match the rendered ones.
  for (size_t v = 0; v < poses.size(); ++v) {
    const PoseError e = ComparePoses(r.cam_from_target[v], poses[v]);
    EXPECT_LT(e.rotation_rad, 0.05 * kDeg) << "view " << v;
    EXPECT_LT(e.translation_m, 0.1e-3) << "view " << v;
  }
}

}  // namespace
}  // namespace lt
