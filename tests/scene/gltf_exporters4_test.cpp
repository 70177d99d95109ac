// Features found in the fourth pass over real files (docs/scene-format.md, "Real
// files checked, fourth pass"): 3D Tiles' CESIUM_RTC centre, a required
// KHR_animation_pointer, material factors outside [0, 1], and the messages for a
// skin's inverse bind matrix that is not finite and a COLOR_0 of the wrong type.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::AllWarnings;
using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;

// b3dm tiles' glTF (py3dtiles, FME, Cesium's converters) hold positions relative
// to a CESIUM_RTC centre in ECEF metres, which 3D Tiles add after turning the
// file's y up to z up: not a translation in the file's frame. The extension was
// ignored without a word (a tile's placement silently lost) and a file requiring
// it was refused; now it loads where its positions put it, with a warning giving
// the centre, and a centre that is not 3 finite numbers is an error naming it.
TEST(GltfExporters4, CesiumRtcCentreIsNamedNotApplied) {
  TempDir dir;
  for (bool required : {false, true}) {
    GltfBuilder b = test::SquareBuilder();
    b.json()["extensions"]["CESIUM_RTC"]["center"] = {1215012.8, -4736313.0, 4081605.2};
    b.json()["extensionsUsed"] = {"CESIUM_RTC"};
    if (required) b.json()["extensionsRequired"] = {"CESIUM_RTC"};
    b.WriteGltf(dir / "tile.gltf", true);
    const GltfAsset a = LoadGltf(dir / "tile.gltf", "tile.gltf");
    ASSERT_EQ(a.instances.size(), 1u) << required;
    EXPECT_TRUE(a.instances[0].file_from_mesh.matrix().isIdentity()) << required;
    EXPECT_THAT(AllWarnings(a), HasSubstr("tile.gltf: CESIUM_RTC: the centre [1215012.8, -4736313, 4081605.2] m is "
                                          "not applied"))
        << required;
  }
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensions"]["CESIUM_RTC"]["center"] = {1.0, 2.0};
  b.WriteGltf(dir / "bad.gltf", true);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "bad.gltf", "bad.gltf"); }),
            "bad.gltf: /extensions/CESIUM_RTC/center: must be an array of 3 finite numbers");
}

// KHR_animation_pointer animates any property (a material's colour, a node's
// visibility). Animations are not played, so a file requiring it loads as
// written, with the warning that counts the animations; it was refused
// ('required extension "KHR_animation_pointer" is not supported').
TEST(GltfExporters4, RequiredAnimationPointerLoadsTheStillPose) {
  GltfBuilder b = test::SquareBuilder();
  const int times = b.AddFloats({0, 1}, "SCALAR");
  const int colours = b.AddFloats({1, 0, 0, 1, 0, 1, 0, 1}, "VEC4");
  b.json()["animations"] = {
      {{"channels", {{{"sampler", 0},
                      {"target", {{"path", "pointer"},
                                  {"extensions", {{"KHR_animation_pointer",
                                                   {{"pointer", "/materials/0/pbrMetallicRoughness/baseColorFactor"}}}}}}}}}},
       {"samplers", {{{"input", times}, {"output", colours}}}}}};
  b.json()["extensionsUsed"] = {"KHR_animation_pointer"};
  b.json()["extensionsRequired"] = {"KHR_animation_pointer"};
  TempDir dir;
  b.WriteGltf(dir / "pointer.gltf", true);
  const GltfAsset a = LoadGltf(dir / "pointer.gltf", "pointer.gltf");
  ASSERT_EQ(a.instances.size(), 1u);
  EXPECT_THAT(AllWarnings(a), HasSubstr("pointer.gltf: 1 animation not played"));
}

// An inverse bind matrix holding a NaN was refused as 'must be affine (last row
// 0 0 0 1)' wherever the NaN was, sending the reader to the wrong row.
TEST(GltfExporters4, NonFiniteInverseBindMatrixIsNamedAsSuch) {
  GltfBuilder b = test::SquareBuilder();
  std::vector<float> joints(16, 0.0f), weights(16, 0.0f);
  for (int v = 0; v < 4; ++v) weights[size_t(4 * v)] = 1;
  const int ja = b.AddAccessor(b.AddBufferView(std::vector<uint8_t>(16, 0).data(), 16), 5121, 4, "VEC4");
  auto& attributes = b.json()["meshes"][0]["primitives"][0]["attributes"];
  attributes["JOINTS_0"] = ja;
  attributes["WEIGHTS_0"] = b.AddFloats(weights, "VEC4");
  b.json()["nodes"][0]["skin"] = 0;
  b.json()["nodes"].push_back({{"name", "bone"}});
  b.json()["scenes"][0]["nodes"] = {0, 1};
  std::vector<float> ibm = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  ibm[12] = std::numeric_limits<float>::quiet_NaN();  // the translation's x
  const int ibm_acc = b.AddFloats(ibm, "MAT4");
  b.json()["skins"] = {{{"joints", {1}}, {"inverseBindMatrices", ibm_acc}}};
  TempDir dir;
  b.WriteGltf(dir / "skin.gltf", true);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "skin.gltf", "skin.gltf"); }),
            "skin.gltf: /accessors/" + std::to_string(ibm_acc) +
                ": inverse bind matrix 0 is not finite (nan at column 3, row 0)");
}

// COLOR_0 is VEC3 or VEC4; a SCALAR one was refused as 'type must be VEC3',
// as if VEC4 were not allowed.
TEST(GltfExporters4, ColourOfWrongTypeNamesBothTypesAllowed) {
  GltfBuilder b = test::SquareBuilder();
  const int acc = b.AddFloats({1, 1, 1, 1}, "SCALAR");
  b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = acc;
  TempDir dir;
  b.WriteGltf(dir / "grey.gltf", true);
  EXPECT_EQ(ErrorOf([&] { LoadGltf(dir / "grey.gltf", "grey.gltf"); }),
            "grey.gltf: /accessors/" + std::to_string(acc) + ": COLOR_0 must be VEC3 or VEC4 (glTF 3.7.2.1), got SCALAR");
}

// Babylon.js's 3ds Max exporter wrote a roughnessFactor of -90.47056 (its
// LeakDetector and FLIREx models); writers of doubles from floats write
// 1.0000000298. Any factor outside [0, 1] refused the whole file, even for an
// object whose scene-file "material" replaces the file's: now clamped, with one
// warning naming each place beyond float noise.
TEST(GltfExporters4, MaterialFactorsOutsideTheirRangeAreClampedAndNamed) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("max", {1.0000000298, 0.5, 0.5, 1}, 1.5, -90.47056);
  TempDir dir;
  b.WriteGltf(dir / "max.gltf", true);
  const GltfAsset a = LoadGltf(dir / "max.gltf", "max.gltf");
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(a.materials[0].base_color[0], 1.0f);
  EXPECT_EQ(a.materials[0].metallic, 1.0f);
  EXPECT_EQ(a.materials[0].roughness, 0.0f);
  EXPECT_THAT(AllWarnings(a), HasSubstr("max.gltf: 2 material factors are outside glTF's range [0, 1] and clamped to "
                                        "it: /materials/0/pbrMetallicRoughness/metallicFactor "
                                        "1.5, /materials/0/pbrMetallicRoughness/roughnessFactor -90.47056\n"));
  EXPECT_THAT(AllWarnings(a), Not(HasSubstr("baseColorFactor")));
}

}  // namespace
}  // namespace lt
