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
  // The plate: a hole (alpha < 0.5) where y < 0.
  test::BuildMaskedPlateOverFloor(world, plate_z, floor_z);
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
