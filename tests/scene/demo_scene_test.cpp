// The demo scene is designed as a scanner would be set up: the laser sheet
// crosses the slots of the test part under the camera, the lit slot bottoms are
// seen by the camera, and the part is in focus. Checked by casting the laser's
// rays into the scene and looking at the hits from the camera.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "scene/embree_scene.h"
#include "scene/scene_file.h"

namespace lt {
namespace {

struct Demo {
  SceneFile scene = LoadSceneFile(std::filesystem::path(LT_SOURCE_DIR) / "scenes/demo/scene.json");
  EmbreeScene embree{std::make_shared<const SceneGeometry>(LoadSceneGeometry(scene))};
  Pose world_from_cam = WorldFromCamAt(scene.motion, 0.0);
};

// Part design (tools/make_demo_scene.cpp): top at z = 3 mm, slot bottoms 1 mm lower.
constexpr double kTop = 3e-3, kSlotBottom = 2e-3;

TEST(DemoScene, LaserSheetCrossesTheSlotsUnderTheCamera) {
  Demo d;
  ASSERT_EQ(d.scene.sensor.lasers.size(), 1u);
  const LaserProjector& laser = d.scene.sensor.lasers[0];
  const Camera& cam = d.scene.sensor.camera;
  const Pose world_from_projector = d.world_from_cam * laser.cam_from_projector();
  const Eigen::Vector3d origin = world_from_projector.translation();
  const Eigen::Vector3d cam_origin = d.world_from_cam.translation();
  const double half_fan = 0.5 * laser.params().fan_angle_rad;

  // Walk along the sheet's fan in small angular steps (about 5 um apart on the
  // part) and record where the light lands and whether the camera sees it there.
  int slots_crossed = 0;            // stretches where the light goes down into a slot
  std::vector<double> seen_bottoms;  // x of each stretch of lit slot bottom the camera sees
  bool in_slot = false, in_seen = false;
  double top_y_at_centre = NAN;
  const int steps = 12000;
  for (int k = 0; k <= steps; ++k) {
    const double phi = -half_fan + 2 * half_fan * k / steps;
    Eigen::Vector3d dir = world_from_projector.linear() * Eigen::Vector3d(std::sin(phi), 0, std::cos(phi));
    auto hit = d.embree.Intersect({origin, dir});
    ASSERT_TRUE(hit);  // the bed catches everything else
    const Eigen::Vector3d& p = hit->position;
    const bool slot = p.z() > 1e-6 && p.z() < kTop - 1e-6 && std::abs(p.y()) < 10e-3;  // a wall or a bottom
    bool seen_bottom = false;
    if (std::abs(p.z() - kSlotBottom) < 1e-6) {
      auto seen = d.embree.Intersect({cam_origin, p - cam_origin});
      auto pixel = cam.Project(d.world_from_cam.inverse() * p);
      seen_bottom = seen && (seen->position - p).norm() < 1e-6 && pixel && cam.InImage(*pixel);
    }
    if (std::abs(p.x()) < 1e-4 && std::abs(p.z() - kTop) < 1e-6) top_y_at_centre = p.y();
    if (slot && !in_slot) ++slots_crossed;
    if (seen_bottom && !in_seen) seen_bottoms.push_back(p.x());
    in_slot = slot;
    in_seen = seen_bottom;
  }
  // The sheet meets the top of the part right under the camera (within 0.5 mm)
  // and crosses all 16 slots.
  EXPECT_LT(std::abs(top_y_at_centre), 0.5e-3);
  EXPECT_EQ(slots_crossed, 16);
  // The camera sees the lit bottom of every slot but the narrowest: the 0.2 mm
  // slot lies 21 mm off-axis, where the laser and view rays lean by about 13 deg
  // the same way, so its walls hide 1 mm x tan 13 deg = 0.23 mm of its bottom:
  // more than its width. (What a slot test part is for: finding that limit.)
  ASSERT_EQ(seen_bottoms.size(), 15u);
  EXPECT_GT(seen_bottoms.front(), -20.9e-3);  // the 0.2 mm slot spans x = -21.1 .. -20.9 mm
  EXPECT_LT(seen_bottoms.front(), -18.8e-3);  // the 0.3 mm slot (x = -19.1 .. -18.8 mm) is seen
}

TEST(DemoScene, PartIsInFocusAndFillsTheImage) {
  Demo d;
  const Camera& cam = d.scene.sensor.camera;
  const double camera_height = d.world_from_cam.translation().z();
  // Blur circle below one pixel on the top surface and in the slots.
  EXPECT_LT(cam.CircleOfConfusionPx(camera_height - kTop), 1.0);
  EXPECT_LT(cam.CircleOfConfusionPx(camera_height - kSlotBottom), 1.0);
  // The camera looks straight down, and the part's 50.2 mm length fits in the
  // image width: both ends of the part's top project inside the image.
  EXPECT_TRUE(d.world_from_cam.linear().col(2).isApprox(Eigen::Vector3d(0, 0, -1), 1e-12));
  for (double x : {-25.0e-3, 25.0e-3}) {
    auto pixel = cam.Project(d.world_from_cam.inverse() * Eigen::Vector3d(x, 0, kTop));
    ASSERT_TRUE(pixel);
    EXPECT_TRUE(cam.InImage(*pixel)) << x;
  }
  // Scanner figures: a 1280x1024 camera with 4.8 um pixels, an 8 mm lens at f/5.6
  // 80 mm above the part, a 650 nm laser of a few mW 30-50 mm from the camera.
  EXPECT_NEAR(cam.focal_length_m(), 8e-3, 1e-5);
  EXPECT_NEAR(camera_height - kTop, 0.080, 1e-9);
  const LaserProjector& laser = d.scene.sensor.lasers[0];
  EXPECT_EQ(laser.wavelength_m(), 650e-9);
  EXPECT_GE(laser.origin_in_cam().norm(), 0.030);
  EXPECT_LE(laser.origin_in_cam().norm(), 0.050);
}

}  // namespace
}  // namespace lt
