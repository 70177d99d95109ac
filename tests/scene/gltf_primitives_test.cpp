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

}  // namespace
}  // namespace lt
