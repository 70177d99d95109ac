// Secondary rays never re-hit the surface they leave (in the spirit of
// pbrt-v4's "Triangle Reintersect" test): random triangles at millimetre and
// building scale, up to 1 km from the origin and up to 500 m from the render
// frame's origin; rays hit them, and rays spawned from the hits in random
// directions on either side must escape the (lone) triangle.
#include <gtest/gtest.h>

#include "core/random.h"
#include "render/path_tracer.h"
#include "render/sampling.h"
#include "render_test_world.h"

namespace lt {
namespace {

Mesh Triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  Mesh m;
  m.name = "triangle";
  Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  for (const auto& p : {a, b, c}) {
    m.positions.push_back(p.cast<float>());
    m.normals.push_back(n.cast<float>());
  }
  m.indices = {0, 1, 2};
  m.triangle_material = {0};
  return m;
}

Eigen::Vector3d RandomUnit(Rng& r) {
  return SampleUniformSphere(r.NextFloat(), r.NextFloat()).cast<double>().normalized();
}

struct Case {
  double offset_m;      // where the triangle is
  double size_m;        // its size
  double far_mesh_m;    // distance of a second mesh that moves the render origin (0: none)
};

TEST(Reintersect, SpawnedRaysNeverHitTheirOwnTriangle) {
  const Case cases[] = {{0, 1e-3, 0}, {0, 1e-6, 0}, {0.1, 0.05, 0}, {1000, 1e-3, 0}, {1000, 10, 0},
                        {1000, 1e-3, 1000}, {1000, 0.5, 1000}, {10, 100, 0}};
  Rng rng(7);
  int spawned = 0;
  for (const Case& c : cases) {
    for (int tri = 0; tri < 20; ++tri) {
      Eigen::Vector3d center = c.offset_m * RandomUnit(rng);
      Eigen::Vector3d a = center + c.size_m * RandomUnit(rng), b = center + c.size_m * RandomUnit(rng),
                      d = center + c.size_m * RandomUnit(rng);
      if ((b - a).cross(d - a).norm() < 0.05 * c.size_m * c.size_m) continue;  // too thin to aim at
      test::World world;
      world.Add(Triangle(a, b, d));
      if (c.far_mesh_m > 0) {
        Eigen::Vector3d far = center + c.far_mesh_m * RandomUnit(rng);
        world.Add(Triangle(far, far + Eigen::Vector3d(1, 0, 0), far + Eigen::Vector3d(0, 1, 0)));
      }
      world.Build();
      Environment env;
      PathTracer tracer(*world.embree, env, nullptr, {}, 0);
      for (int k = 0; k < 50; ++k) {
        // Aim at a random point of the triangle from a random direction.
        float u1 = rng.NextFloat(), u2 = rng.NextFloat();
        Eigen::Vector3f bc = SampleUniformTriangle(u1, u2);
        Eigen::Vector3d target = bc.x() * a + bc.y() * b + bc.z() * d;
        Eigen::Vector3d from = target + 3 * c.size_m * RandomUnit(rng);
        Ray ray{from, target - from, 0, 2};
        auto hit = world.embree->Intersect(ray);
        if (!hit || hit->instance_id != 0) continue;
        for (int s = 0; s < 20; ++s) {
          Eigen::Vector3d dir = RandomUnit(rng);
          if (std::abs(dir.dot(hit->geometric_normal)) < 1e-3) continue;  // tangent: no side to leave to
          Ray out{tracer.SpawnOrigin(hit->position, hit->geometric_normal, dir), dir, 0,
                  std::numeric_limits<double>::infinity()};
          auto again = world.embree->Intersect(out);
          ASSERT_FALSE(again && again->instance_id == 0)
              << "offset " << c.offset_m << " m, size " << c.size_m << " m: re-hit at t = " << again->t;
          ++spawned;
        }
      }
    }
  }
  EXPECT_GT(spawned, 50000);
}

}  // namespace
}  // namespace lt
