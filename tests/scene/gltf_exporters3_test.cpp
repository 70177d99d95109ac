// Features of real exporters' files found in the third pass over real files
// (docs/scene-format.md, "Real files checked, third pass"): extensions a file
// requires that are read or ignored by design (lights, transmission, material
// variants, node visibility), KHR_meshopt_compression, the primitive-restart
// value, old exporters' byteStride values and image data: URIs of other media types.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "core/base64.h"
#include "core/image_io.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::AllWarnings;
using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;
using ::testing::Not;

// The Khronos DirectionalLight sample (Blender I/O 1.7.33 + manual edit) requires
// KHR_lights_punctual. Lights are ignored by design (the scene file sets the
// lights), so requiring them changes nothing here: the file was refused
// ('required extension "KHR_lights_punctual" is not supported') and now loads
// with the warning that counts the lights.
TEST(GltfExporters3, RequiredPunctualLightsAreIgnoredAsLightsAre) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {
      {{"type", "directional"}, {"color", {0.9, 0.8, 0.1}}, {"intensity", 1}, {"name", "Sun"}}};
  b.AddNode("Sun_Orientation", -1);
  b.json()["nodes"][1]["extensions"]["KHR_lights_punctual"] = {{"light", 0}};
  b.json()["extensionsUsed"] = {"KHR_lights_punctual"};
  b.json()["extensionsRequired"] = {"KHR_lights_punctual"};
  b.WriteGltf(dir / "lit.gltf", true);
  GltfAsset a = LoadGltf(dir / "lit.gltf", "lit.gltf");
  ASSERT_EQ(a.instances.size(), 1u);
  EXPECT_EQ(a.meshes[0].indices.size(), 6u);
  EXPECT_THAT(AllWarnings(a), HasSubstr("lit.gltf: 1 KHR_lights_punctual light ignored (the scene file sets the "
                                        "sensor and the lights)"));
}

// KHR_materials_transmission is read (its diffuse share removed,
// gltf_exporters_test.cpp); a file requiring it was refused all the same.
TEST(GltfExporters3, RequiredTransmissionIsRead) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("clear", {0.8, 0.4, 0.2, 1}, 0, 0.1);
  b.json()["materials"][0]["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", 1.0}};
  b.json()["extensionsUsed"] = {"KHR_materials_transmission"};
  b.json()["extensionsRequired"] = {"KHR_materials_transmission"};
  b.WriteGltf(dir / "clear.gltf", true);
  GltfAsset a = LoadGltf(dir / "clear.gltf", "clear.gltf");
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(a.materials[0].base_color, Eigen::Vector3f::Zero());
  EXPECT_THAT(AllWarnings(a), HasSubstr("KHR_materials_transmission: transmitted light is not traced"));
}

// gltfpack 1.0 writes the ratified KHR_meshopt_compression (the Khronos
// BrainStem glTF-Meshopt: required, a fallback buffer without uri), earlier
// versions EXT_meshopt_compression. Only the EXT_ name was known: required, the
// refusal gave no hint; its fallback buffer was 'buffer has no uri (a .gltf
// buffer needs one)'.
TEST(GltfExporters3, KhrMeshoptIsRefusedAsExtMeshoptIs) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensionsUsed"] = {"KHR_mesh_quantization", "KHR_meshopt_compression"};
  b.json()["extensionsRequired"] = {"KHR_mesh_quantization", "KHR_meshopt_compression"};
  b.WriteGltf(dir / "packed.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "packed.gltf", "packed.gltf"); }),
              HasSubstr("packed.gltf: /extensionsRequired/1: required extension \"KHR_meshopt_compression\" is not "
                        "supported (the buffers are meshopt-compressed: write the file without it, e.g. gltfpack "
                        "without -c/-cc)"));

  b.json()["extensionsRequired"] = {"KHR_mesh_quantization"};
  b.json()["buffers"] = {{{"byteLength", 4}, {"uri", "data:application/octet-stream;base64,AAAAAA=="}},
                         {{"byteLength", b.bin().size()}, {"extensions", {{"KHR_meshopt_compression", {{"fallback", true}}}}}}};
  for (auto& view : b.json()["bufferViews"]) view["buffer"] = 1;
  b.WriteGltf(dir / "packed.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "packed.gltf", "packed.gltf"); }),
              HasSubstr("packed.gltf: /buffers/1: the buffer holds no data: it is the fallback buffer of "
                        "KHR_meshopt_compression, whose compressed data is not supported"));
}

// Blender I/O 3.3.2's KHR_materials_variants test file requires the extension.
// glTF shows a primitive's own "material" when no variant is chosen, so the
// file loads with its default materials and a warning; it was refused.
TEST(GltfExporters3, RequiredMaterialVariantsShowTheDefaultMaterials) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  b.AddMaterial("Red", {1, 0, 0, 1}, 0, 0.4);
  b.json()["meshes"][0]["primitives"][0]["material"] = b.AddMaterial("Blue", {0, 0, 1, 1}, 0, 0.4);
  b.json()["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = {
      {{"material", 0}, {"variants", {0}}}, {{"material", 1}, {"variants", {1}}}};
  b.json()["extensions"]["KHR_materials_variants"]["variants"] = {{{"name", "Variant_Red"}}, {{"name", "Variant_Blue"}}};
  b.json()["extensionsUsed"] = {"KHR_materials_variants"};
  b.json()["extensionsRequired"] = {"KHR_materials_variants"};
  b.WriteGltf(dir / "variants.gltf", true);
  GltfAsset a = LoadGltf(dir / "variants.gltf", "variants.gltf");
  ASSERT_EQ(a.meshes.size(), 1u);
  for (uint32_t m : a.meshes[0].triangle_material) EXPECT_EQ(a.materials.at(m).name, "Blue");
  EXPECT_THAT(AllWarnings(a), HasSubstr("variants.gltf: KHR_materials_variants: 2 variants not applied; each "
                                        "primitive has its default material (its \"material\")"));
}

// OpenGL ES 3 and WebGL 2 restart a strip at the largest index value; glTF forbids
// that value in indices. A strip written with one is refused as before, and the
// message now says what the value is (it only said "past the vertex count").
TEST(GltfExporters3, PrimitiveRestartValueIsNamed) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();
  auto& prim = b.json()["meshes"][0]["primitives"][0];
  prim["mode"] = 5;
  prim["indices"] = b.AddIndices({0, 1, 3, 2, 65535, 0, 1, 3}, 5123);
  b.WriteGltf(dir / "strip.gltf", true);
  const std::string error = ErrorOf([&] { LoadGltf(dir / "strip.gltf", "strip.gltf"); });
  EXPECT_THAT(error, HasSubstr("strip.gltf: /accessors/3: index 65535 (element 4) is past the vertex count 4 (the "
                               "primitive-restart value, which glTF does not allow in indices"));

  prim["indices"] = b.AddIndices({0, 1, 3, 2, 255, 0}, 5121);
  b.WriteGltf(dir / "strip.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "strip.gltf", "strip.gltf"); }), HasSubstr("primitive-restart value"));
  prim["indices"] = b.AddIndices({0, 1, 3, 2, 254, 0}, 5121);  // an index merely out of range
  b.WriteGltf(dir / "strip.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "strip.gltf", "strip.gltf"); }),
              Not(HasSubstr("primitive-restart value")));
}

// KHR_node_visibility, as Godot 4.6 writes it (the Khronos CubeVisibility sample:
// required): a node written "visible": false hides itself and its descendants.
// The file was refused; loading it whole would show the hidden parts.
TEST(GltfExporters3, NodeVisibilityHidesTheNodeAndItsDescendants) {
  TempDir dir;
  GltfBuilder b = test::SquareBuilder();  // node 0: "square_node", a root
  const int hidden = b.AddNode("InvisibleCube", 0, {-1.5, 0, 0});
  const int child = b.AddNode("ChildOfInvisible", 0, {0, 1.5, 0}, false);
  const int grandchild = b.AddNode("DescendantOfInvisible", 0, {0, 1.5, 0}, false);
  const int shown = b.AddNode("AnimatedVisibility", 0, {1.5, 0, 0});
  b.json()["nodes"][size_t(hidden)]["children"] = {child};
  b.json()["nodes"][size_t(child)]["children"] = {grandchild};
  b.json()["nodes"][size_t(hidden)]["extensions"]["KHR_node_visibility"] = {{"visible", false}};
  b.json()["nodes"][size_t(shown)]["extensions"]["KHR_node_visibility"] = {{"visible", true}};
  b.json()["extensionsUsed"] = {"KHR_node_visibility"};
  b.json()["extensionsRequired"] = {"KHR_node_visibility"};
  b.WriteGltf(dir / "vis.gltf", true);
  GltfAsset a = LoadGltf(dir / "vis.gltf", "vis.gltf");
  ASSERT_EQ(a.instances.size(), 2u);
  EXPECT_EQ(a.instances[0].node_name, "square_node");
  EXPECT_EQ(a.instances[1].node_name, "AnimatedVisibility");
  EXPECT_THAT(AllWarnings(a), HasSubstr("vis.gltf: 1 node hidden by KHR_node_visibility (\"visible\": false) not "
                                        "loaded, with their descendants: \"InvisibleCube\""));

  b.json()["nodes"][size_t(hidden)]["extensions"]["KHR_node_visibility"]["visible"] = 0;
  b.WriteGltf(dir / "vis.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "vis.gltf", "vis.gltf"); }),
              HasSubstr("vis.gltf: /nodes/1/extensions/KHR_node_visibility/visible: must be true or false"));
}

// byteStride values glTF refuses but exporters wrote and viewers read: 2 on a view
// of unsigned short indices (three.js's GLTFExporter before r89; glTF gives
// byteStride to vertex attributes only) and 0 (Google Poly's exports; CesiumJS,
// three.js and gltf-rs read it as absent). Both files were refused
// ('/bufferViews/3/byteStride: must be an integer in [4, 252], got 2').
TEST(GltfExporters3, HarmlessByteStridesOfOldExportersAreRead) {
  for (const bool glb : {false, true}) {
    TempDir dir;
    GltfBuilder b = test::SquareBuilder();
    auto& prim = b.json()["meshes"][0]["primitives"][0];
    prim["indices"] = b.AddIndices(test::SquareIndices(), 5123);
    const size_t index_view = b.json()["accessors"][3]["bufferView"].get<size_t>();
    b.json()["bufferViews"][index_view]["byteStride"] = 2;
    b.json()["bufferViews"][0]["byteStride"] = 0;  // the positions, tightly packed
    const std::string name = glb ? "old.glb" : "old.gltf";
    if (glb) {
      b.WriteGlb(dir / name);
    } else {
      b.WriteGltf(dir / name, true);
    }
    GltfAsset a = LoadGltf(dir / name, name);
    ASSERT_EQ(a.meshes.size(), 1u);
    EXPECT_EQ(a.meshes[0].indices.size(), 6u);
    EXPECT_EQ(a.meshes[0].positions[2], Eigen::Vector3f(1, 1, 0));
    EXPECT_THAT(AllWarnings(a), HasSubstr(name + ": byteStride 0 read as tightly packed (glTF asks for 4 to 252 or "
                                                 "none) in 1 buffer view: /bufferViews/0/byteStride"));
    EXPECT_THAT(AllWarnings(a), HasSubstr(name + ": byteStride of views read only as indices ignored (glTF gives it "
                                                 "to vertex attributes only; it equals the index size) in 1 buffer "
                                                 "view: /bufferViews/" + std::to_string(index_view) +
                                                 "/byteStride (2)"));

    // A stride that is not the index size, or on a view of vertices, is refused as before.
    b.json()["bufferViews"][index_view]["byteStride"] = 6;
    b.WriteGltf(dir / "bad.gltf", true);
    EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "bad.gltf", "bad.gltf"); }),
                HasSubstr("bad.gltf: /bufferViews/" + std::to_string(index_view) + "/byteStride: must be a multiple of 4, got 6"));
    b.json()["bufferViews"][index_view]["byteStride"] = 2;
    b.json()["bufferViews"][0]["byteStride"] = 2;
    b.WriteGltf(dir / "bad.gltf", true);
    EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "bad.gltf", "bad.gltf"); }),
                HasSubstr("bad.gltf: /bufferViews/0/byteStride: must be an integer in [4, 252], got 2"));
  }
}

// An image data: URI is decoded by its content, whatever its media type says, as
// browsers (three.js) and Blender read it: "image/jpg" (not a media type) holding a
// PNG was "image could not be loaded from "data:image/jpg;base64,..."" (tinygltf
// took the URI for a file name), and a WebP so embedded gave the same message
// instead of saying it is WebP.
TEST(GltfExporters3, ImageDataUrisAreDecodedByTheirContent) {
  TempDir dir;
  WriteImage(dir / "tex.png", Image<uint8_t>(2, 2, 4, 200));
  std::ifstream in(dir / "tex.png", std::ios::binary);
  const std::vector<uint8_t> png((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  GltfBuilder b = test::SquareBuilder(true, true);
  b.json()["textures"] = {{{"source", 0}}};
  int mat = b.AddMaterial("labelled", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  for (const char* label : {"image/jpg", "image/png;charset=binary", "", "image/jpeg"}) {
    b.json()["images"] = {{{"uri", std::string("data:") + label + ";base64," + Base64Encode(png.data(), png.size())}}};
    b.WriteGltf(dir / "img.gltf", true);
    GltfAsset a = LoadGltf(dir / "img.gltf", "img.gltf");
    ASSERT_EQ(a.materials.size(), 1u) << label;
    ASSERT_NE(a.materials[0].base_color_texture, nullptr) << label;
    EXPECT_EQ(a.materials[0].base_color_texture->image.width, 2) << label;
  }
  const std::vector<uint8_t> webp = {'R', 'I', 'F', 'F', 30, 0, 0, 0, 'W', 'E', 'B', 'P', 'V', 'P', '8', ' ', 0, 0};
  b.json()["images"] = {{{"uri", "data:image/webp;base64," + Base64Encode(webp.data(), webp.size())}}};
  b.WriteGltf(dir / "img.gltf", true);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "img.gltf", "img.gltf"); }),
              HasSubstr("img.gltf: /images/0: cannot decode the image: WebP"));
}

}  // namespace
}  // namespace lt
