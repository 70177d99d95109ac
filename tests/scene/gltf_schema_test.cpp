// Structural errors of the glTF JSON name their JSON pointer. tinygltf reported
// them without saying where ("'componentType' property is missing in Accessor.")
// or skipped them silently: a node's `mesh` or `children` of the wrong type
// dropped the mesh or the subtree, a primitive without `attributes` vanished.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <functional>

#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;

std::string GlbError(const std::function<void(nlohmann::json&)>& edit) {
  GltfBuilder b = test::SquareBuilder();
  edit(b.json());
  TempDir dir;
  b.WriteGlb(dir / "bad.glb");
  return ErrorOf([&] { LoadGltf(dir / "bad.glb", "bad.glb"); });
}

TEST(GltfSchema, ErrorsNameTheirPointer) {
  // Loaded without the mesh, without the child, without the primitive before.
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["mesh"] = "0"; }),
            "bad.glb: /nodes/0/mesh: must be an integer, got \"0\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["children"] = "1"; }),
            "bad.glb: /nodes/0/children: must be an array of node indices, got \"1\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["children"] = {1.5}; }),
            "bad.glb: /nodes/0/children/0: must be a node index (an integer), got 1.5");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["meshes"][0]["primitives"][0].erase("attributes"); }),
            "bad.glb: /meshes/0/primitives/0: missing required property \"attributes\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = "1"; }),
            "bad.glb: /meshes/0/primitives/0/attributes/NORMAL: must be an accessor index (an integer), got \"1\"");
  // Refused by tinygltf before, without the place.
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["bufferViews"][0]["byteStride"] = 6; }),
            "bad.glb: /bufferViews/0/byteStride: must be a multiple of 4, got 6");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["bufferViews"][0]["byteStride"] = 256; }),
            "bad.glb: /bufferViews/0/byteStride: must be an integer in [4, 252], got 256");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["bufferViews"][1].erase("byteLength"); }),
            "bad.glb: /bufferViews/1: missing required property \"byteLength\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][1].erase("componentType"); }),
            "bad.glb: /accessors/1: missing required property \"componentType\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][1]["componentType"] = 5124; }),
            "bad.glb: /accessors/1/componentType: must be 5120 (byte), 5121 (unsigned byte), 5122 (short), 5123 "
            "(unsigned short), 5125 (unsigned int) or 5126 (float), got 5124");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][1]["type"] = "VEC5"; }),
            "bad.glb: /accessors/1/type: must be \"SCALAR\", \"VEC2\", \"VEC3\", \"VEC4\", \"MAT2\", \"MAT3\" or "
            "\"MAT4\", got \"VEC5\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][0]["count"] = "4"; }),
            "bad.glb: /accessors/0/count: must be an integer, got \"4\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][0]["count"] = 4.0; }),
            "bad.glb: /accessors/0/count: must be an integer, got 4.0");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"] = {{"a", 1}}; }), "bad.glb: /accessors: must be an array");
}

}  // namespace
}  // namespace lt
