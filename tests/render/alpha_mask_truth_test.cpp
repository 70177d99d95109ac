// Ground-truth stripe centres see glTF MASK holes as the Embree scene does (the
// alpha filter of scene/embree_alpha.cpp): behind a plate whose upper half is
// cut out, the centres of the upper rows lie on the floor, those of the lower
// rows on the plate. Before, the plate was opaque and every centre lay on it.
#include <gtest/gtest.h>

#include "render/stripe_truth.h"
#include "render_test_world.h"

namespace lt {
namespace {

TEST(AlphaMaskTruth, CentresThroughAMaskHoleLandOnTheSurfaceBehind) {
  const double plate_z = 0.1, floor_z = 0.12;
  test::World world;
  world.Add(test::Rectangle({0, 0, floor_z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.3, 0.3));
  // The plate: u runs along world y (u = 0 at y = -0.1), a 2x1 texture of alpha
  // (0, 1), clamped: alpha < 0.5 (a hole) where y < 0.
  Mesh plate = test::Rectangle({0, 0, plate_z}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.1, 0.1, 1);
  plate.texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  world.Add(plate);
  auto texture = std::make_shared<Texture>();
  texture->image = Image<uint8_t>(2, 1, 4, 255);
  texture->image.At(0, 0, 3) = 0;
  texture->wrap_s = texture->wrap_t = WrapMode::kClampToEdge;
  Material mask = test::Plastic();
  mask.alpha_mode = AlphaMode::kMask;
  mask.base_color_texture = texture;
  world.geometry->materials = {test::Plastic(), mask};
  world.Build();
  ASSERT_EQ(world.embree->alpha_filtered_mesh_count(), 1u);

  const Camera cam = test::TestCamera(160, 120, 150);
  const std::vector<LaserProjector> lasers = {test::TestLaser(0.03, 0.11)};
  const auto centers = ComputeStripeCenters(*world.embree, cam, lasers, Pose::Identity(), ScanAxis::kRows);
  int on_floor = 0, on_plate = 0;
  for (const StripeCenter& c : centers) {
    const double y = c.p_world.y();
    if (std::abs(y) < 2e-3) continue;  // the blended edge
    // (float vertices: 0.1 is 0.1 + 1.5e-9)
    EXPECT_NEAR(c.p_world.z(), y < 0 ? floor_z : plate_z, 1e-7) << "row " << c.v;
    (y < 0 ? on_floor : on_plate)++;
  }
  EXPECT_GT(on_floor, 40);
  EXPECT_GT(on_plate, 40);
}

}  // namespace
}  // namespace lt
