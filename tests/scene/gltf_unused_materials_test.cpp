// Materials, textures and images that no triangle uses (gltf_used.h). Exporters write
// whole material libraries (pygltflib, CAD appearances, Blender's fake-user
// materials): a file loads for what its triangles use. What nothing uses is not read
// (no image file looked for or decoded), not warned about, and keeps its material id;
// a dangling reference is still refused wherever it is, with its pointer. Before, a
// missing or undecodable image of an unused material refused the whole file, and an
// unused material's metallic-roughness texture and factors were warned about.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

#include "core/image_io.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::AllWarnings;
using test::ErrorOf;
using test::TempDir;
using test::LoadWrittenGltf;
using ::testing::HasSubstr;

// A square using material "used" (its base colour texture: texture 0, image 0 =
// used.png, 2x2, written), beside a library material "library" that no triangle
// uses, whose base colour texture is texture 1 (image 1 = `library_uri`, not written).
GltfBuilder Library(const TempDir& dir, const std::string& library_uri) {
  WriteImage(dir / "used.png", Image<uint8_t>(2, 2, 4, 200));
  GltfBuilder b = test::SquareBuilder(true, true);
  const int used = b.AddMaterial("used", {1, 1, 1, 1}, 0, 0.5);
  const int library = b.AddMaterial("library", {0.2, 0.4, 0.6, 1}, 0, 0.3);
  b.json()["images"] = {{{"uri", "used.png"}}, {{"uri", library_uri}}};
  b.json()["textures"] = {{{"source", 0}}, {{"source", 1}}};
  b.json()["materials"][size_t(used)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["materials"][size_t(library)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 1}};
  b.json()["meshes"][0]["primitives"][0]["material"] = used;
  return b;
}

// pygltflib's material library: the unused material's image file is missing.
TEST(GltfUnused, AMissingImageOfAnUnusedMaterialIsNotLookedFor) {
  TempDir dir;
  const GltfAsset a = LoadWrittenGltf(Library(dir, "textures/library.png"), dir);
  EXPECT_EQ(AllWarnings(a), "");
  ASSERT_EQ(a.materials.size(), 2u);  // the unused one keeps its id
  ASSERT_TRUE(a.materials[0].base_color_texture);
  EXPECT_EQ(a.materials[0].base_color_texture->image.width, 2);
  EXPECT_EQ(a.materials[0].base_color_texture->image.pixels[0], 200);
  EXPECT_EQ(a.materials[1].name, "library");
  EXPECT_FALSE(a.materials[1].base_color_texture);
  EXPECT_EQ(a.materials[1].base_color, Eigen::Vector3f(0.2f, 0.4f, 0.6f));  // its factors, as written
  for (const Mesh& m : a.meshes) {
    for (uint32_t id : m.triangle_material) EXPECT_EQ(id, 0u);
  }
  // Used, the same missing file refuses the file, as before.
  GltfBuilder b = Library(dir, "textures/library.png");
  b.json()["meshes"][0]["primitives"][0]["material"] = 1;
  EXPECT_THAT(ErrorOf([&] { LoadWrittenGltf(b, dir); }),
              HasSubstr("model.gltf: /images/1/uri: texture image file not found (looked for "));
  // Nor is a remote uri of an unused image refused.
  EXPECT_EQ(AllWarnings(LoadWrittenGltf(Library(dir, "https://example.com/library.png"), dir)), "");
}

// A material used only by a mesh that no node of the scene places, or only by points
// or lines (skipped), is unused too.
TEST(GltfUnused, MaterialsOfUnplacedMeshesAndOfPointsAreUnused) {
  TempDir dir;
  GltfBuilder b = Library(dir, "missing.png");
  b.AddTriangleMesh("spare", test::SquarePositions(), test::SquareNormals(), test::SquareTexcoords(),
                    test::SquareIndices(), 1);
  b.AddNode("unplaced", 1, {}, false);  // in no scene
  EXPECT_EQ(AllWarnings(LoadWrittenGltf(b, dir)), "");
  b.json()["meshes"][0]["primitives"].push_back(b.json()["meshes"][0]["primitives"][0]);
  b.json()["meshes"][0]["primitives"][1]["material"] = 1;
  b.json()["meshes"][0]["primitives"][1]["mode"] = 0;  // points
  const GltfAsset a = LoadWrittenGltf(b, dir);
  EXPECT_THAT(AllWarnings(a), HasSubstr("points skipped"));
  EXPECT_THAT(AllWarnings(a), ::testing::Not(HasSubstr("missing.png")));
  // As triangles, it is used: its image is looked for.
  b.json()["meshes"][0]["primitives"][1]["mode"] = 4;
  EXPECT_THAT(ErrorOf([&] { LoadWrittenGltf(b, dir); }), HasSubstr("/images/1/uri: texture image file not found"));
}

// The warnings of a material's reader (textures not sampled, factors clamped,
// extensions ignored or converted, no metallicFactor) are for used materials only.
TEST(GltfUnused, AnUnusedMaterialIsNotWarnedAbout) {
  TempDir dir;
  GltfBuilder b = Library(dir, "used.png");
  auto& lib = b.json()["materials"][1];
  lib["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
  lib["emissiveTexture"] = {{"index", 0}};
  lib["normalTexture"] = {{"index", 1}};
  lib["pbrMetallicRoughness"]["roughnessFactor"] = 1.5;  // clamped
  lib["extensions"]["KHR_materials_clearcoat"] = nlohmann::json::object();
  lib["extensions"]["KHR_materials_transmission"] = {{"transmissionFactor", 0.5}};
  lib["extensions"]["KHR_materials_unlit"] = nlohmann::json::object();
  b.AddMaterial("no_metallic", {1, 1, 1, 1}, 0, 0.5);
  b.json()["materials"][2]["pbrMetallicRoughness"].erase("metallicFactor");
  b.json()["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_materials_transmission", "KHR_materials_unlit"};
  const GltfAsset a = LoadWrittenGltf(b, dir);
  EXPECT_EQ(AllWarnings(a), "");
  EXPECT_EQ(a.metallic_by_default, "");
  ASSERT_EQ(a.materials.size(), 3u);
  EXPECT_EQ(a.materials[1].roughness, 1.0f);
  // Used, each is warned about, as before.
  b.json()["meshes"][0]["primitives"][0]["material"] = 1;
  const std::string warnings = AllWarnings(LoadWrittenGltf(b, dir));
  EXPECT_THAT(warnings, HasSubstr("KHR_materials_clearcoat ignored (not rendered), used by material \"library\""));
  EXPECT_THAT(warnings, HasSubstr("KHR_materials_unlit"));
  EXPECT_THAT(warnings, HasSubstr("/materials/1/pbrMetallicRoughness/roughnessFactor 1.5"));
  EXPECT_THAT(warnings, HasSubstr("ignored normal texture"));
  b.json()["meshes"][0]["primitives"][0]["material"] = 2;
  EXPECT_THAT(LoadWrittenGltf(b, dir).metallic_by_default, "material \"no_metallic\"");
}

// The metallic-roughness texture of an unused material (the warning of the last
// glTF pass): no "texture not sampled, its mean used".
TEST(GltfUnused, AnUnusedMetallicRoughnessTextureIsNotWarned) {
  TempDir dir;
  GltfBuilder b = Library(dir, "used.png");
  b.json()["materials"][1]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
  EXPECT_EQ(AllWarnings(LoadWrittenGltf(b, dir)), "");
  b.json()["materials"][0]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 1}};
  EXPECT_THAT(AllWarnings(LoadWrittenGltf(b, dir)),
              HasSubstr("model.gltf: material \"used\": metallic-roughness texture not sampled, its mean used"));
}

// An unused image whose bytes are no image (a data: URI, and a GLB's buffer view) is
// not decoded; used, it is refused by its pointer.
TEST(GltfUnused, AnUnusedImageThatDoesNotDecodeIsNotRead) {
  TempDir dir;
  GltfBuilder b = Library(dir, "data:image/png;base64,AAAAAAAA");
  EXPECT_EQ(AllWarnings(LoadWrittenGltf(b, dir)), "");
  const std::vector<uint8_t> junk(64, 7);
  const int view = b.AddBufferView(junk.data(), junk.size());
  b.json()["images"][1] = {{"bufferView", view}, {"mimeType", "image/png"}};
  b.WriteGlb(dir / "model.glb");
  EXPECT_EQ(AllWarnings(LoadGltf(dir / "model.glb", "model.glb")), "");
  b.json()["meshes"][0]["primitives"][0]["material"] = 1;
  b.WriteGlb(dir / "model.glb");
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "model.glb", "model.glb"); }),
              HasSubstr("model.glb: /images/1: cannot decode the image"));
}

// A dangling reference makes the file malformed for every reader (glTF-Validator's
// UNRESOLVED_REFERENCE): refused, with its pointer, whether or not anything uses it.
// Before, an unused texture's missing sampler or image was never looked at.
TEST(GltfUnused, ADanglingReferenceIsRefusedUsedOrNot) {
  TempDir dir;
  GltfBuilder b = Library(dir, "used.png");
  b.json()["textures"].push_back({{"source", 0}, {"sampler", 3}});  // texture 2: no material uses it
  EXPECT_EQ(ErrorOf([&] { LoadWrittenGltf(b, dir); }), "model.gltf: /textures/2/sampler: sampler 3 does not exist (0 samplers)");
  b.json()["textures"][2] = {{"source", 5}};
  EXPECT_EQ(ErrorOf([&] { LoadWrittenGltf(b, dir); }), "model.gltf: /textures/2/source: image 5 does not exist (2 images)");
  b.json()["textures"].erase(2);
  b.json()["materials"][1]["emissiveTexture"] = {{"index", 4}};  // of the unused material
  EXPECT_EQ(ErrorOf([&] { LoadWrittenGltf(b, dir); }), "model.gltf: /materials/1/emissiveTexture/index: texture 4 does not exist (2 textures)");
}

}  // namespace
}  // namespace lt
