// Motion during the exposure. An emitting box (radiance 1) on a black
// background, seen by a camera that slides sideways by Delta = 8 px during the
// 1 ms exposure: each edge of the box becomes a linear ramp Delta pixels wide
// (a pixel's value is the fraction of the exposure it saw the box), and a row's
// total light is unchanged. The same scene standing still has sharp edges.
#include <gtest/gtest.h>

#include "render/frame_renderer.h"
#include "render_test_world.h"

namespace lt {
namespace {

struct Edges {
  double row_sum = 0;
  int partial = 0;  // pixels strictly between 5% and 95%
};

Edges MeasureRow(const RenderedFrame& f, int v) {
  Edges e;
  for (int u = 0; u < f.radiance.width; ++u) {
    double x = f.radiance.At(u, v, 0);
    e.row_sum += x;
    e.partial += x > 0.05 && x < 0.95;
  }
  return e;
}

RenderedFrame RenderBox(const Motion& motion) {
  test::World world;
  world.Add(test::Box({-0.02, -0.02, 0.1}, {0.02, 0.02, 0.12}));
  Material glow = test::Plastic(0.0f, 1.0f);
  glow.emissive = Eigen::Vector3f::Ones();
  world.geometry->materials = {glow};
  world.Build();
  SensorRig& rig = world.scene.sensor;
  rig.camera = test::TestCamera(80, 40, 150);
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"bright", 1e-3, false, false, false}};
  rig.shutter = ShutterSchedule(sh);
  world.scene.render.spp = 64;
  world.scene.render.adaptive_noise = 0;  // every pixel takes its 64 time samples
  world.scene.render.max_bounces = 0;
  world.scene.motion = motion;
  return FrameRenderer(world.scene, *world.embree).Render(0);
}

TEST(MotionBlur, SlidingCameraSmearsEdgesByTheDistanceTravelled) {
  // 8 px at depth 0.1 m with fx = 150 px is 5.333 mm; travelled in the 1 ms exposure.
  const double travel = 8 * 0.1 / 150;
  auto dir = std::filesystem::temp_directory_path() / "lt_motion_blur";
  RenderedFrame moving = RenderBox(test::SlidingAlongX(dir, travel / 1e-3));
  RenderedFrame still = RenderBox(DefaultMotion());
  for (int v = 12; v < 28; v += 3) {
    Edges m = MeasureRow(moving, v), s = MeasureRow(still, v);
    // The box is 40 mm wide: 60 px of radiance 1 in every row, moving or not
    // (64 time samples per pixel: about 0.3 px of noise on the sum).
    EXPECT_NEAR(s.row_sum, 60.0, 0.5) << "row " << v;
    EXPECT_NEAR(m.row_sum, 60.0, 1.0) << "row " << v;
    EXPECT_LE(s.partial, 2) << "row " << v;
    // Two ramps of 8 px; their end pixels may read within 5% of 0 or 1.
    EXPECT_GE(m.partial, 2 * 8 - 4) << "row " << v;
    EXPECT_LE(m.partial, 2 * 8 + 2) << "row " << v;
  }
  // The ground truth is taken at mid-exposure: half the travel.
  EXPECT_NEAR(moving.world_from_cam.translation().x(), travel / 2, 1e-12);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lt
