// A calibration session on synthetic images: boards rendered through a known
// camera, corners detected, the camera calibrated from them, then the laser
// plane from stripe pixels on the calibrated target poses.
#include <gtest/gtest.h>

#include "calib_test_util.h"

#include <cmath>

#include "core/random.h"
#include "pipeline/calib_camera.h"
#include "pipeline/calib_corners.h"
#include "pipeline/calib_laser_plane.h"
#include "sensor/laser.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

CameraParams TrueCamera() { return Camera640Params({-0.18, 0.09, 3e-4, -2e-4, 0}); }

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

// The camera calibrated from rendered boards (shared by the tests below).
struct Session {
  CameraCalibrationResult calibration;
  std::vector<Pose> true_poses;
};

const Session& CalibratedSession() {
  static const Session session = [] {
    Session s;
    const Camera cam(TrueCamera());
    const CheckerboardSpec board = Board();
    std::vector<CalibrationView> views;
    s.true_poses = SessionPoses();
    for (size_t v = 0; v < s.true_poses.size(); ++v) {
      SyntheticBoardOptions o;
      o.noise_sigma = 0.01 * (o.white - o.black);
      o.seed = 300 + v;
      const CornerDetection d = DetectCheckerboard(RenderCheckerboard(cam, s.true_poses[v], board, o).View(), board);
      EXPECT_TRUE(d.ok) << "view " << v << ": " << d.reason;
      if (d.ok) views.push_back({board.CornerPoints(), d.corners});
    }
    s.calibration = CalibrateCamera(views, 640, 480);
    return s;
  }();
  return session;
}

TEST(CalibSyntheticSession, CameraFromRenderedBoards) {
  const Camera cam(TrueCamera());
  const Session& s = CalibratedSession();
  const CameraCalibrationResult& r = s.calibration;
  ASSERT_TRUE(r.ok) << r.reason;
  const auto& poses = s.true_poses;
  ASSERT_EQ(r.cam_from_target.size(), poses.size());
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

// The laser plane from the stripe on the same boards, triangulated with the
// calibrated camera and the calibrated board poses: the error now includes
// the calibration's own (a laser 60 mm beside the camera, its sheet crossing
// the optical axis at 200 mm; 0.1 px stripe noise).
TEST(CalibSyntheticSession, LaserPlaneThroughTheCalibratedCamera) {
  const Session& s = CalibratedSession();
  ASSERT_TRUE(s.calibration.ok) << s.calibration.reason;
  const Camera truth_cam(TrueCamera());
  const Camera calibrated(s.calibration.camera);
  LaserParams lp;
  lp.cam_from_projector = Pose::Identity();
  lp.cam_from_projector.linear() = Eigen::AngleAxisd(std::atan(0.3), Eigen::Vector3d::UnitX()).toRotationMatrix();
  lp.cam_from_projector.translation() = Eigen::Vector3d(0, 0.06, 0);
  lp.fan_angle_rad = 40 * kDeg;
  const LaserProjector laser(lp);
  const Plane sheet = laser.SheetPlane(0);
  std::vector<LaserTargetView> views;
  for (size_t v = 0; v < s.true_poses.size(); ++v) {
    const Pose& pose = s.true_poses[v];
    const Plane target = Plane{Eigen::Vector3d::UnitZ(), 0.0}.Transformed(pose);
    const Eigen::Vector3d dir = sheet.n.cross(target.n).normalized();
    Eigen::Matrix3d a;
    a << sheet.n.transpose(), target.n.transpose(), dir.transpose();
    const Eigen::Vector3d x0 = a.inverse() * Eigen::Vector3d(-sheet.d, -target.d, 0);
    LaserTargetView view;
    view.cam_from_target = s.calibration.cam_from_target[v];
    int k = 0;
    for (double t = -0.05; t <= 0.05; t += 2e-4) {
      const Eigen::Vector3d p = x0 + t * dir;
      const Eigen::Vector3d on_board = pose.inverse() * p;
      const CheckerboardSpec b = Board();
      if (on_board.x() < -b.square_m || on_board.x() > b.cols * b.square_m || on_board.y() < -b.square_m ||
          on_board.y() > b.rows * b.square_m) {
        continue;
      }
      const auto px = truth_cam.Project(p);
      if (!px || !truth_cam.InImage(*px)) continue;
      Rng rng = Rng::For(7, v, k++, 0, 5);
      view.stripe_pixels.push_back(*px + 0.1 * Eigen::Vector2d(rng.NextGaussian(), rng.NextGaussian()));
    }
    views.push_back(view);
  }
  const auto fits = CalibrateLaserPlanes(calibrated, views);
  ASSERT_EQ(fits.size(), 1u);
  ASSERT_TRUE(fits[0].ok) << fits[0].reason;
  const PlaneError e = ComparePlanes(fits[0].plane, sheet);
  EXPECT_LT(e.normal_angle_rad, 0.05 * kDeg);
  EXPECT_LT(e.offset_m, 0.05e-3);
  // The pose and intrinsics errors are small against the stripe scatter here,
  // so the reported uncertainty (which covers the scatter only) still holds.
  EXPECT_LT(e.normal_angle_rad, 4 * fits[0].normal_std_rad);
  EXPECT_LT(e.offset_m, 4 * fits[0].offset_std_m);
}

}  // namespace
}  // namespace lt
