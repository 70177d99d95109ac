// Triangulation by ray-plane intersection, checked against closed forms: a
// plane at known depth seen by a pinhole camera, rays of distorted cameras
// (the point must lie on the plane and project back to its pixel), grazing and
// parallel rays, planes behind the camera, and a fuzz test that nothing
// returned is NaN or infinite.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "pipeline/triangulation.h"
#include "sensor/laser.h"

namespace lt {
namespace {

constexpr double kDeg = M_PI / 180.0;

CameraParams PinholeParams() {
  CameraParams p;
  p.width = 160;
  p.height = 120;
  p.fx = 460;
  p.fy = 455;
  p.cx = 81.3;
  p.cy = 58.9;
  return p;
}

CameraParams BrownConradyParams() {
  CameraParams p;
  p.width = 160;
  p.height = 120;
  p.fx = p.fy = 462.97;
  p.cx = 79.5;
  p.cy = 59.5;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.2, 0.05, 0.001, -0.0005, 0.01};
  return p;
}

CameraParams FisheyeParams() {
  CameraParams p;
  p.width = 320;
  p.height = 240;
  p.fx = p.fy = 200;  // corners at about 57 degrees from the axis
  p.cx = 159.5;
  p.cy = 119.5;
  p.distortion = DistortionModel::kFisheye;
  p.fisheye = {0.05, -0.01, 0.002, 0};
  return p;
}

// Each camera is built once: the distortion's domain analysis is costly in
// sanitizer builds.
const Camera& Pinhole() {
  static const Camera camera(PinholeParams());
  return camera;
}
const Camera& BrownConrady() {
  static const Camera camera(BrownConradyParams());
  return camera;
}
const Camera& Fisheye() {
  static const Camera camera(FisheyeParams());
  return camera;
}

TEST(Triangulation, PlaneAtKnownDepthPinhole) {
  const double z0 = 0.0937;
  Triangulator t(Pinhole(), {Plane{{0, 0, 1}, -z0}}, {});
  for (double v = -0.5; v <= 119.5; v += 7.25) {
    for (double u = -0.5; u <= 159.5; u += 9.5) {
      auto p = t.Triangulate({u, v}, 0);
      ASSERT_TRUE(p) << u << "," << v;
      // Closed form: X = (u - cx) / fx * Z, Y = (v - cy) / fy * Z.
      EXPECT_NEAR(p->z(), z0, 1e-15);
      EXPECT_NEAR(p->x(), (u - 81.3) / 460 * z0, 1e-12 * z0);
      EXPECT_NEAR(p->y(), (v - 58.9) / 455 * z0, 1e-12 * z0);
    }
  }
}

// With distortion the exact answer is the point of the plane that projects to
// the pixel: it lies on the plane and Project() (the closed-form forward
// model) maps it back to the pixel.
void CheckDistortedCamera(const Camera& cam, const Plane& plane) {
  Triangulator t(cam, {plane}, {});
  int checked = 0;
  for (double v = -0.5; v <= cam.height() - 0.5; v += cam.height() / 17.0) {
    for (double u = -0.5; u <= cam.width() - 0.5; u += cam.width() / 23.0) {
      TriangulationFailure why = TriangulationFailure::kNone;
      auto p = t.Triangulate({u, v}, 0, &why);
      ASSERT_TRUE(p) << u << "," << v << ": " << TriangulationFailureName(why);
      EXPECT_NEAR(plane.SignedDistance(*p), 0.0, 1e-15);
      auto back = cam.Project(*p);
      ASSERT_TRUE(back);
      // Unproject converges to 1e-9 px (sensor/distortion.h).
      EXPECT_NEAR(back->x(), u, 2e-9) << u << "," << v;
      EXPECT_NEAR(back->y(), v, 2e-9) << u << "," << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 300);
}

TEST(Triangulation, DistortedRaysLandOnThePlaneAndProjectBack) {
  // A tilted plane about 80 mm in front (the demo's laser sheet geometry).
  const Plane sheet = Plane::FromPointNormal({0, 0, 0.08}, {0, 0.894, 0.447});
  CheckDistortedCamera(BrownConrady(), sheet);
  CheckDistortedCamera(Fisheye(), Plane::FromPointNormal({0, 0, 0.05}, {0.2, -0.3, 1}));
}

TEST(Triangulation, DistortionMatters) {
  // The same pixel through the distorted and the undistorted camera gives
  // different points: Unproject is really used. Near the corner, barrel
  // distortion (k1 < 0) pulls the image inwards, so the ray points further out.
  CameraParams p = BrownConrady().params();
  p.distortion = DistortionModel::kNone;
  const Plane plane{{0, 0, 1}, -0.1};
  auto d = Triangulator(BrownConrady(), {plane}).Triangulate({0, 0}, 0);
  auto n = Triangulator(Camera(p), {plane}).Triangulate({0, 0}, 0);
  ASSERT_TRUE(d && n);
  EXPECT_GT(d->head<2>().norm(), n->head<2>().norm() * 1.005);
}

TEST(Triangulation, GrazingRaysAreRejected) {
  // Plane y = 0.01 (n = (0, 1, 0)): the ray through pixel (cx, v) makes the
  // angle atan(|v - cy| / fy) with it.
  const Camera cam = Pinhole();
  const double min_deg = 5;
  TriangulationOptions o;
  o.min_ray_angle_deg = min_deg;
  Triangulator t(cam, {Plane{{0, 1, 0}, -0.01}}, o);
  int accepted = 0, rejected = 0;
  for (int v = 0; v < cam.height(); ++v) {
    const double angle = std::atan(std::abs(v - cam.cy()) / cam.fy()) / kDeg;
    TriangulationFailure why;
    auto p = t.Triangulate({cam.cx(), double(v)}, 0, &why);
    if (v > cam.cy() && angle >= min_deg) {
      ASSERT_TRUE(p) << v;
      EXPECT_NEAR(p->y(), 0.01, 1e-15);
      ++accepted;
    } else if (angle < min_deg) {
      EXPECT_FALSE(p) << v;
      EXPECT_EQ(why, TriangulationFailure::kGrazing) << v;
      ++rejected;
    } else {
      // v < cy: the ray goes up, the plane lies below: behind the camera.
      EXPECT_FALSE(p) << v;
      EXPECT_EQ(why, TriangulationFailure::kBehind) << v;
    }
  }
  // 5 degrees is 39.8 px from cy at fy = 455: rows 0..19 and 99..119 qualify.
  EXPECT_EQ(accepted, 21);
  EXPECT_EQ(rejected, 79);
}

TEST(Triangulation, ParallelRayGivesNoPoint) {
  const Plane plane{{0, 1, 0}, -0.01};
  TriangulationFailure why;
  // Exactly parallel: even with no minimum angle there is no point.
  EXPECT_FALSE(IntersectRayWithPlane({0, 0, 0}, {0, 0, 1}, plane, 0.0, &why));
  EXPECT_EQ(why, TriangulationFailure::kGrazing);
  EXPECT_FALSE(IntersectRayWithPlane({0, 0, 0}, Eigen::Vector3d(1, 0, 1).normalized(), plane, 0.0, &why));
  // Almost parallel: a finite but huge point with no minimum angle ...
  const Eigen::Vector3d dir = Eigen::Vector3d(0, 1e-300, 1).normalized();
  auto far = IntersectRayWithPlane({0, 0, 0}, dir, plane, 0.0, &why);
  if (far) {
    EXPECT_TRUE(far->allFinite());
  }
  // ... and none with the default 5 degrees.
  EXPECT_FALSE(IntersectRayWithPlane({0, 0, 0}, dir, plane, 5 * kDeg, &why));
  EXPECT_EQ(why, TriangulationFailure::kGrazing);
}

TEST(Triangulation, PlaneBehindOrThroughTheCamera) {
  TriangulationFailure why;
  // z = -0.1: behind.
  EXPECT_FALSE(IntersectRayWithPlane({0, 0, 0}, {0, 0, 1}, Plane{{0, 0, 1}, 0.1}, 0.0, &why));
  EXPECT_EQ(why, TriangulationFailure::kBehind);
  // Through the camera centre: every ray meets it at t = 0, which is no measurement.
  EXPECT_FALSE(IntersectRayWithPlane({0, 0, 0}, {0, 0, 1}, Plane{{0, 0, 1}, 0.0}, 0.0, &why));
  EXPECT_EQ(why, TriangulationFailure::kBehind);
}

TEST(Triangulation, UnknownPlaneAndPixelWithoutRay) {
  Triangulator t(Pinhole(), {Plane{{0, 0, 1}, -0.1}});
  TriangulationFailure why;
  EXPECT_FALSE(t.Triangulate({10, 10}, -1, &why));
  EXPECT_EQ(why, TriangulationFailure::kNoPlane);
  EXPECT_FALSE(t.Triangulate({10, 10}, 1, &why));
  EXPECT_EQ(why, TriangulationFailure::kNoPlane);
  EXPECT_FALSE(t.Triangulate({std::nan(""), 10}, 0, &why));
  EXPECT_EQ(why, TriangulationFailure::kNoRay);
  EXPECT_FALSE(t.Triangulate({INFINITY, 10}, 0, &why));
  EXPECT_EQ(why, TriangulationFailure::kNoRay);
}

TEST(Triangulation, NeverNaNOrInfinite) {
  // Random pixels (far outside the image too), random planes (many nearly
  // through the camera or nearly parallel to the rays), every minimum angle:
  // whatever comes back is finite and on the plane.
  const Camera* cams[] = {&Pinhole(), &BrownConrady(), &Fisheye()};
  int points = 0;
  for (int i = 0; i < 20000; ++i) {
    Rng rng = Rng::For(11, 0, uint64_t(i), 0);
    const Camera& cam = *cams[i % 3];
    Eigen::Vector3d n(rng.NextGaussian(), rng.NextGaussian(), rng.NextGaussian());
    if (i % 4 == 0) n.z() *= 1e-12;  // planes containing the optical axis direction
    n.normalize();
    const double d = (i % 5 == 0) ? 1e-300 * rng.NextGaussian() : 0.2 * rng.NextGaussian();
    TriangulationOptions o;
    o.min_ray_angle_deg = (i % 2) ? 0.0 : 89.0 * rng.NextDouble();
    Triangulator t(cam, {Plane{n, d}}, o);
    const double scale = (i % 7 == 0) ? 1e6 : 2.0;
    Eigen::Vector2d px(cam.width() * (scale * rng.NextDouble() - 0.5 * (scale - 1)),
                       cam.height() * (scale * rng.NextDouble() - 0.5 * (scale - 1)));
    auto p = t.Triangulate(px, 0);
    if (!p) continue;
    ++points;
    ASSERT_TRUE(p->allFinite()) << i;
    EXPECT_LE(std::abs(Plane{n, d}.SignedDistance(*p)), 1e-12 * std::max(1.0, p->norm())) << i;
  }
  EXPECT_GT(points, 2000);
}

TEST(Triangulation, OptionsAndPlanesAreChecked) {
  TriangulationOptions o;
  o.min_ray_angle_deg = 90;
  EXPECT_THROW(o.Check(), InputError);
  o.min_ray_angle_deg = -1;
  EXPECT_THROW(o.Check(), InputError);
  o.min_ray_angle_deg = std::nan("");
  EXPECT_THROW(o.Check(), InputError);
  try {
    Triangulator t(Pinhole(), {Plane{{0, 0, 1}, -0.1}, Plane{{0, 0, 2}, -0.1}});
    FAIL() << "a non-unit normal was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), "laser plane 1");
  }
  EXPECT_THROW(Triangulator(Pinhole(), {Plane{{0, 0, 1}, INFINITY}}), InputError);
}

TEST(Triangulation, FramePointsInCameraAndWorld) {
  const double z0 = 0.1;
  Triangulator t(Pinhole(), {Plane{{0, 0, 1}, -z0}});
  Pose world_from_cam = Pose::Identity();
  world_from_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  world_from_cam.translation() = Eigen::Vector3d(0.5, -0.2, 1.0);
  std::vector<StripePoint> pts = {{10, 20, 4, 100, 0}, {11, 20, 4, 100, -1}, {std::nan(""), 3, 4, 100, 0}};
  TriangulationStats stats;
  auto out = TriangulatePoints(t, pts, world_from_cam, &stats);
  ASSERT_EQ(out.size(), 3u);
  ASSERT_TRUE(out[0].p_in_cam && out[0].p_in_world);
  EXPECT_TRUE(out[0].p_in_world->isApprox(world_from_cam * *out[0].p_in_cam, 1e-15));
  EXPECT_NEAR(out[0].p_in_cam->z(), z0, 1e-15);
  EXPECT_FALSE(out[1].p_in_cam || out[1].p_in_world);
  EXPECT_FALSE(out[2].p_in_cam || out[2].p_in_world);
  EXPECT_EQ(stats.points, 3);
  EXPECT_EQ(stats.triangulated, 1);
  EXPECT_EQ(stats.no_plane, 1);
  EXPECT_EQ(stats.no_ray, 1);
  // Without a pose: camera frame only.
  auto cam_only = TriangulatePoints(t, pts, std::nullopt);
  EXPECT_TRUE(cam_only[0].p_in_cam);
  EXPECT_FALSE(cam_only[0].p_in_world);
}

// The v where sheet `plane` crosses the image's centre column when it lights
// the surface z = depth (pinhole: v = cy + fy y / z on x = 0).
double SheetRowAtCentre(const Camera& cam, const Plane& sheet, double depth) {
  const double y = -(sheet.n.z() * depth + sheet.d) / sheet.n.y();
  return cam.cy() + cam.fy() * y / depth;
}

TEST(Triangulation, PlanesInImageOrderFollowTheStripes) {
  // A 5-sheet diffractive projector 40 mm below the camera (as in the demo),
  // tilted 26.6 degrees: horizontal stripes, searched along columns. Sheet k
  // tilts toward +y with its angle, and the projector sits at +y, so the
  // sheet numbers run against the image order (top to bottom) or with it
  // depending on the tilt: check against where each stripe is seen.
  for (double roll_deg : {26.565, -26.565}) {
    LaserParams lp;
    lp.sheet_angles_rad = EvenSheetAngles(5, 3 * kDeg);
    lp.sheet_power.assign(5, 1.0);
    lp.cam_from_projector = Pose::Identity();
    lp.cam_from_projector.translation() = Eigen::Vector3d(0, roll_deg > 0 ? 0.04 : -0.04, 0);
    lp.cam_from_projector.linear() = Eigen::AngleAxisd(roll_deg * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
    LaserProjector laser(lp);
    std::vector<Plane> planes;
    for (int k = 0; k < 5; ++k) planes.push_back(laser.SheetPlane(k));
    EXPECT_EQ(StripeAxis(planes), SearchAxis::kCols);
    std::vector<int> order = PlanesInImageOrder(planes, SearchAxis::kCols);
    ASSERT_EQ(order.size(), 5u);
    const Camera cam = Pinhole();
    for (double depth : {0.06, 0.08, 0.12}) {
      for (size_t i = 1; i < order.size(); ++i) {
        EXPECT_LT(SheetRowAtCentre(cam, planes[size_t(order[i - 1])], depth),
                  SheetRowAtCentre(cam, planes[size_t(order[i])], depth))
            << roll_deg << " " << depth << " " << i;
      }
    }
  }
  // Vertical stripes (projector beside the camera, tilted about y): rows, left to right.
  std::vector<Plane> vertical;
  for (double x : {0.01, -0.02, 0.0}) vertical.push_back(Plane::FromPointNormal({x, 0, 0.08}, {1, 0, 0.2}));
  EXPECT_EQ(StripeAxis(vertical), SearchAxis::kRows);
  EXPECT_EQ(PlanesInImageOrder(vertical, SearchAxis::kRows), (std::vector<int>{1, 2, 0}));
  EXPECT_THROW(StripeAxis({}), InputError);
}

}  // namespace
}  // namespace lt
