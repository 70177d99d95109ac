// Calibration results written as a calibration file and read back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "calib_test_util.h"
#include "pipeline/calib_output.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

CameraCalibrationResult CalibratedCamera640() {
  const Camera cam(Camera640Params({-0.18, 0.09, 3e-4, -2e-4, 0.01}));
  std::vector<CalibrationView> views;
  for (int v = 0; v < 5; ++v) {
    Pose pose = Pose::Identity();
    pose.linear() = (Eigen::AngleAxisd(0.4, Eigen::Vector3d(std::cos(1.3 * v), std::sin(1.3 * v), 0)) *
                     Eigen::AngleAxisd(0.5 * v, Eigen::Vector3d::UnitZ()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(0.01 * (v % 2), -0.005 * (v % 3), 0.2) - pose.linear() * Eigen::Vector3d(0.027, 0.018, 0);
    CalibrationView view;
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 10; ++j) {
        const Eigen::Vector3d q(j * 6e-3, i * 6e-3, 0);
        view.target_points.push_back(q);
        view.pixels.push_back(*cam.Project(pose * q));
      }
    views.push_back(view);
  }
  return CalibrateCamera(views, 640, 480);
}

std::vector<LaserPlaneFit> TwoPlanes() {
  std::vector<LaserPlaneFit> fits;
  for (int id = 0; id < 2; ++id) {
    const Plane truth = Plane::FromPointNormal(Eigen::Vector3d(0, 0.01 * id, 0.08), Eigen::Vector3d(0, 0.9, 0.44 + 0.1 * id));
    const Eigen::Vector3d u = truth.n.unitOrthogonal(), w = truth.n.cross(u);
    std::vector<Eigen::Vector3d> pts;
    for (int a = 0; a < 10; ++a)
      for (int b = 0; b < 10; ++b) pts.push_back(-truth.d * truth.n + 1e-3 * a * u + 1e-3 * b * w);
    fits.push_back(FitLaserPlane(pts, {}, id));
  }
  return fits;
}

TEST(CalibOutput, ResultsRoundTripThroughTheFile) {
  const CameraCalibrationResult cam = CalibratedCamera640();
  ASSERT_TRUE(cam.ok) << cam.reason;
  const auto planes = TwoPlanes();
  ASSERT_TRUE(planes[0].ok && planes[1].ok);
  HandEyeResult he;
  he.ok = true;
  he.tool_from_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  he.tool_from_cam.translation() = Eigen::Vector3d(0.05, -0.02, 0.08);

  const fs::path path = fs::temp_directory_path() / ("lt_calib_output_" + std::to_string(::getpid()) + ".yml");
  WriteCalibrationFile(path, MakeCalibrationFile(&cam, &planes, &he));
  const CalibrationFile back = ReadCalibrationFile(path);
  fs::remove(path);

  ASSERT_TRUE(back.camera.has_value());
  EXPECT_EQ(back.camera->width, 640);
  EXPECT_EQ(back.camera->fx, cam.camera.fx);
  EXPECT_EQ(back.camera->cy, cam.camera.cy);
  EXPECT_EQ(back.camera->distortion, DistortionModel::kBrownConrady);
  EXPECT_EQ(back.camera->brown_conrady.k3, cam.camera.brown_conrady.k3);
  // The camera from the file projects as the calibrated one.
  const Camera from_file = back.MakeCamera(CameraParams{}, "calibration.yml");
  const Camera calibrated(cam.camera);
  const Eigen::Vector3d p(0.02, -0.01, 0.19);
  EXPECT_LT((*from_file.Project(p) - *calibrated.Project(p)).norm(), 1e-9);
  ASSERT_EQ(back.laser_planes.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    EXPECT_LT((back.laser_planes[size_t(k)].n - planes[size_t(k)].plane.n).norm(), 1e-12);
    EXPECT_NEAR(back.laser_planes[size_t(k)].d, planes[size_t(k)].plane.d, 1e-12);
  }
  ASSERT_TRUE(back.tool_from_cam.has_value());
  EXPECT_LT((back.tool_from_cam->matrix() - he.tool_from_cam.matrix()).norm(), 1e-12);

  // Parts may be left out.
  const CalibrationFile only_planes = MakeCalibrationFile(nullptr, &planes, nullptr);
  EXPECT_FALSE(only_planes.camera.has_value());
  EXPECT_FALSE(only_planes.tool_from_cam.has_value());
}

TEST(CalibOutput, RefusedResultsAndMissingPlanesAreErrors) {
  CameraCalibrationResult refused;
  refused.reason = "too few views: 2 (at least 3 are needed)";
  try {
    MakeCalibrationFile(&refused, nullptr, nullptr);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("too few views"), std::string::npos) << e.what();
  }
  auto planes = TwoPlanes();
  planes.erase(planes.begin());  // only plane 1
  EXPECT_THROW(MakeCalibrationFile(nullptr, &planes, nullptr), InputError);
  planes = TwoPlanes();
  planes[1].ok = false;
  EXPECT_THROW(MakeCalibrationFile(nullptr, &planes, nullptr), InputError);
  HandEyeResult he;
  EXPECT_THROW(MakeCalibrationFile(nullptr, nullptr, &he), InputError);
}

}  // namespace
}  // namespace lt
