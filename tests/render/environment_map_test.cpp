// The lat-long environment map: world z up, v = polar angle from +z (top row),
// u = azimuth from -x (left edge) through -y, +x (centre), +y. A camera looking
// straight up sees the top rows, looking down the bottom rows; a white convex
// object under a uniform map reads the map's value (furnace).
#include <gtest/gtest.h>

#include "core/image_io.h"
#include "render/frame_renderer.h"
#include "render_test_world.h"

namespace lt {
namespace {

RenderedFrame RenderSky(const std::filesystem::path& exr, const Pose& world_from_cam, bool with_box) {
  test::World world;
  if (with_box) {
    world.Add(test::Box({-0.02, -0.02, 0.08}, {0.02, 0.02, 0.12}));
  } else {
    world.Add(test::Rectangle({100, 100, 100}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 1e-3, 1e-3));
  }
  world.geometry->materials = {test::Plastic(1.0f, 0.8f)};
  world.scene.environment.kind = Environment::Kind::kMap;
  world.scene.environment.exr = exr;
  world.scene.environment.scale = 2.0;
  world.Build();
  SensorRig& rig = world.scene.sensor;
  rig.camera = test::TestCamera(20, 16, 40);
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"bright", 1e-3, false, false, false}};
  rig.shutter = ShutterSchedule(sh);
  world.scene.render.spp = 16;
  world.scene.render.max_bounces = 3;
  world.scene.motion = StaticMotion{world_from_cam};
  return FrameRenderer(world.scene, *world.embree).Render(0);
}

TEST(EnvironmentMap, OrientationAndScale) {
  auto dir = std::filesystem::temp_directory_path() / "lt_env_map";
  std::filesystem::create_directories(dir);
  Image<float> map(64, 32, 3, 0.0f);
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 64; ++x) map.At(x, y, y < 16 ? 0 : 2) = y < 16 ? 3.0f : 5.0f;
  WriteImage(dir / "sky.exr", map);
  // Camera z along world +z (up): the upper hemisphere, red 3 x scale 2.
  RenderedFrame up = RenderSky(dir / "sky.exr", Pose::Identity(), false);
  EXPECT_FLOAT_EQ(up.radiance.At(10, 8, 0), 6.0f);
  EXPECT_FLOAT_EQ(up.radiance.At(10, 8, 2), 0.0f);
  // Turned upside down: the lower hemisphere, blue 5 x 2.
  Pose down = Pose::Identity();
  down.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  RenderedFrame below = RenderSky(dir / "sky.exr", down, false);
  EXPECT_FLOAT_EQ(below.radiance.At(10, 8, 2), 10.0f);
  EXPECT_FLOAT_EQ(below.radiance.At(10, 8, 0), 0.0f);
  std::filesystem::remove_all(dir);
}

TEST(EnvironmentMap, UniformMapFurnace) {
  auto dir = std::filesystem::temp_directory_path() / "lt_env_map_uniform";
  std::filesystem::create_directories(dir);
  WriteImage(dir / "sky.exr", Image<float>(32, 16, 3, 1.5f));
  RenderedFrame f = RenderSky(dir / "sky.exr", Pose::Identity(), true);
  double sum = 0;
  for (int y = 0; y < f.radiance.height; ++y)
    for (int x = 0; x < f.radiance.width; ++x) sum += f.radiance.At(x, y, 1);
  // 320 pixels x 16 samples of a white convex box under a uniform sky of 3.
  EXPECT_NEAR(sum / (f.radiance.width * f.radiance.height), 3.0, 0.03);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace lt
