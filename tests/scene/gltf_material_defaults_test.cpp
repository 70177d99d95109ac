// Materials that lean on glTF's defaults: a pbrMetallicRoughness without
// metallicFactor is metallic 1 (glTF 2.0 5.22). COLLADA2GLTF writes no factor for
// its Phong materials (the Khronos Box, BoxInterleaved), nor do KHR_materials_common
// materials (trimesh's TestScene); Blender's first exporter left it out too
// (MultiUVTest, OrientationTest). Such a part rendered as metal, its laser line a
// conductor's reflection (BoxInterleaved: 2 true centres, none measured), with no
// warning.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scene/gltf_loader.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

using test::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;

// Six squares, one per material: "plain" (base colour only), "bare" (no
// pbrMetallicRoughness at all), "metal" (metallicFactor 1 written), "mapped" (a
// metallic-roughness texture), "flat" (KHR_materials_unlit), "painted"
// (metallicFactor 0); and "spare", as "plain" but used by no triangle.
GltfBuilder SquaresOfEachMaterial() {
  GltfBuilder b;
  const std::vector<std::string> names = {"plain", "bare", "metal", "mapped", "flat", "painted", "spare"};
  for (const std::string& name : names) b.AddMaterial(name, {0.8, 0.2, 0.2, 1}, 0, 1);
  nlohmann::json& m = b.json()["materials"];
  for (size_t i : {0, 1, 3, 4, 6}) m[i]["pbrMetallicRoughness"].erase("metallicFactor");
  m[1].erase("pbrMetallicRoughness");
  m[2]["pbrMetallicRoughness"]["metallicFactor"] = 1.0;
  m[3]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
  m[4]["extensions"] = {{"KHR_materials_unlit", nlohmann::json::object()}};
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["images"] = {{{"uri", "missing.png"}}};  // never decoded: the mean texel is warned as unknown
  for (size_t i = 0; i + 1 < names.size(); ++i) {
    std::vector<float> p = test::SquarePositions();
    for (size_t k = 0; k < p.size(); k += 3) p[k] += float(2 * i);
    b.AddNode(names[i], b.AddTriangleMesh(names[i], p, test::SquareNormals(), {}, test::SquareIndices(), int(i)));
  }
  return b;
}

TEST(GltfMaterialDefaults, MaterialsWithoutMetallicFactorAreNamed) {
  TempDir dir;
  test::WriteText(dir / "missing.png", "not a png");
  SquaresOfEachMaterial().WriteGltf(dir / "parts.gltf", false);
  const GltfAsset a = LoadGltf(dir / "parts.gltf", "parts.gltf");
  ASSERT_EQ(a.materials.size(), 7u);
  EXPECT_EQ(a.materials[0].metallic, 1.0f);  // glTF's default, as the file says
  EXPECT_EQ(a.metallic_by_default, "materials \"plain\", \"bare\"");

  // The scene warns unless the object gives its own material.
  const std::string scene = R"({"objects": [{"name": "parts", "gltf": "parts.gltf"MATERIAL}],
    "materials": {"pla": {"base_color": [0.8, 0.8, 0.8], "metallic": 0, "roughness": 0.5}},
    "sensor": {"camera": {"resolution": [8, 8], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}}})";
  auto warnings = [&](const std::string& material) {
    std::string text = scene;
    text.replace(text.find("MATERIAL"), 8, material);
    test::WriteText(dir / "scene.json", text);
    std::string all;
    for (const auto& w : LoadSceneGeometry(LoadSceneFile(dir / "scene.json")).warnings) all += w + "\n";
    return all;
  };
  EXPECT_THAT(warnings(""), HasSubstr("object \"parts\": " + (dir / "parts.gltf").string() +
                                      ": no metallicFactor in materials \"plain\", \"bare\", which glTF then makes "
                                      "metal (metallic 1: a laser line on it is a conductor's reflection, not the "
                                      "diffuse line on plastic); give the object a \"material\" if the part is not "
                                      "metal"));
  EXPECT_THAT(warnings(R"(, "material": "pla")"), Not(HasSubstr("metallicFactor")));
}

}  // namespace
}  // namespace lt
