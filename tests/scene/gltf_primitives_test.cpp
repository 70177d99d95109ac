// Primitive topologies as exporters write them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::TempDir;

// Two runs of a triangle strip joined by repeating the last vertex of the first
// and the first of the second (the usual stitching; glTF has no restart index):
// the joining triangles have a repeated corner. They are dropped without being
// reported as degenerate (every stitched strip file warned before); a strip
// triangle whose three distinct corners are collinear still is.
TEST(GltfPrimitives, StripJoinsAreNotReportedAsDegenerate) {
  // Run 1: quad x in [0, 1]; run 2: quad x in [2, 3] (4 vertices each).
  const std::vector<float> positions = {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0,
                                        2, 0, 0, 2, 1, 0, 3, 0, 0, 3, 1, 0};
  for (bool indexed : {true, false}) {
    GltfBuilder b;
    std::vector<uint32_t> strip = {0, 1, 2, 3, 3, 4, 4, 5, 6, 7};
    std::vector<float> pos = positions;
    if (!indexed) {  // the same strip with the repeated vertices written out twice
      pos.clear();
      for (uint32_t i : strip) pos.insert(pos.end(), {positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]});
      strip.clear();
    }
    const int mesh = b.AddTriangleMesh("strips", pos, {}, {}, strip, -1, 5);
    // A second strip primitive: one triangle of three collinear corners.
    b.json()["meshes"][size_t(mesh)]["primitives"].push_back(
        {{"attributes", {{"POSITION", b.AddFloats({5, 0, 0, 6, 0, 0, 7, 0, 0}, "VEC3")}}}, {"mode", 5}});
    b.AddNode("n", mesh);
    TempDir dir;
    b.WriteGlb(dir / "strip.glb");
    const GltfAsset a = LoadGltf(dir / "strip.glb", "strip.glb");
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].TriangleCount(), 4u) << indexed;  // 2 + 2, the joins dropped
    EXPECT_EQ(a.degenerate_triangles, 1u) << indexed;      // only the collinear strip triangle
    EXPECT_THAT(a.warnings, ::testing::Contains("strip.glb: 1 degenerate triangles dropped")) << indexed;
  }
}

// An assembly whose parts each carry an outline of lines beside their triangles
// (a web CAD viewer's export, trimesh's paths), and edge-only meshes: the skipped
// primitives and the meshes left without triangles are one warning per kind that
// counts them and names the first three, where each part added a line of its own
// (300 parts: 301 warnings). Up to three still get a line each (ListsWarnings).
TEST(GltfPrimitives, ManySkippedPrimitivesAreCountedInOneWarning) {
  GltfBuilder b;
  const int p = b.AddFloats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  for (int i = 0; i < 10; ++i) {
    b.json()["meshes"].push_back({{"name", "part" + std::to_string(i)},
                                  {"primitives", {{{"attributes", {{"POSITION", p}}}},
                                                  {{"attributes", {{"POSITION", p}}}, {"mode", 1}}}}});
    b.AddNode("part" + std::to_string(i), i);
  }
  for (int i = 0; i < 5; ++i) {
    b.json()["meshes"].push_back(
        {{"name", "edges" + std::to_string(i)}, {"primitives", {{{"attributes", {{"POSITION", p}}}, {"mode", 3}}}}});
    b.AddNode("edges" + std::to_string(i), 10 + i);
  }
  TempDir dir;
  b.WriteGlb(dir / "assembly.glb");
  const GltfAsset a = LoadGltf(dir / "assembly.glb", "assembly.glb");
  EXPECT_EQ(a.instances.size(), 10u);
  EXPECT_THAT(a.warnings, ::testing::ElementsAre(
      "assembly.glb: lines skipped (only triangles are rendered) in 10 primitives: mesh \"part0\" primitive 1, "
      "mesh \"part1\" primitive 1, mesh \"part2\" primitive 1 and 7 more",
      "assembly.glb: line strip skipped (only triangles are rendered) in 5 primitives: mesh \"edges0\" primitive 0, "
      "mesh \"edges1\" primitive 0, mesh \"edges2\" primitive 0 and 2 more",
      "assembly.glb: 5 meshes have no triangles; they are skipped: \"edges0\", \"edges1\", \"edges2\" and 2 more"));
}

}  // namespace
}  // namespace lt
