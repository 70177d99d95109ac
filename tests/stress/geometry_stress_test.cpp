// Numerical stress: extreme geometry (docs/stress.md). Each test states the
// expected behaviour (an error bound against a closed form, or a clean
// rejection) and checks that no output holds NaN or infinity.
#include <gtest/gtest.h>

#include "core/random.h"
#include "stress_scenes.h"

namespace lt {
namespace {

using test::PlaneSetup;

constexpr double kDeg = M_PI / 180.0;

// Centre-of-mass error bound on a clean stripe: 0.5 px. The stripe profile is
// a pixel-integrated Gaussian (sigma about 1 px) rendered with 4 samples per
// pixel; the centroid of a symmetric profile is exact, and shot noise,
// sampling noise and the profile's asymmetry on a tilted surface move it by
// well under half a pixel (docs/extraction.md measures < 0.05 px on clean
// stripes). Grazing cases get their own bounds below.
constexpr double kComBoundPx = 0.5;

// Expected: at view angles up to 89.5 degrees (the surface seen almost edge-on)
// the ground-truth centres still satisfy the closed form to 1e-6 of the range
// (root finding to 1e-6 px). Up to 75 degrees the stripe is found on at least
// half the rows within 0.5 px. Beyond, the stripe collapses into about one
// pixel per row; a row whose stripe is narrower than the extractor's minimum
// width counts only where its light continues on the neighbouring rows, else
// it is dropped (not guessed), and those found are within 1 px of the truth
// (the centroid can only err within the pixel the light falls in).
// No output is NaN or infinite.
TEST(StressGeometry, GrazingViewAngles) {
  std::vector<double> angles = {0, 45, 75, 85, 89, 89.5};
  if (test::LongStress()) angles = {0, 15, 30, 45, 60, 70, 75, 80, 83, 85, 87, 88, 89, 89.3, 89.5};
  for (double view_deg : angles) {
    SCOPED_TRACE("view angle " + std::to_string(view_deg));
    PlaneSetup s;
    s.tilt_rad = -view_deg * kDeg;  // negative tilt turns the surface away from the laser
    test::World world = test::PlaneWorld(s);
    test::StressResult r = test::RenderAndScan(world);
    test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
    test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);
    int matched = 0;
    double worst = test::WorstCentreErrorPx(r, &matched);
    EXPECT_GE(matched, view_deg <= 75 ? s.height / 2 : 0);
    EXPECT_LE(worst, view_deg > 75 ? 1.0 : kComBoundPx);
    test::ExpectPointsNearSurface(r, s, view_deg > 75 ? 1.0 : kComBoundPx);
  }
}

// Expected: with the laser sheet meeting the surface at up to 89.5 degrees
// from its normal (the stripe smeared far across the surface and dim), the
// truth still satisfies the closed form. The light on the surface is then a
// skewed profile whose centroid drifts away from the sheet's plane (by more
// than a pixel at 85 degrees): every extracted centre must lie within 0.5 px
// of the closed-form centroid of that profile (PredictedCentroidPx), and up to
// 75 degrees, where the skew is below 0.1 px, within 0.5 px of the truth. Rows
// whose stripe is too dim or too wide give no point (dropped, not guessed).
// No output is NaN or infinite.
TEST(StressGeometry, GrazingLaserAngles) {
  std::vector<double> angles = {30, 75, 85, 89, 89.5};
  if (test::LongStress()) angles = {20, 30, 45, 60, 70, 75, 80, 83, 85, 87, 88, 89, 89.3, 89.5};
  for (double laser_deg : angles) {
    SCOPED_TRACE("laser angle " + std::to_string(laser_deg));
    PlaneSetup s;
    const double theta = std::atan2(s.baseline, s.distance);  // the laser's angle from the optical axis
    s.tilt_rad = laser_deg * kDeg - theta;                    // incidence = tilt + theta
    test::World world = test::PlaneWorld(s);
    test::StressResult r = test::RenderAndScan(world);
    test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
    test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);
    for (const StripePoint& p : r.extracted) {
      auto predicted = test::PredictedCentroidPx(world, s, int(p.v));
      ASSERT_TRUE(predicted.has_value());
      EXPECT_NEAR(p.u, *predicted, kComBoundPx) << "row " << p.v;
    }
    if (laser_deg <= 75) {
      EXPECT_LE(test::WorstCentreErrorPx(r), kComBoundPx);
      test::ExpectPointsNearSurface(r, s, kComBoundPx);
    }
  }
}

// Expected: the same scanner geometry scaled from 10 mm to 10 m (baseline 0.3
// D, surface tilted 20 degrees, power scaled with D^2 so that the image stays
// the same: the lit area grows as D^2) gives the same relative accuracy at
// every scale: truth to 1e-6 of the range, centres within 0.5 px, points within
// the 0.5 px bound.
TEST(StressGeometry, WorkingDistancesFrom10mmTo10m) {
  std::vector<double> distances = {0.01, 0.1, 1, 10};
  if (test::LongStress()) distances = {0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10};
  for (double D : distances) {
    SCOPED_TRACE("distance " + std::to_string(D));
    PlaneSetup s;
    s.distance = D;
    s.baseline = 0.3 * D;
    s.tilt_rad = 20 * kDeg;
    s.power_w = 5e-3 * (D / 0.1) * (D / 0.1);  // the stripe's area on the surface grows as D^2
    test::World world = test::PlaneWorld(s);
    test::StressResult r = test::RenderAndScan(world);
    test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
    test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);
    int matched = 0;
    EXPECT_LE(test::WorstCentreErrorPx(r, &matched), kComBoundPx);
    EXPECT_GE(matched, s.height - 2);
    test::ExpectPointsNearSurface(r, s, kComBoundPx);
  }
}

// Expected: a scanner and surface 1 km from the world origin, with a second
// object at the origin so that the scene's bounds span the whole kilometre
// (Embree then works in float 500 m from its frame's origin, where one ulp is
// 30 um), give the same stripe as at the origin: truth to 1e-6 of the range,
// every truth centre within 1e-4 px of the centre rendered at the origin,
// world points 1 km away, no NaN.
TEST(StressGeometry, SceneOneKilometreFromTheOrigin) {
  PlaneSetup near;
  near.tilt_rad = 25 * kDeg;
  test::World at_origin = test::PlaneWorld(near);
  test::StressResult r0 = test::RenderAndScan(at_origin);

  PlaneSetup far = near;
  far.world_from_cam = Pose::Identity();
  far.world_from_cam.translation() = Eigen::Vector3d(800, -500, 300);  // 1 km
  far.world_from_cam.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  test::World world = test::PlaneWorld(far);  // the surface, placed by a double transform
  world.Add(test::Box({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01}));  // at the origin, out of view
  world.Build();
  test::StressResult r = test::RenderAndScan(world);
  test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
  test::ExpectTruthOnPlane(r, world, far, size_t(far.height) - 2);
  ASSERT_EQ(r.frame.centers.size(), r0.frame.centers.size());
  for (size_t i = 0; i < r.frame.centers.size(); ++i) {
    EXPECT_NEAR(r.frame.centers[i].u, r0.frame.centers[i].u, 1e-4);
    EXPECT_EQ(r.frame.centers[i].v, r0.frame.centers[i].v);
    EXPECT_NEAR((r.frame.centers[i].p_world - far.world_from_cam.translation()).norm(),
                r0.frame.centers[i].p_world.norm(), 1e-6);
  }
  EXPECT_LE(test::WorstCentreErrorPx(r), kComBoundPx);
  test::ExpectPointsNearSurface(r, far, kComBoundPx);
  int with_world = 0;
  for (const ScanPoint& p : r.scanned) {
    if (p.p_in_world) {
      EXPECT_NEAR((*p.p_in_world - far.world_from_cam.translation()).norm(), p.p_in_cam->norm(), 1e-9);
      ++with_world;
    }
  }
  EXPECT_GE(with_world, far.height - 2);
}

// A surface tiled with slivers `width` wide (full height), over |x| <= half.
Mesh Slivers(double z, double half, double width, double height) {
  Mesh m;
  m.name = "slivers";
  const int n = int(std::lround(2 * half / width));
  for (int i = 0; i < n; ++i) {
    // Neighbouring slivers share their edge's coordinates exactly.
    float x0 = float(-half + i * width), x1 = float(-half + (i + 1) * width);
    uint32_t base = uint32_t(m.positions.size());
    for (auto [x, y] : {std::pair{x0, float(-height)}, {x1, float(-height)}, {x1, float(height)}, {x0, float(height)}}) {
      m.positions.push_back(Eigen::Vector3f(x, y, float(z)));
      m.normals.push_back(Eigen::Vector3f(0, 0, -1));
    }
    // Facing -z (the camera): wind (0, 3, 2), (0, 2, 1).
    for (uint32_t k : {0u, 3u, 2u, 0u, 2u, 1u}) m.indices.push_back(base + k);
    m.triangle_material.push_back(0);
    m.triangle_material.push_back(0);
  }
  return m;
}

// Expected: a surface built of 0.5 um wide triangles where the stripe falls
// (9600 slivers over the 2.4 mm around it, ordinary rectangles beyond) renders
// like the plain surface: every pixel sees it (no ray slips through the
// cracks between slivers), truth within 1e-6 of the closed form, centres
// within 0.5 px, no NaN.
TEST(StressGeometry, SubMicrometreTriangles) {
  PlaneSetup s;  // facing the camera at 0.1 m, stripe down the middle column
  // Slivers over |x| <= 1.2 mm: the boundary with the neighbouring rectangles
  // (separate meshes, which Embree does not join watertight) lies between
  // pixel centres (x = -1.0, -0.33, 0.33, 1.0 mm at 0.1 m).
  const double half = 1.2e-3, width = test::LongStress() ? 0.1e-6 : 0.5e-6;
  test::World world;
  world.Add(Slivers(s.distance, half, width, 0.02));
  world.Add(test::Rectangle({-0.1 - half, 0, s.distance}, Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), 0.1,
                            0.02));
  world.Add(test::Rectangle({0.1 + half, 0, s.distance}, Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(), 0.1,
                            0.02));
  world.Build();
  test::ConfigureRig(s, &world);
  test::StressResult r = test::RenderAndScan(world);
  test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) ASSERT_NEAR(r.frame.gt.depth.At(x, y, 0), s.distance, 1e-6) << x << "," << y;
  test::ExpectTruthOnPlane(r, world, s, size_t(s.height));
  int matched = 0;
  EXPECT_LE(test::WorstCentreErrorPx(r, &matched), kComBoundPx);
  EXPECT_EQ(matched, s.height);
  test::ExpectPointsNearSurface(r, s, kComBoundPx);
}

// Expected: rays leaving a point of a huge triangle (a 400 m x 40 m
// rectangle, vertices 200 m from the points, where Embree's float arithmetic
// errs by about 1e-5 m) from 1 um above it never find that triangle again
// (EmbreeScene skips hits whose exact intersection lies behind the ray's
// origin): none of 2000 shadow rays towards points 0.03-0.3 m above is
// occluded, and none of 2000 rays leaving it finds a hit.
TEST(StressGeometry, LargeTrianglesDoNotShadowThemselves) {
  test::World world;
  Eigen::Affine3d at = Eigen::Affine3d::Identity();
  at.translation() = Eigen::Vector3d(0.3, -0.2, 1.0);
  const Eigen::Vector3d a = Eigen::Vector3d(1, 0.2, 0.1).normalized();
  const Eigen::Vector3d b = a.cross(Eigen::Vector3d(0.1, 0.3, 1)).normalized();
  world.Add(test::Rectangle(Eigen::Vector3d::Zero(), a, b, 200, 20), at);
  world.Build();
  const Eigen::Vector3d n = a.cross(b).normalized();
  Rng rng = Rng::For(7, 0, 0, 0, 0);
  int occluded = 0, rehit = 0;
  for (int i = 0; i < 2000; ++i) {
    Eigen::Vector3d p = at * ((rng.NextDouble() - 0.5) * 0.2 * a + (rng.NextDouble() - 0.5) * 0.2 * b);
    Eigen::Vector3d target = p + (0.03 + 0.27 * rng.NextDouble()) * (n + (rng.NextDouble() - 0.5) * a).normalized();
    Ray shadow;
    shadow.origin = p + 1e-6 * n;
    shadow.direction = target - shadow.origin;
    shadow.t_max = 1.0 - 1e-9;
    occluded += world.embree->Occluded(shadow);
    Ray away = shadow;
    away.t_max = INFINITY;
    rehit += world.embree->Intersect(away).has_value();
  }
  EXPECT_EQ(occluded, 0);
  EXPECT_EQ(rehit, 0);
}

}  // namespace
}  // namespace lt
