// The exact point-to-surface distance (scene/surface_distance.h): the nearest
// point of a triangle in each of its Voronoi regions (closed forms), the
// hierarchy against a search over every triangle, and a scene's surfaces with
// a printed part that grows over time.
#include <gtest/gtest.h>

#include <random>

#include "scene/scene_file.h"
#include "scene/surface_distance.h"
#include "test_util.h"

namespace lt {
namespace {

using Eigen::Vector3d;

TEST(ClosestPointOnTriangle, EachRegion) {
  const Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto near = [&](const Vector3d& p) { return ClosestPointOnTriangle(p, a, b, c); };
  EXPECT_TRUE(near({0.2, 0.3, 2}).isApprox(Vector3d(0.2, 0.3, 0)));    // face: the foot of the normal
  EXPECT_TRUE(near({-1, -2, 1}).isApprox(a));                            // vertex regions
  EXPECT_TRUE(near({3, -0.5, 0}).isApprox(b));
  EXPECT_TRUE(near({-0.5, 3, -1}).isApprox(c));
  EXPECT_TRUE(near({0.5, -1, 3}).isApprox(Vector3d(0.5, 0, 0)));        // edge ab
  EXPECT_TRUE(near({-2, 0.25, 1}).isApprox(Vector3d(0, 0.25, 0)));      // edge ca
  EXPECT_TRUE(near({1, 1, 0.5}).isApprox(Vector3d(0.5, 0.5, 0)));       // edge bc
  // A degenerate triangle (a segment) gives the nearest point of the segment.
  EXPECT_TRUE(ClosestPointOnTriangle({0.5, 1, 0}, a, b, Vector3d(2, 0, 0)).isApprox(Vector3d(0.5, 0, 0)));
}

TEST(TriangleSet, MatchesTheNearestOfEveryTriangle) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1, 1), small(-0.1, 0.1);
  Mesh mesh;
  for (int t = 0; t < 500; ++t) {
    const Eigen::Vector3f centre(float(coord(rng)), float(coord(rng)), float(coord(rng)));
    for (int k = 0; k < 3; ++k) {
      mesh.positions.push_back(centre + Eigen::Vector3f(float(small(rng)), float(small(rng)), float(small(rng))));
      mesh.indices.push_back(uint32_t(mesh.positions.size() - 1));
    }
  }
  Eigen::Affine3d world_from_mesh = Eigen::Translation3d(5, -2, 1) * Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()) *
                                    Eigen::Scaling(0.01);
  TriangleSet set;
  EXPECT_FALSE(set.ClosestPoint(Vector3d::Zero()));  // empty
  set.Add(mesh, world_from_mesh);
  set.Build();
  ASSERT_EQ(set.size(), 500u);
  for (int i = 0; i < 200; ++i) {
    const Vector3d p = world_from_mesh * Vector3d(2 * coord(rng), 2 * coord(rng), 2 * coord(rng));
    double best = 1e300;
    for (size_t t = 0; t < 500; ++t) {
      const auto corner = [&](size_t k) { return world_from_mesh * mesh.positions[3 * t + k].cast<double>(); };
      best = std::min(best, (ClosestPointOnTriangle(p, corner(0), corner(1), corner(2)) - p).norm());
    }
    const auto q = set.ClosestPoint(p);
    ASSERT_TRUE(q);
    EXPECT_DOUBLE_EQ((*q - p).norm(), best);
  }
}

// Line A of the G-code, 20 mm at y = 0, is printed during [0.01, 1.01] s; its
// bead's top is at z = 0.2 mm (tests/scene/printed_part_test.cpp).
// A scene of the demo's bed and the part `gcode` prints (in `dir`), one chunk
// per run of extrusions.
SceneFile PrintScene(const test::TempDir& dir, const std::string& gcode) {
  test::WriteText(dir / "part.gcode", gcode);
  const std::string text = std::string(R"({"objects": [{"name": "bed", "gltf": ")") + LT_SOURCE_DIR +
                           R"(/scenes/demo/print_bed.glb"}],
  "materials": {"pla": {"base_color": [0.8, 0.8, 0.8], "roughness": 0.5}},
  "sensor": {"camera": {"resolution": [32, 24], "pixel_pitch_um": 10, "focal_length_mm": 8, "f_number": 4}},
  "motion": {"type": "gcode", "file": "part.gcode"}, "print": {"material": "pla", "chunk_moves": 1}})";
  return ParseSceneText(text, "scene.json", dir.path());
}

TEST(SceneSurface, APrintedPartGrowsWithTime) {
  test::TempDir dir;
  const SceneFile scene = PrintScene(dir, ";Layer height: 0.2\nG0 F1200 Z0.2\nG1 X20 E0.8\n");
  SceneSurface surface(scene);
  const Vector3d above_end(15e-3, 0, 1.2e-3);  // 1 mm above the bead's top near its end
  surface.UpdateTo(0.51);                      // the nozzle at x = 10 mm: not printed yet
  const double before = *surface.Distance(above_end);
  EXPECT_GT(before, 1.1e-3);  // the bed (z <= 0), or the bead's end 5 mm away
  surface.UpdateTo(2.0);      // printed
  EXPECT_NEAR(*surface.Distance(above_end), 1e-3, 1e-9);
  surface.UpdateTo(0.51);  // and back
  EXPECT_DOUBLE_EQ(*surface.Distance(above_end), before);
}

// Four lines, each its own chunk (travels between them). Stepping through the
// print meshes each chunk once when it completes, plus the growing one at each
// time, and gives the distances of a surface made afresh at that time; going
// back in time does too.
TEST(SceneSurface, StepsThroughThePrintMeshingOnlyWhatChanged) {
  test::TempDir dir;
  const SceneFile scene = PrintScene(dir, ";Layer height: 0.2\nG0 F1200 Z0.2\nG1 X20 E0.8\nG0 Y5\nG1 X0 E1.6\n"
                                          "G0 Y10\nG1 X20 E2.4\nG0 Y15\nG1 X0 E3.2\n");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-2e-3, 22e-3), y(-2e-3, 17e-3), z(0, 2e-3);
  std::vector<Vector3d> points;
  for (int i = 0; i < 50; ++i) points.emplace_back(x(rng), y(rng), z(rng));
  auto expect_as_fresh = [&](const SceneSurface& surface, double t) {
    SceneSurface fresh(scene);
    fresh.UpdateTo(t);
    EXPECT_EQ(surface.triangle_count(), fresh.triangle_count()) << t;
    for (const Vector3d& p : points) EXPECT_DOUBLE_EQ(*surface.Distance(p), *fresh.Distance(p)) << t;
  };
  SceneSurface surface(scene);
  int steps = 0;
  for (double t = 0.3; t < 6; t += 0.35, ++steps) {
    surface.UpdateTo(t);
    expect_as_fresh(surface, t);
  }
  // Remade every time, the chunks printed so far would be 40 meshes; each chunk
  // is made once when complete, and one growing chunk at most per step.
  EXPECT_LE(surface.chunk_meshes_made(), size_t(4 + steps));
  EXPECT_GE(surface.chunk_meshes_made(), 4u);
  surface.UpdateTo(1.5);
  expect_as_fresh(surface, 1.5);
  surface.UpdateTo(4.0);
  expect_as_fresh(surface, 4.0);
}

}  // namespace
}  // namespace lt
