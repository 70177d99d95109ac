// Laser plane calibration on synthetic target views of a known laser (the
// default rig: camera 80 mm above the work, laser 40 mm beside it, tilted
// 26.565 degrees so its sheet crosses the optical axis at about 80 mm).
#include <gtest/gtest.h>

#include "calib_test_util.h"

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "pipeline/calib_laser_plane.h"
#include "sensor/laser.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

LaserProjector RigLaser(int sheets = 1) {
  LaserParams l;
  l.cam_from_projector = Pose::Identity();
  l.cam_from_projector.linear() = Eigen::AngleAxisd(26.565 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  l.cam_from_projector.translation() = Eigen::Vector3d(0, 0.04, 0);
  l.fan_angle_rad = 40 * kDeg;
  if (sheets > 1) l.sheet_angles_rad = EvenSheetAngles(sheets, 5 * kDeg);
  return LaserProjector(l);
}

// cam_from_target: the target's origin at (ox, oy, z), tilted by `tilt` about
// an in-plane axis at angle `axis`.
Pose TargetPose(double ox, double oy, double z, double tilt, double axis) {
  Pose p = Pose::Identity();
  p.linear() = Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)).toRotationMatrix();
  p.translation() = Eigen::Vector3d(ox, oy, z);
  return p;
}

std::vector<Pose> StandardTargets() {
  return {TargetPose(0, 0, 0.080, 0, 0),          TargetPose(0.002, 0.001, 0.070, 20 * kDeg, 0),
          TargetPose(-0.003, 0, 0.090, 25 * kDeg, 90 * kDeg), TargetPose(0, -0.002, 0.075, 15 * kDeg, 200 * kDeg),
          TargetPose(0.001, 0.002, 0.085, 30 * kDeg, 300 * kDeg), TargetPose(0, 0, 0.065, 10 * kDeg, 45 * kDeg),
          TargetPose(0, 0, 0.095, 20 * kDeg, 135 * kDeg)};
}

// Stripe pixels where each sheet meets each target (within 30 mm of the
// target's origin, inside the fan and the image), one sample per ~1 px along
// the line, with Gaussian pixel noise and a fraction of outlier pixels
// anywhere in the image.
std::vector<LaserTargetView> StripeViews(const Camera& cam, const LaserProjector& laser, const std::vector<Pose>& targets,
                                         double noise_px, double outlier_fraction, uint64_t seed = 5) {
  std::vector<LaserTargetView> views;
  for (size_t v = 0; v < targets.size(); ++v) {
    LaserTargetView view;
    view.cam_from_target = targets[v];
    const Plane target = Plane{Eigen::Vector3d::UnitZ(), 0.0}.Transformed(targets[v]);
    int k = 0;
    for (int s = 0; s < laser.sheet_count(); ++s) {
      const Plane sheet = laser.SheetPlane(s);
      const Eigen::Vector3d dir = sheet.n.cross(target.n).normalized();
      Eigen::Matrix3d a;
      a << sheet.n.transpose(), target.n.transpose(), dir.transpose();
      const Eigen::Vector3d x0 = a.inverse() * Eigen::Vector3d(-sheet.d, -target.d, 0);
      for (double t = -0.03; t <= 0.03; t += 4e-5) {
        const Eigen::Vector3d p = x0 + t * dir;
        if ((targets[v].inverse() * p).norm() > 0.03) continue;
        if (laser.SheetIntensity(s, laser.projector_from_cam() * p) <= 0) continue;
        const auto px = cam.Project(p);
        if (!px || !cam.InImage(*px)) continue;
        Rng rng = Rng::For(seed, v, k++, 0, 2);
        Eigen::Vector2d q = *px + noise_px * Eigen::Vector2d(rng.NextGaussian(), rng.NextGaussian());
        if (rng.NextDouble() < outlier_fraction) q = {rng.NextDouble() * 1279, rng.NextDouble() * 1023};
        view.stripe_pixels.push_back(q);
        view.plane_ids.push_back(s);
      }
    }
    views.push_back(view);
  }
  return views;
}

TEST(CalibLaserPlane, StripePointsLieOnTheLaserPlane) {
  const Camera cam = RigCamera();
  const LaserProjector laser = RigLaser();
  int skipped = -1;
  const auto pts = StripePointsOnTarget(cam, StripeViews(cam, laser, StandardTargets(), 0, 0), &skipped);
  EXPECT_EQ(skipped, 0);
  ASSERT_GT(pts.size(), 3000u);
  const Plane truth = laser.SheetPlane(0);
  for (const auto& p : pts) ASSERT_LT(std::abs(truth.SignedDistance(p.p_in_cam)), 1e-9);
}

TEST(CalibLaserPlane, RecoversTheDefaultRigPlaneFromNoisyStripes) {
  const Camera cam = RigCamera();
  const LaserProjector laser = RigLaser();
  int skipped = -1;
  const auto fits = CalibrateLaserPlanes(cam, StripeViews(cam, laser, StandardTargets(), 0.2, 0.05), {}, &skipped);
  EXPECT_EQ(skipped, 0);
  ASSERT_EQ(fits.size(), 1u);
  const LaserPlaneFit& f = fits[0];
  ASSERT_TRUE(f.ok) << f.reason;
  const PlaneError e = ComparePlanes(f.plane, laser.SheetPlane(0));
  EXPECT_LT(e.normal_angle_rad, 0.05 * kDeg);
  EXPECT_LT(e.offset_m, 0.05e-3);
  // The reported uncertainty covers the error (4 standard deviations).
  EXPECT_LT(e.normal_angle_rad, 4 * f.normal_std_rad);
  EXPECT_LT(e.offset_m, 4 * f.offset_std_m);
  // About 5% outliers were rejected (some outliers land near the plane).
  EXPECT_NEAR(double(f.inliers) / f.points, 0.95, 0.01);
  // 0.2 px at ~80 mm is ~9 um across the ray; residuals of that order.
  EXPECT_GT(f.residual_rms_m, 2e-6);
  EXPECT_LT(f.residual_rms_m, 30e-6);
  EXPECT_LT(f.plane.d, 0.0);
}

TEST(CalibLaserPlane, FitsEachSheetOfAMultiLineLaser) {
  const Camera cam = RigCamera();
  const LaserProjector laser = RigLaser(3);
  const auto fits = CalibrateLaserPlanes(cam, StripeViews(cam, laser, StandardTargets(), 0.2, 0.02));
  ASSERT_EQ(fits.size(), 3u);
  for (int s = 0; s < 3; ++s) {
    ASSERT_TRUE(fits[size_t(s)].ok) << fits[size_t(s)].reason;
    EXPECT_EQ(fits[size_t(s)].plane_id, s);
    const PlaneError e = ComparePlanes(fits[size_t(s)].plane, laser.SheetPlane(s));
    EXPECT_LT(e.normal_angle_rad, 0.05 * kDeg) << "sheet " << s;
    EXPECT_LT(e.offset_m, 0.05e-3) << "sheet " << s;
  }
}

TEST(CalibLaserPlane, RefusesTargetViewsInOnePlane) {
  const Camera cam = RigCamera();
  const LaserProjector laser = RigLaser();
  // The target slides and turns within one plane: every stripe lies on the
  // same 3D line. Then nearly so (0.02 degree tilts).
  for (double tilt : {0.0, 0.02 * kDeg}) {
    std::vector<Pose> targets;
    const Pose base = TargetPose(0, 0, 0.08, 15 * kDeg, 30 * kDeg);
    for (int v = 0; v < 6; ++v) {
      Pose in_plane = Pose::Identity();
      in_plane.linear() = (Eigen::AngleAxisd(0.3 * v, Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(tilt * (v % 2 ? 1 : -1), Eigen::Vector3d::UnitX()))
                              .toRotationMatrix();
      in_plane.translation() = Eigen::Vector3d(0.002 * v, -0.001 * v, 0);
      targets.push_back(base * in_plane);
    }
    for (double noise : {0.0, 0.2}) {
      const auto fits = CalibrateLaserPlanes(cam, StripeViews(cam, laser, targets, noise, 0));
      ASSERT_EQ(fits.size(), 1u);
      EXPECT_FALSE(fits[0].ok) << "tilt " << tilt << " noise " << noise;
      EXPECT_NE(fits[0].reason.find("collinear"), std::string::npos) << fits[0].reason;
    }
    // With stray pixels (5%) the points span the common target plane, which
    // RANSAC finds; it is refused as the target plane.
    const auto fits = CalibrateLaserPlanes(cam, StripeViews(cam, laser, targets, 0.2, 0.05));
    ASSERT_EQ(fits.size(), 1u);
    EXPECT_FALSE(fits[0].ok) << "tilt " << tilt;
    EXPECT_NE(fits[0].reason.find("target plane of view"), std::string::npos) << fits[0].reason;
  }
}

// Parallel target planes at different depths still determine the plane: the
// stripes are parallel lines that span it.
TEST(CalibLaserPlane, ParallelTargetsAtDifferentDepthsAreEnough) {
  const Camera cam = RigCamera();
  const LaserProjector laser = RigLaser();
  std::vector<Pose> targets;
  for (int v = 0; v < 5; ++v) targets.push_back(TargetPose(0, 0, 0.07 + 0.005 * v, 0, 0));
  const auto fits = CalibrateLaserPlanes(cam, StripeViews(cam, laser, targets, 0.2, 0));
  ASSERT_TRUE(fits[0].ok) << fits[0].reason;
  const PlaneError e = ComparePlanes(fits[0].plane, laser.SheetPlane(0));
  EXPECT_LT(e.normal_angle_rad, 4 * fits[0].normal_std_rad);
  EXPECT_LT(e.normal_angle_rad, 0.05 * kDeg);
}

// RANSAC with many outliers, seeded: the same seed gives the same fit.
TEST(CalibLaserPlane, RansacRejectsOutliersDeterministically) {
  const Plane truth = Plane::FromPointNormal(Eigen::Vector3d(0, 0.01, 0.08), Eigen::Vector3d(0.1, 0.9, 0.4));
  const Eigen::Vector3d u = truth.n.unitOrthogonal(), w = truth.n.cross(u);
  std::vector<Eigen::Vector3d> pts;
  for (int i = 0; i < 1000; ++i) {
    Rng rng = Rng::For(9, i, 0, 0);
    const Eigen::Vector3d on = -truth.d * truth.n + 0.02 * (rng.NextDouble() - 0.5) * u + 0.02 * (rng.NextDouble() - 0.5) * w;
    if (i % 10 < 3) {  // 30% outliers within ±5 mm of the plane
      pts.push_back(on + 0.01 * (rng.NextDouble() - 0.5) * truth.n);
    } else {
      pts.push_back(on + 10e-6 * rng.NextGaussian() * truth.n);
    }
  }
  LaserPlaneFitOptions o;
  o.inlier_threshold_m = 50e-6;
  const LaserPlaneFit a = FitLaserPlane(pts, o), b = FitLaserPlane(pts, o);
  ASSERT_TRUE(a.ok) << a.reason;
  EXPECT_EQ(a.plane.n, b.plane.n);
  EXPECT_EQ(a.plane.d, b.plane.d);
  EXPECT_EQ(a.ransac_iterations, b.ransac_iterations);
  const PlaneError e = ComparePlanes(a.plane, truth);
  EXPECT_LT(e.normal_angle_rad, 4 * a.normal_std_rad);
  EXPECT_LT(e.offset_m, 4 * a.offset_std_m);
  // Inliers: the 700 good points and the outliers that fall within 50 um (1% of 300).
  EXPECT_NEAR(a.inliers, 703, 8);
  EXPECT_NEAR(a.residual_rms_m, 10e-6, 1.5e-6);

  o.min_inlier_fraction = 0.8;
  const LaserPlaneFit c = FitLaserPlane(pts, o);
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.reason.find("too few inliers"), std::string::npos) << c.reason;
}

TEST(CalibLaserPlane, BadInput) {
  std::vector<Eigen::Vector3d> few(10, Eigen::Vector3d(0, 0, 0.1));
  const LaserPlaneFit f = FitLaserPlane(few);
  EXPECT_FALSE(f.ok);
  EXPECT_NE(f.reason.find("too few points"), std::string::npos) << f.reason;
  std::vector<Eigen::Vector3d> line;
  for (int i = 0; i < 50; ++i) line.emplace_back(0.001 * i, 0.002 * i, 0.1);
  const LaserPlaneFit g = FitLaserPlane(line);
  EXPECT_FALSE(g.ok);
  EXPECT_NE(g.reason.find("collinear"), std::string::npos) << g.reason;
  line[3].x() = NAN;
  EXPECT_FALSE(FitLaserPlane(line).ok);
  LaserPlaneFitOptions o;
  o.inlier_threshold_m = 0;
  EXPECT_THROW(FitLaserPlane(line, o), InputError);
  LaserTargetView v;
  v.cam_from_target = TargetPose(0, 0, 0.08, 0, 0);
  v.stripe_pixels = {{600, 500}, {601, 500}};
  v.plane_ids = {0};
  EXPECT_THROW(StripePointsOnTarget(RigCamera(), {v}), InputError);
  v.plane_ids = {0, -1};
  EXPECT_THROW(StripePointsOnTarget(RigCamera(), {v}), InputError);
  // Stripe points of a single view: refused (one line, and one view).
  const Camera cam = RigCamera();
  const LaserProjector laser = RigLaser();
  const auto one = CalibrateLaserPlanes(cam, StripeViews(cam, laser, {StandardTargets()[1]}, 0.2, 0));
  EXPECT_FALSE(one[0].ok);
}

TEST(CalibLaserPlane, ComparePlanesIgnoresTheNormalsSign) {
  const Plane a = Plane::FromPointNormal(Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(0, 0, 1));
  const Plane b{-a.n, -a.d + 1e-4};
  const PlaneError e = ComparePlanes(b, a);
  EXPECT_EQ(e.normal_angle_rad, 0.0);
  EXPECT_NEAR(e.offset_m, 1e-4, 1e-15);
  const Plane c = Plane::FromPointNormal(Eigen::Vector3d(0, 0, 0.1), Eigen::Vector3d(1e-7, 0, 1));
  EXPECT_NEAR(ComparePlanes(c, a).normal_angle_rad, 1e-7, 1e-15);
}

}  // namespace
}  // namespace lt
