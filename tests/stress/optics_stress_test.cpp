// Numerical stress: extreme optics and radiometry (docs/stress.md): a laser
// sheet almost parallel to the view rays, strong lens distortion near the
// image corners, saturated stripes, zero laser power, and an exposure too short
// for any signal. Each test states the expected behaviour and checks that no
// output holds NaN or infinity.
#include <gtest/gtest.h>

#include "core/error.h"
#include "scene/scene_file.h"
#include "sensor/param_error.h"
#include "stress_scenes.h"

namespace lt {
namespace {

using test::PlaneSetup;

constexpr double kDeg = M_PI / 180.0;
constexpr double kComBoundPx = 0.5;  // as in geometry_stress_test.cpp

// Expected: a sheet whose plane nearly contains the camera centre (baseline
// 0.1 mm at 0.1 m: the rays meet the sheet at 0.06 degrees) still gives a
// stripe and exact truth, but triangulation refuses every point as grazing
// (default minimum angle 5 degrees) instead of returning points whose error is
// 1000 times the centre error; with the minimum set to 0 the points it returns
// lie on the sheet and are finite. A sheet through the camera centre (baseline
// 0) gives no point at all. No NaN anywhere.
TEST(StressOptics, LaserSheetNearlyParallelToViewRays) {
  for (double baseline : {1e-4, 0.0}) {
    SCOPED_TRACE("baseline " + std::to_string(baseline));
    PlaneSetup s;
    s.baseline = baseline;
    s.tilt_rad = 20 * kDeg;
    test::World world = test::PlaneWorld(s);
    test::StressResult r = test::RenderAndScan(world);
    test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
    EXPECT_GE(r.extracted.size(), size_t(s.height) - 2);
    EXPECT_LE(test::WorstCentreErrorPx(r), kComBoundPx);
    EXPECT_EQ(r.stats.triangulated, 0);
    EXPECT_EQ(r.stats.grazing + r.stats.behind, int(r.extracted.size()));

    TriangulationOptions any_angle;
    any_angle.min_ray_angle_deg = 0;
    test::StressResult r0 = test::RenderAndScan(world, ExtractionMethod::kCom, any_angle);
    test::ExpectAllFinite(r0, world.scene.sensor.image_sensor);
    for (const ScanPoint& p : r0.scanned) {
      if (p.p_in_cam) {
        EXPECT_LE(std::abs(r0.planes[0].SignedDistance(*p.p_in_cam)), 1e-9 * p.p_in_cam->norm());
      }
    }
    if (baseline == 0) {
      EXPECT_EQ(r0.stats.triangulated, 0);
    }
  }
}

// Expected: Brown-Conrady barrel distortion k1 at 95% of the strength at which
// the lens folds inside the image (for a purely radial k1 the fold is at
// undistorted radius r with 1 + 3 k1 r^2 = 0, distorted radius 2r/3, so it
// reaches the image corner at k1 = -4 / (27 r_c^2)) is accepted, 105% is
// refused (ParamError on "distortion"). With a stripe 6 px from the left edge
// in the middle row, bowed through the corners' strongly compressed region:
// truth within 1e-6 of the closed form and reprojecting to its pixel within
// 1e-6 px, extracted centres within 0.5 px wherever found (at least half the
// rows), no NaN.
TEST(StressOptics, StrongDistortionNearTheImageCorners) {
  PlaneSetup s;
  s.height = 48;  // 4:3, so that the corners lie far out
  // Long version: 5 times the resolution, the sheet 5 times thinner (stripe sigma still ~1 px).
  if (test::LongStress()) s.width = 320, s.height = 240, s.fx = 750, s.divergence_rad /= 5;
  const double cx = (s.width - 1) / 2.0, cy = (s.height - 1) / 2.0;
  const double r_corner = std::hypot(cx + 0.5, cy + 0.5) / s.fx;
  const double k1_fold = -4.0 / (27.0 * r_corner * r_corner);
  s.distortion = DistortionModel::kBrownConrady;
  s.bc.k1 = 1.05 * k1_fold;
  EXPECT_THROW(
      {
        try {
          test::TestCamera(s.width, s.height, s.fx, s.distortion, s.bc);
        } catch (const ParamError& e) {
          EXPECT_EQ(e.key(), "distortion");
          throw;
        }
      },
      ParamError);
  s.bc.k1 = 0.95 * k1_fold;
  Camera cam = test::TestCamera(s.width, s.height, s.fx, s.distortion, s.bc);
  auto ray = cam.Unproject({6.0, cy});
  ASSERT_TRUE(ray.has_value());
  s.aim_x = s.distance * ray->x() / ray->z();
  s.baseline = s.aim_x + 0.3 * s.distance;
  test::World world = test::PlaneWorld(s);
  test::StressResult r = test::RenderAndScan(world);
  test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
  test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);
  for (const StripeCenter& c : r.frame.centers) {
    auto px = cam.Project(c.p_cam);
    ASSERT_TRUE(px.has_value());
    EXPECT_NEAR(px->x(), c.u, 1e-6);
    EXPECT_NEAR(px->y(), c.v, 1e-6);
  }
  // Barrel distortion pulls the ends of the (straight) stripe towards the
  // centre more than its middle: it bows out towards the image edge.
  EXPECT_GT(r.frame.centers.front().u, r.frame.centers[r.frame.centers.size() / 2].u + 1.0);
  int matched = 0;
  EXPECT_LE(test::WorstCentreErrorPx(r, &matched), kComBoundPx);
  EXPECT_GE(matched, s.height / 2);
  test::ExpectPointsNearSurface(r, s, kComBoundPx);
}

// Expected: 100 times the power needed for a well-exposed stripe saturates
// its core (several pixels at the ADC's full scale on every row): the digital
// numbers stay within [0, full scale], and the centroid of the flat, symmetric
// plateau stays within 0.5 px of the truth. No NaN.
TEST(StressOptics, SaturatedStripes) {
  PlaneSetup s;
  s.tilt_rad = 20 * kDeg;
  s.power_w *= 100;
  test::World world = test::PlaneWorld(s);
  test::StressResult r = test::RenderAndScan(world);
  test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
  const ImageSensor& sensor = world.scene.sensor.image_sensor;
  const double full_scale = std::min(sensor.max_dn(), sensor.params().full_well_e * sensor.SystemGain());
  int saturated_rows = 0;
  for (int y = 0; y < s.height; ++y) {
    int n = 0;
    for (int x = 0; x < s.width; ++x) n += r.frame.raw.At(x, y, 0) >= full_scale - 1;
    saturated_rows += n >= 2;
  }
  EXPECT_GE(saturated_rows, s.height - 2);
  test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);
  int matched = 0;
  EXPECT_LE(test::WorstCentreErrorPx(r, &matched), kComBoundPx);
  EXPECT_GE(matched, s.height - 2);
  test::ExpectPointsNearSurface(r, s, kComBoundPx);
}

// Expected: zero laser power is refused, in code (ParamError "power_mw") and
// in a scene file (InputError at /sensor/lasers/0/power_mw); so are sheet
// powers that are all 0. A power too small to give one photo-electron (1e-20
// W) renders a frame with truth but no stripe: nothing is extracted and no
// output is NaN.
TEST(StressOptics, ZeroLaserPower) {
  PlaneSetup s;
  s.power_w = 0;
  EXPECT_THROW(test::AimedLaser(s), ParamError);
  const std::string scene_text = R"({
    "objects": [{"name": "square", "gltf": "square.gltf"}],
    "sensor": {"camera": {"resolution": [64, 48], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4},
               "lasers": [{"power_mw": POWER, "wavelength_nm": 650, "fan_angle_deg": 40 SHEETS,
                           "cam_from_projector": {"translation_m": [0.03, 0, 0]}}]}})";
  auto scene_with = [&](const std::string& power, const std::string& sheets) {
    std::string t = scene_text;
    t.replace(t.find("POWER"), 5, power);
    t.replace(t.find("SHEETS"), 6, sheets);
    return ParseSceneText(t, "stress.json", std::string(LT_SOURCE_DIR) + "/tests/data/gltf");
  };
  EXPECT_NO_THROW(scene_with("5", ""));
  try {
    scene_with("0", "");
    ADD_FAILURE() << "zero power accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/sensor/lasers/0/power_mw"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scene_with("5", R"(, "sheet_count": 2, "sheet_spacing_deg": 5, "sheet_power": [0, 0])"), InputError);

  s.power_w = 1e-20;
  test::World world = test::PlaneWorld(s);
  test::StressResult r = test::RenderAndScan(world);
  test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
  EXPECT_TRUE(r.extracted.empty());
  EXPECT_TRUE(r.scanned.empty());
  test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);
}

// Expected: an exposure of 1 ps collects no signal: the image holds only
// dark noise around the black level (no pixel above black level + 6 sigma of
// the dark noise in DN), extraction finds no stripe point, the truth centres
// (which do not depend on exposure) still satisfy the closed form, no NaN. A
// zero exposure is refused (ParamError).
TEST(StressOptics, ExposureGivingZeroSignal) {
  PlaneSetup s;
  s.exposure_s = 1e-12;
  test::World world = test::PlaneWorld(s);
  world.scene.sensor.image_sensor = ImageSensor([] {
    ImageSensorParams p;
    p.black_level_dn = 64;
    return p;
  }());
  test::StressResult r = test::RenderAndScan(world);
  test::ExpectAllFinite(r, world.scene.sensor.image_sensor);
  const ImageSensorParams& sp = world.scene.sensor.image_sensor.params();
  const double limit = sp.black_level_dn + 6 * sp.dark_noise_e * sp.system_gain_dn_per_e + 1;
  for (uint16_t dn : r.frame.raw.pixels) ASSERT_LE(double(dn), limit);
  EXPECT_TRUE(r.extracted.empty());
  test::ExpectTruthOnPlane(r, world, s, size_t(s.height) - 2);

  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"dim", 0.0, true, false, false}};
  EXPECT_THROW(ShutterSchedule{sh}, ParamError);
}

}  // namespace
}  // namespace lt
