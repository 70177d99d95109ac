// Planar PnP (pipeline/calib_target_pose.h): the board pose from its corners
// through a known camera, exact without noise, with an honest standard
// deviation with noise, usable at steep tilts, and refusals instead of NaN.
#include <gtest/gtest.h>

#include "calib_test_util.h"

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "pipeline/calib_target_pose.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

CalibrationView Project(const Camera& cam, const Pose& cam_from_board, double noise_px, uint64_t seed) {
  CalibrationView v;
  const CheckerboardSpec b = Board();
  int k = 0;
  for (const Eigen::Vector3d& p : b.CornerPoints()) {
    const auto px = cam.Project(cam_from_board * p);
    EXPECT_TRUE(px.has_value());
    Rng rng = Rng::For(seed, 0, uint64_t(k++), 0, 11);
    v.target_points.push_back(p);
    v.pixels.push_back(*px + noise_px * Eigen::Vector2d(rng.NextGaussian(), rng.NextGaussian()));
  }
  return v;
}

TEST(CalibTargetPose, ExactWithoutNoise) {
  const Camera cam = RigCamera();  // Brown–Conrady k1 = −0.1: the distortion is removed exactly
  for (const Pose& truth : {BoardPose(0, 0, 0.2, 30 * kDeg, 0, 0), BoardPose(0.01, -0.005, 0.21, 40 * kDeg, 2.0, 3.0),
                            BoardPose(-0.01, 0.01, 0.19, 5 * kDeg, 1.0, -2.0)}) {
    const TargetPoseResult r = EstimateTargetPose(cam, Project(cam, truth, 0, 1));
    ASSERT_TRUE(r.ok) << r.reason;
    const PoseError e = ComparePoses(r.cam_from_target, truth);
    EXPECT_LT(e.rotation_rad, 1e-9);
    EXPECT_LT(e.translation_m, 1e-11);
    EXPECT_LT(r.rms_px, 1e-8);
  }
}

// With 0.1 px corner noise the pose error stays within 4 reported standard
// deviations in every view (a bound a correct σ fails with probability < 1e-3
// per component), and σ itself is of the expected size.
TEST(CalibTargetPose, NoisyCornersHonestUncertainty) {
  const Camera cam = RigCamera();
  int v = 0;
  for (const Pose& truth : {BoardPose(0, 0, 0.2, 30 * kDeg, 0, 0), BoardPose(0.01, -0.005, 0.21, 40 * kDeg, 2.0, 3.0),
                            BoardPose(-0.01, 0.01, 0.19, 20 * kDeg, 1.0, -2.0)}) {
    const TargetPoseResult r = EstimateTargetPose(cam, Project(cam, truth, 0.1, 100 + v++));
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_NEAR(r.rms_px, 0.1, 0.03);
    const Pose& est = r.cam_from_target;
    const Eigen::Vector3d drot = RotationLog(est.linear() * truth.linear().transpose());
    const Eigen::Vector3d dt = est.translation() - truth.translation();
    for (int i = 0; i < 3; ++i) {
      EXPECT_GT(r.pose_std[i], 0);
      EXPECT_LT(std::abs(drot[i]), 4 * r.pose_std[i]) << "rotation axis " << i;
      EXPECT_LT(std::abs(dt[i]), 4 * r.pose_std[3 + i]) << "translation axis " << i;
    }
    EXPECT_LT(r.pose_std.tail<3>().norm(), 0.05e-3);  // tens of µm at 200 mm
  }
}

// A board seen at a grazing 75° (squares foreshortened to a quarter) still
// gives a pose, within 4 of its reported, finite standard deviations.
TEST(CalibTargetPose, GrazingViewHasAnHonestUncertainty) {
  const Camera cam = RigCamera();
  for (double axis : {0.0, 1.2, 2.5}) {
    const Pose truth = BoardPose(0, 0, 0.2, 75 * kDeg, axis, 0.5);
    const TargetPoseResult r = EstimateTargetPose(cam, Project(cam, truth, 0.1, 7));
    ASSERT_TRUE(r.ok) << r.reason;
    ASSERT_TRUE(r.pose_std.allFinite());
    const Eigen::Vector3d drot = RotationLog(r.cam_from_target.linear() * truth.linear().transpose());
    const Eigen::Vector3d dt = r.cam_from_target.translation() - truth.translation();
    for (int i = 0; i < 3; ++i) {
      EXPECT_LT(std::abs(drot[i]), 4 * r.pose_std[i]) << "axis " << axis << ", rotation " << i;
      EXPECT_LT(std::abs(dt[i]), 4 * r.pose_std[3 + i]) << "axis " << axis << ", translation " << i;
    }
  }
}

TEST(CalibTargetPose, RefusesDegenerateViews) {
  const Camera cam = RigCamera();
  const CalibrationView good = Project(cam, BoardPose(0, 0, 0.2, 30 * kDeg, 0, 0), 0, 1);
  CalibrationView few = good;
  few.target_points.resize(3);
  few.pixels.resize(3);
  EXPECT_NE(EstimateTargetPose(cam, few).reason.find("at least 4"), std::string::npos);

  CalibrationView line;  // the first row of corners only: collinear
  for (int j = 0; j < Board().cols; ++j) {
    line.target_points.push_back(good.target_points[size_t(j)]);
    line.pixels.push_back(good.pixels[size_t(j)]);
  }
  const TargetPoseResult r = EstimateTargetPose(cam, line);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_TRUE(r.cam_from_target.matrix().allFinite());

  CalibrationView nan = good;
  nan.pixels[5].x() = std::nan("");
  EXPECT_NE(EstimateTargetPose(cam, nan).reason.find("non-finite"), std::string::npos);

  CalibrationView bumpy = good;
  bumpy.target_points[2].z() = 1e-3;
  EXPECT_NE(EstimateTargetPose(cam, bumpy).reason.find("planar"), std::string::npos);

  CalibrationView mismatched = good;
  mismatched.pixels.pop_back();
  EXPECT_THROW(EstimateTargetPose(cam, mismatched), InputError);
}

}  // namespace
}  // namespace lt
