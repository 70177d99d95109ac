// Beam pixels at a geometric edge take render.edge_spp_factor times spp
// (FrameRenderer::SampleBudgets, docs/rendering.md); other pixels keep theirs.
#include <gtest/gtest.h>

#include <cstdio>

#include "render/frame_renderer.h"
#include "render_test_world.h"

namespace lt {
namespace {

constexpr double D = 0.1, H = 0.01, b = 0.03;
constexpr int kW = 64, kH = 48;

void SetUpRig(test::World& world, int spp, int edge_factor, double divergence_rad = 2e-3) {
  world.Build();
  SensorRig& rig = world.scene.sensor;
  rig.camera = test::TestCamera(kW, kH, 100);                    // 1 mm pixels at D
  rig.lasers = {test::TestLaser(b, D, 5e-3, divergence_rad)};  // a vertical stripe near the centre column
  ShutterParams sh;
  sh.cycle = {ShutterFrameSpec{"dim", 1e-4, true, false, false}};
  rig.shutter = ShutterSchedule(sh);
  world.scene.render.spp = spp;
  world.scene.render.max_bounces = 0;
  world.scene.render.edge_spp_factor = edge_factor;
}

// A floor at depth D and, over the image's lower half (y > 0), a box whose top
// stands H nearer the camera: a step 10 footprints high across the stripe,
// between rows 23 and 24.
RenderedFrame RenderStep(int spp, int edge_factor) {
  test::World world;
  world.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2));
  world.Add(test::Box({-0.2, 0, D - H}, {0.2, 0.2, D}));
  SetUpRig(world, spp, edge_factor);
  return FrameRenderer(world.scene, *world.embree).Render(0);
}

int64_t NearPixelsInRows(const RenderedFrame& frame, int y0, int y1) {
  int64_t n = 0;
  for (int y = y0; y <= y1; ++y)
    for (int x = 0; x < kW; ++x) n += frame.near_mask.At(x, y) > 0;
  return n;
}

TEST(EdgeBudget, BeamPixelsAtAStepTakeTheEdgeBudget) {
  const int spp = 4, factor = 4;
  const RenderedFrame edges = RenderStep(spp, factor);
  const RenderedFrame plain = RenderStep(spp, 1);
  // The edge pixels are the beam's pixels within two rows of the step (rows 23
  // and 24 lie across it): rows 21 to 26, and no other.
  ASSERT_GT(NearPixelsInRows(edges, 21, 26), 6);
  EXPECT_EQ(edges.stats.edge_pixels, NearPixelsInRows(edges, 21, 26));
  EXPECT_EQ(plain.stats.edge_pixels, 0);
  EXPECT_EQ(edges.stats.near_pixels, plain.stats.near_pixels);
  // At spp 4 a beam pixel's first batch is all its samples; an edge pixel takes
  // factor * spp, whatever its neighbours' noise.
  EXPECT_EQ(edges.stats.samples - plain.stats.samples, uint64_t(edges.stats.edge_pixels) * uint64_t((factor - 1) * spp));
  std::printf("edge pixels %lld of %lld near, samples %llu (factor %d) and %llu (factor 1)\n",
              (long long)edges.stats.edge_pixels, (long long)edges.stats.near_pixels,
              (unsigned long long)edges.stats.samples, factor, (unsigned long long)plain.stats.samples);
}

TEST(EdgeBudget, AnEdgeInTheBeamAwayFromTheSheetTakesNoEdgeBudget) {
  // A sheet of sigma 0.03 rad (~3 px at D; FrameRenderer: the beam reaches 8
  // sigma and two footprints, the sheet itself 3 sigma and two footprints,
  // and the edge budget that plus 3 px) and, beside the stripe at column ~31,
  // a box whose top stands H nearer from x = 0.02 m on: its wall, columns
  // ~51-54, ~20 px from the stripe, runs parallel to it. The wall's pixels are
  // in the beam but the stripe crosses no edge: no edge budget.
  test::World world;
  world.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2));
  world.Add(test::Box({0.02, -0.2, D - H}, {0.2, 0.2, D}));
  SetUpRig(world, 4, 4, 0.12);
  const RenderedFrame frame = FrameRenderer(world.scene, *world.embree).Render(0);
  for (int x = 49; x <= 56; ++x) ASSERT_GT(frame.near_mask.At(x, kH / 2), 0.0f) << "column " << x;  // in the beam
  EXPECT_EQ(frame.stats.edge_pixels, 0);
  // The same box across the stripe (its wall at x = 0): the stripe crosses the
  // wall's edges, whose pixels take the budget.
  test::World across;
  across.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX(), 0.2, 0.2));
  across.Add(test::Box({0.0, -0.2, D - H}, {0.2, 0.2, D}));
  SetUpRig(across, 4, 4, 0.12);
  EXPECT_GT(FrameRenderer(across.scene, *across.embree).Render(0).stats.edge_pixels, 2 * kH);
}

TEST(EdgeBudget, ASteepPlaneHasNoEdge) {
  // A plane at 70 degrees to the optical axis: neighbouring pixels' points lie
  // far apart along it, but on its plane.
  test::World world;
  const double tilt = 70.0 * M_PI / 180.0;
  const Eigen::Vector3d along(std::sin(tilt), 0, std::cos(tilt));  // in the plane, away from the camera to +x
  world.Add(test::Rectangle({0, 0, D}, Eigen::Vector3d::UnitY(), along, 0.2, 0.5));
  SetUpRig(world, 4, 4);
  const RenderedFrame frame = FrameRenderer(world.scene, *world.embree).Render(0);
  ASSERT_GT(frame.stats.near_pixels, 0);
  EXPECT_EQ(frame.stats.edge_pixels, 0);
}

}  // namespace
}  // namespace lt
