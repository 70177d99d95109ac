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
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][0]["count"] = 4.25; }),
            "bad.glb: /accessors/0/count: must be an integer, got 4.25");  // 4.0 is read (below)
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"] = {{"a", 1}}; }), "bad.glb: /accessors: must be an array");
}

// Numbers of the wrong type in a node's transform or a material: tinygltf keeps the
// numbers before a non-number and drops a value that is not an array or a number, so
// assimp's regression file malformed_node_scale.gltf ("scale": [2.0, "not-a-number",
// 3.0]) failed with "must have 3 elements", a "scale": 2 loaded unscaled, a
// "metallicFactor": "0" loaded as a metal and a string in baseColorFactor as white.
TEST(GltfSchema, MistypedNumbersNameTheirPointer) {
  auto with_material = [](nlohmann::json& j) {
    j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.8, 0.8, 1.0}}, {"metallicFactor", 0}}}}};
    j["meshes"][0]["primitives"][0]["material"] = 0;
  };
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["scale"] = {2.0, "not-a-number", 3.0}; }),
            "bad.glb: /nodes/0/scale/1: must be a number, got \"not-a-number\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["scale"] = 2; }),
            "bad.glb: /nodes/0/scale: must be an array of 3 numbers, got 2");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["translation"] = {0, 1}; }),
            "bad.glb: /nodes/0/translation: must be an array of 3 numbers, got 2 elements");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["weights"] = {"0.5"}; }),
            "bad.glb: /nodes/0/weights/0: must be a number, got \"0.5\"");
  EXPECT_EQ(GlbError([&](nlohmann::json& j) {
              with_material(j);
              j["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = "0";
            }),
            "bad.glb: /materials/0/pbrMetallicRoughness/metallicFactor: must be a number, got \"0\"");
  EXPECT_EQ(GlbError([&](nlohmann::json& j) {
              with_material(j);
              j["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][2] = "0.8";
            }),
            "bad.glb: /materials/0/pbrMetallicRoughness/baseColorFactor/2: must be a number, got \"0.8\"");
  EXPECT_EQ(GlbError([&](nlohmann::json& j) {
              with_material(j);
              j["materials"][0]["doubleSided"] = "true";
            }),
            "bad.glb: /materials/0/doubleSided: must be true or false, got \"true\"");
  EXPECT_EQ(GlbError([&](nlohmann::json& j) {
              with_material(j);
              j["materials"][0]["emissiveTexture"] = {{"index", "0"}};
            }),
            "bad.glb: /materials/0/emissiveTexture/index: must be an integer, got \"0\"");
  // Well-typed values still load.
  GltfBuilder b = test::SquareBuilder();
  with_material(b.json());
  b.json()["nodes"][0]["scale"] = {2, 2.0, 1};
  TempDir dir;
  b.WriteGlb(dir / "ok.glb");
  const GltfAsset asset = LoadGltf(dir / "ok.glb", "ok.glb");
  ASSERT_EQ(asset.materials.size(), 1u);
  EXPECT_FLOAT_EQ(asset.materials[0].metallic, 0.0f);
  ASSERT_EQ(asset.instances.size(), 1u);
  EXPECT_NEAR(asset.instances[0].file_from_mesh.linear()(0, 0), 2.0, 1e-12);
}

// assimp's regression files: malformed_sparse.gltf (a sparse accessor without
// "values") failed with tinygltf's "the sparse object of this accessor doesn't have
// values", no place; mixed_skin_joints.gltf (JOINTS_1 as unsigned ints) with
// "JOINTS_1 must be unsigned bytes or shorts, not normalized", not saying what it is.
TEST(GltfSchema, SparseAndJointsErrorsSayWhatIsWrong) {
  EXPECT_EQ(GlbError([](nlohmann::json& j) {
              j["accessors"][0]["sparse"] = {{"count", 1}, {"indices", {{"bufferView", 0}, {"componentType", 5121}}}};
            }),
            "bad.glb: /accessors/0/sparse: missing required property \"values\"");
  EXPECT_EQ(GlbError([](nlohmann::json& j) {
              j["accessors"][0]["sparse"] = {{"count", 1}, {"indices", {{"componentType", 5121}}}, {"values", {{"bufferView", 0}}}};
            }),
            "bad.glb: /accessors/0/sparse/indices: missing required property \"bufferView\"");
  GltfBuilder b = test::SquareBuilder();
  const std::vector<uint32_t> joints(16, 0);
  const int jv = b.AddBufferView(joints.data(), joints.size() * sizeof(uint32_t));
  auto& attributes = b.json()["meshes"][0]["primitives"][0]["attributes"];
  attributes["JOINTS_0"] = b.AddAccessor(jv, 5125, 4, "VEC4");
  attributes["WEIGHTS_0"] = b.AddFloats({1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0}, "VEC4");
  b.json()["nodes"][0]["skin"] = 0;
  b.json()["nodes"].push_back({{"name", "joint"}});
  b.json()["skins"] = {{{"joints", {1}}}};
  TempDir dir;
  b.WriteGlb(dir / "bad.glb");
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "bad.glb", "bad.glb"); }),
            "bad.glb: /accessors/" + std::to_string(attributes["JOINTS_0"].get<int>()) +
                ": JOINTS_0 must be unsigned bytes or shorts (componentType 5121 or 5123) without \"normalized\" "
                "(glTF 3.7.3.1), got componentType 5125");
}

// glTF 2.0, "JSON encoding": an integer property MAY be written as a decimal with a
// zero fractional part or with an exponent. Writers whose numbers are all doubles
// (Python code dividing byte counts, JavaScript) write "count": 4.0; cesium-native
// and the glTF validator's schema read them, tinygltf refused them and so did the
// loader ("/accessors/0/count: must be an integer, got 4.0"). Every integer of a
// square with a child node is written as a decimal here, as .glb and as .gltf.
TEST(GltfSchema, IntegersWrittenAsDecimalsAreRead) {
  GltfBuilder b = test::SquareBuilder();
  b.AddNode("child", 0, {2, 0, 0}, false);
  b.json()["nodes"][0]["children"] = {1};
  std::function<void(nlohmann::json&)> as_decimals = [&](nlohmann::json& j) {
    if (j.is_number_integer() || j.is_number_unsigned()) j = j.get<double>();
    if (j.is_structured()) {
      for (auto& e : j) as_decimals(e);
    }
  };
  as_decimals(b.json());
  ASSERT_TRUE(b.json()["accessors"][0]["count"].is_number_float());
  TempDir dir;
  b.WriteGlb(dir / "decimals.glb");
  b.WriteGltf(dir / "decimals.gltf", true);
  for (const char* name : {"decimals.glb", "decimals.gltf"}) {
    const GltfAsset a = LoadGltf(dir / name, name);
    ASSERT_EQ(a.meshes.size(), 1u) << name;
    EXPECT_EQ(a.meshes[0].TriangleCount(), 2u) << name;
    ASSERT_EQ(a.instances.size(), 2u) << name;
    EXPECT_TRUE(a.instances[1].file_from_mesh.translation().isApprox(Eigen::Vector3d(2, 0, 0))) << name;
  }
  // A fractional part is still an error, in a list too.
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["accessors"][0]["count"] = 4.5; }),
            "bad.glb: /accessors/0/count: must be an integer, got 4.5");
  EXPECT_EQ(GlbError([](nlohmann::json& j) { j["nodes"][0]["children"] = {0.0, 1.5}; }),
            "bad.glb: /nodes/0/children/1: must be a node index (an integer), got 1.5");
}

}  // namespace
}  // namespace lt
