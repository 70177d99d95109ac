// The chief rays' packets (render/chief_rays.h) give every pixel the hit that
// EmbreeScene::Intersect gives its ray alone, also where the ray crosses the
// edge two triangles share and the traversal order picks one of them.
#include "render/chief_rays.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "render_test_world.h"

namespace lt {
namespace {

constexpr int kW = 61, kH = 61;  // odd: pixel (i, i) sees the square's diagonal exactly; a partial last packet

void ExpectSameHit(const std::optional<Hit>& a, const std::optional<Hit>& b, int x, int y) {
  ASSERT_EQ(a.has_value(), b.has_value()) << "pixel " << x << ", " << y;
  if (!a) return;
  EXPECT_EQ(a->instance_id, b->instance_id) << "pixel " << x << ", " << y;
  EXPECT_EQ(a->primitive_id, b->primitive_id) << "pixel " << x << ", " << y;
  EXPECT_EQ(a->material_id, b->material_id);
  EXPECT_EQ(a->t, b->t);
  EXPECT_EQ(a->position, b->position);
  EXPECT_EQ(a->geometric_normal, b->geometric_normal);
  EXPECT_EQ(a->shading_normal, b->shading_normal);
}

TEST(ChiefRays, PacketsGiveTheSingleRaysHits) {
  // A square facing the camera, centred on its axis and split along its
  // diagonal; in front of its lower right part, a box turned to show three faces
  // and their creases.
  test::World world;
  world.Add(test::Rectangle({0, 0, 0.1}, Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), 0.08, 0.08));
  Eigen::Affine3d box_pose = Eigen::Translation3d(0.02, 0.02, 0.08) *
                             Eigen::AngleAxisd(0.6, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX());
  world.Add(test::Box({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01}), box_pose);
  world.Build();
  const Camera cam = test::TestCamera(kW, kH, 40);
  const Pose world_from_cam = Pose::Identity();
  std::vector<ChiefRay> rays(size_t(kW) * size_t(kH));
  EXPECT_EQ(TraceChiefRays(*world.embree, cam, world_from_cam, 0, 0, kW, kH, rays), uint64_t(kW) * uint64_t(kH));
  int hits = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const ChiefRay& r = rays[size_t(y) * kW + size_t(x)];
      ASSERT_TRUE(r.traced);
      Ray ray;
      ray.direction = *cam.Unproject(Eigen::Vector2d(x, y));
      EXPECT_EQ(r.direction, ray.direction);
      ExpectSameHit(r.hit, world.embree->Intersect(ray), x, y);
      hits += r.hit.has_value();
    }
  EXPECT_GT(hits, kW * kH / 2);
  // A block inside the image: the same rays, its own packets.
  std::vector<ChiefRay> block(size_t(7) * size_t(5));
  EXPECT_EQ(TraceChiefRays(*world.embree, cam, world_from_cam, 30, 28, 37, 33, block), 35u);
  for (int y = 28; y < 33; ++y)
    for (int x = 30; x < 37; ++x)
      ExpectSameHit(block[size_t(y - 28) * 7 + size_t(x - 30)].hit, rays[size_t(y) * kW + size_t(x)].hit, x, y);
  std::vector<ChiefRay> wrong(3);
  EXPECT_THROW(TraceChiefRays(*world.embree, cam, world_from_cam, 0, 0, 2, 2, wrong), std::invalid_argument);
}

TEST(ChiefRays, PacketsSeeMaskHolesAsSingleRaysDo) {
  // A plate whose upper half a MASK texture cuts out (the alpha filter runs on
  // 16-ray packets), over a floor: each pixel's hit equals Intersect's, and
  // rays through the hole reach the floor.
  test::World world;
  test::BuildMaskedPlateOverFloor(world, 0.1, 0.12);
  ASSERT_EQ(world.embree->alpha_filtered_mesh_count(), 1u);
  const Camera cam = test::TestCamera(kW, kH, 40);
  std::vector<ChiefRay> rays(size_t(kW) * size_t(kH));
  TraceChiefRays(*world.embree, cam, Pose::Identity(), 0, 0, kW, kH, rays);
  int on_floor = 0, on_plate = 0;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const ChiefRay& r = rays[size_t(y) * kW + size_t(x)];
      Ray ray;
      ray.direction = r.direction;
      ExpectSameHit(r.hit, world.embree->Intersect(ray), x, y);
      if (r.hit) (r.hit->instance_id == 0 ? on_floor : on_plate)++;
    }
  EXPECT_GT(on_plate, 100);
  EXPECT_GT(on_floor, 100);
}

}  // namespace
}  // namespace lt
