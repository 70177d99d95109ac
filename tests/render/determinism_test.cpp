// Same seed, same frame: bit-identical output whatever the thread count.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "render/frame_renderer.h"
#include "render_test_world.h"

namespace lt {
namespace {

test::World SceneWithEverything() {
  test::World world;
  world.Add(test::Rectangle({0, 0, 0.1}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2));
  world.Add(test::Box({-0.01, -0.01, 0.085}, {0.01, 0.01, 0.1}));
  Material pla = test::Plastic(0.8f, 0.4f);
  pla.subsurface = Subsurface{Eigen::Vector3d::Constant(3e-4), 3e-4};
  world.geometry->materials = {pla};
  world.scene.environment.radiance = Eigen::Vector3d(0.5, 0.4, 0.3);
  world.Build();
  SensorRig& rig = world.scene.sensor;
  rig.camera = test::TestCamera(64, 48, 150);
  rig.lasers = {test::TestLaser(0.03, 0.1, 5e-3, 4e-3, 3, 0.05)};
  LedParams led;
  led.cam_from_led.translation() = Eigen::Vector3d(0, -0.02, 0);
  rig.led = Led(led);
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"mixed", 1e-3, true, false, true}};
  rig.shutter = ShutterSchedule(sh);
  world.scene.render.spp = 4;
  world.scene.render.max_bounces = 3;
  world.scene.render.russian_roulette_depth = 1;
  world.scene.render.speckle_contrast = 0.5;
  return world;
}

TEST(Determinism, BitIdenticalWithOneAndTwoThreads) {
  test::World world = SceneWithEverything();
  RenderOverrides one, two;
  one.threads = 1;
  two.threads = 2;
  RenderedFrame a = FrameRenderer(world.scene, *world.embree, one).Render(3);
  RenderedFrame b = FrameRenderer(world.scene, *world.embree, two).Render(3);
  EXPECT_EQ(a.raw.pixels, b.raw.pixels);
  EXPECT_EQ(a.radiance.pixels, b.radiance.pixels);
  EXPECT_EQ(a.laser_radiance.pixels, b.laser_radiance.pixels);
  EXPECT_EQ(a.gt.plane.pixels, b.gt.plane.pixels);
  ASSERT_EQ(a.centers.size(), b.centers.size());
  for (size_t i = 0; i < a.centers.size(); ++i) EXPECT_EQ(a.centers[i].u, b.centers[i].u);
  // And the frame is not trivially empty.
  float laser = 0, rgb = 0;
  for (int y = 0; y < a.radiance.height; ++y)
    for (int x = 0; x < a.radiance.width; ++x) laser += a.radiance.At(x, y, 3), rgb += a.radiance.At(x, y, 0);
  EXPECT_GT(laser, 0);
  EXPECT_GT(rgb, 0);
  EXPECT_GT(a.centers.size(), 40u);
}

// A scanner moving during the exposure (0.1 m/s across the stripe, 1 ms: six
// time slices of the subsurface caches) and light paths at their own times.
TEST(Determinism, MovingFrameBitIdenticalWithOneAndTwoThreads) {
  test::World world = SceneWithEverything();
  const auto dir = std::filesystem::temp_directory_path() / ("lt_determinism_moving_" + std::to_string(::getpid()));
  world.scene.motion = test::SlidingAlongX(dir, 0.1);
  world.scene.render.light_paths = 64;
  RenderOverrides one, two;
  one.threads = 1;
  two.threads = 2;
  RenderedFrame a = FrameRenderer(world.scene, *world.embree, one).Render(0);  // frame 0: within the poses' 10 ms
  RenderedFrame b = FrameRenderer(world.scene, *world.embree, two).Render(0);
  std::filesystem::remove_all(dir);
  EXPECT_GT(a.stats.entry_tree_slices, 1);
  EXPECT_GT(a.stats.light_paths, 0);
  EXPECT_EQ(a.raw.pixels, b.raw.pixels);
  EXPECT_EQ(a.radiance.pixels, b.radiance.pixels);
  EXPECT_EQ(a.laser_radiance.pixels, b.laser_radiance.pixels);
}

TEST(Determinism, OtherSeedOtherNoise) {
  test::World world = SceneWithEverything();
  RenderOverrides s1, s2;
  s1.seed = 1;
  s2.seed = 2;
  RenderedFrame a = FrameRenderer(world.scene, *world.embree, s1).Render(0);
  RenderedFrame b = FrameRenderer(world.scene, *world.embree, s2).Render(0);
  EXPECT_NE(a.raw.pixels, b.raw.pixels);
}

TEST(Determinism, NoNaNOrInfAnywhere) {
  test::World world = SceneWithEverything();
  RenderedFrame a = FrameRenderer(world.scene, *world.embree).Render(1);
  for (const Image<float>* img : {&a.radiance, &a.laser_radiance, &a.gt.depth, &a.gt.normal, &a.gt.plane}) {
    for (float v : img->pixels) ASSERT_TRUE(std::isfinite(v));
  }
}

}  // namespace
}  // namespace lt
