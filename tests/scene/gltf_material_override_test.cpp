// An object with its own "material" needs none of its glTF file's materials: the
// file is loaded without them (GltfLoadOptions::materials), so materials that cannot
// be read (a KTX2 or DDS texture, a missing image file, a refused material extension)
// no longer refuse a file whose look the scene replaces. Before, each such file was
// refused whatever the object's "material".
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <string>
#include <vector>

#include "core/image_io.h"
#include "scene/gltf_loader.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;

// A square whose one material ("look") has a base-colour texture (image 0, `uri`),
// placed by a node with an inexact translation and rotation (they go through the
// JSON rewrite that drops the materials).
GltfBuilder TexturedSquare(const std::string& uri) {
  GltfBuilder b;
  const int mat = b.AddMaterial("look", {0.8, 0.2, 0.2, 1}, 0, 0.5);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b.json()["samplers"] = {{{"wrapS", 33071}}};
  b.json()["images"] = {{{"uri", uri}}};
  const int mesh = b.AddTriangleMesh("square", test::SquarePositions(), test::SquareNormals(),
                                     test::SquareTexcoords(), test::SquareIndices(), mat);
  const int node = b.AddNode("square_node", mesh, {0.1, -0.3, 0.7000000000000001});
  b.json()["nodes"][size_t(node)]["rotation"] = {0.1, 0.2, 0.3, 0.9273618495495703};
  return b;
}

void Require(GltfBuilder* b, const std::string& extension) {
  b->json()["extensionsUsed"].push_back(extension);
  b->json()["extensionsRequired"].push_back(extension);
}

// A scene of one object per entry: {name, gltf file name, material or ""}; its
// material "pla" has the base_color_texture `pla_texture` if one is given.
std::string SceneText(const std::vector<std::array<std::string, 3>>& objects, const std::string& pla_texture = "") {
  std::string list;
  for (const auto& [name, gltf, material] : objects) {
    list += std::string(list.empty() ? "" : ", ") + R"({"name": ")" + name + R"(", "gltf": ")" + gltf + "\"" +
            (material.empty() ? "" : R"(, "material": ")" + material + "\"") + "}";
  }
  return R"({"objects": [)" + list + R"(],
    "materials": {"pla": {"base_color": [0.8, 0.8, 0.8], "metallic": 0, "roughness": 0.5)" +
         (pla_texture.empty() ? "" : R"(, "base_color_texture": ")" + pla_texture + "\"") + R"(}},
    "sensor": {"camera": {"resolution": [8, 8], "pixel_pitch_um": 5, "focal_length_mm": 4, "f_number": 4}}})";
}

SceneGeometry LoadScene(const TempDir& dir, const std::vector<std::array<std::string, 3>>& objects,
                        const std::string& pla_texture = "") {
  test::WriteText(dir / "scene.json", SceneText(objects, pla_texture));
  return LoadSceneGeometry(LoadSceneFile(dir / "scene.json"));
}

std::string AllWarnings(const std::vector<std::string>& warnings) {
  std::string s;
  for (const auto& w : warnings) s += w + "\n";
  return s;
}

// The file loads for an object with a material, quietly, its triangles taking it;
// without one it is refused with `error`.
void ExpectLoadsOnlyWithAMaterial(const TempDir& dir, const std::string& gltf, const std::string& error) {
  SCOPED_TRACE(gltf);
  const SceneGeometry g = LoadScene(dir, {{"part", gltf, "pla"}});
  ASSERT_EQ(g.instances.size(), 1u);
  EXPECT_EQ(g.InstancedTriangleCount(), 2u);
  EXPECT_EQ(g.instances[0].material_override, 0);
  ASSERT_EQ(g.materials.size(), 1u);  // the scene's "pla" alone
  EXPECT_EQ(g.materials[0].name, "pla");
  EXPECT_EQ(g.meshes[0].triangle_material, std::vector<uint32_t>(2, 0u));
  EXPECT_TRUE(g.warnings.empty()) << AllWarnings(g.warnings);
  EXPECT_THAT(ErrorOf([&] { LoadScene(dir, {{"part", gltf, ""}}); }), HasSubstr(error));
}

TEST(GltfMaterialOverride, Ktx2TextureIsNotReadForAnObjectWithAMaterial) {
  TempDir dir;
  std::vector<uint8_t> ktx2(80, 0);
  std::memcpy(ktx2.data(), "\xABKTX 20\xBB\r\n\x1A\n", 12);
  test::WriteBytes(dir / "look.ktx2", ktx2);
  GltfBuilder b = TexturedSquare("look.ktx2");
  b.json()["images"][0]["mimeType"] = "image/ktx2";
  b.json()["textures"][0].erase("source");
  b.json()["textures"][0]["extensions"]["KHR_texture_basisu"] = {{"source", 0}};
  Require(&b, "KHR_texture_basisu");
  b.WriteGltf(dir / "part.gltf", false);
  ExpectLoadsOnlyWithAMaterial(dir, "part.gltf",
                               "part.gltf: /extensionsRequired/0: required extension \"KHR_texture_basisu\" is not "
                               "supported (the textures are KTX2: write or convert them as PNG or JPEG)");
  // Not required (a PNG fallback left out): the image, undecodable, is named.
  b.json().erase("extensionsRequired");
  b.WriteGlb(dir / "part.glb");
  ExpectLoadsOnlyWithAMaterial(dir, "part.glb", "/textures/0");
}

TEST(GltfMaterialOverride, MissingTextureFileIsNotLookedForForAnObjectWithAMaterial) {
  TempDir dir;
  TexturedSquare("textures/look.png").WriteGltf(dir / "part.gltf", false);
  ExpectLoadsOnlyWithAMaterial(dir, "part.gltf", "part.gltf: /images/0/uri: texture image file not found");
}

// Required extensions of materials and textures alone are accepted without
// materials; those of the geometry are refused as before.
TEST(GltfMaterialOverride, OnlyMaterialExtensionsAreAcceptedWithoutMaterials) {
  TempDir dir;
  WriteImage(dir / "look.png", Image<uint8_t>(1, 1, 4, 255));
  for (const std::string ext : {"MSFT_texture_dds", "EXT_texture_webp", "KHR_materials_clearcoat"}) {
    GltfBuilder b = TexturedSquare("look.png");
    Require(&b, ext);
    b.WriteGltf(dir / "part.gltf", false);
    ExpectLoadsOnlyWithAMaterial(dir, "part.gltf", "required extension \"" + ext + "\" is not supported");
  }
  for (const std::string ext : {"KHR_draco_mesh_compression", "EXT_meshopt_compression"}) {
    GltfBuilder b = TexturedSquare("look.png");
    Require(&b, ext);
    b.WriteGltf(dir / "part.gltf", false);
    EXPECT_THAT(ErrorOf([&] { LoadScene(dir, {{"part", "part.gltf", "pla"}}); }),
                HasSubstr("/extensionsRequired/0: required extension \"" + ext + "\" is not supported"));
  }
}

// A malformed material and an ignored feature (a normal texture, material variants)
// say nothing for an object with a material.
TEST(GltfMaterialOverride, MaterialsAreNotCheckedNorWarnedAbout) {
  TempDir dir;
  WriteImage(dir / "look.png", Image<uint8_t>(1, 1, 4, 255));
  GltfBuilder b = TexturedSquare("look.png");
  b.json()["materials"][0]["normalTexture"] = {{"index", 0}};
  b.json()["extensions"]["KHR_materials_variants"] = {{"variants", {{{"name", "red"}}}}};
  b.json()["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"] = {
      {{"material", 0}, {"variants", {0}}}};
  b.WriteGltf(dir / "part.gltf", false);
  const SceneGeometry quiet = LoadScene(dir, {{"part", "part.gltf", "pla"}});
  EXPECT_TRUE(quiet.warnings.empty()) << AllWarnings(quiet.warnings);
  const SceneGeometry own = LoadScene(dir, {{"part", "part.gltf", ""}});
  EXPECT_THAT(AllWarnings(own.warnings), HasSubstr("KHR_materials_variants"));

  b.json()["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] = "0";
  b.WriteGltf(dir / "part.gltf", false);
  ExpectLoadsOnlyWithAMaterial(dir, "part.gltf", "/materials/0/pbrMetallicRoughness/metallicFactor");
}

// One file used by an object with a material and, after it, by one without: the
// second keeps the file's materials.
TEST(GltfMaterialOverride, SharedFileKeepsItsMaterialsForAnObjectWithout) {
  TempDir dir;
  WriteImage(dir / "look.png", Image<uint8_t>(1, 1, 4, 255));
  TexturedSquare("look.png").WriteGltf(dir / "part.gltf", false);
  const SceneGeometry g = LoadScene(dir, {{"a", "part.gltf", "pla"}, {"b", "part.gltf", ""}});
  ASSERT_EQ(g.meshes.size(), 1u);  // loaded once
  ASSERT_EQ(g.instances.size(), 2u);
  EXPECT_EQ(g.materials[g.MaterialOf(g.instances[0], 0)].name, "pla");
  const Material& look = g.materials[g.MaterialOf(g.instances[1], 0)];
  EXPECT_EQ(look.name, "look");
  EXPECT_NE(look.base_color_texture, nullptr);
  EXPECT_TRUE(g.warnings.empty()) << AllWarnings(g.warnings);
}

// An object with its own material reads TEXCOORD_0, whichever other objects use
// the file: here the file's material reads TEXCOORD_1 (Blender's second UV map).
// Before, the object read TEXCOORD_0 alone but TEXCOORD_1 beside an object taking
// the file's materials (the file was loaded once, with them).
TEST(GltfMaterialOverride, OwnMaterialReadsTexcoord0WhateverTheOtherObjects) {
  TempDir dir;
  WriteImage(dir / "look.png", Image<uint8_t>(1, 1, 4, 255));
  GltfBuilder b = TexturedSquare("look.png");
  const std::vector<float> second = {0.5f, 0.5f, 0.75f, 0.5f, 0.75f, 0.25f, 0.5f, 0.25f};
  b.json()["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] = b.AddFloats(second, "VEC2");
  b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["texCoord"] = 1;
  b.WriteGltf(dir / "part.gltf", false);
  std::vector<Eigen::Vector2f> set0, set1;
  for (size_t i = 0; i < 4; ++i) {
    set0.emplace_back(test::SquareTexcoords()[2 * i], test::SquareTexcoords()[2 * i + 1]);
    set1.emplace_back(second[2 * i], second[2 * i + 1]);
  }
  // "pla" reads a texture of its own, at the object's TEXCOORD_0.
  const SceneGeometry alone = LoadScene(dir, {{"a", "part.gltf", "pla"}}, "look.png");
  ASSERT_EQ(alone.instances.size(), 1u);
  EXPECT_EQ(alone.meshes[alone.instances[0].mesh].texcoords, set0);
  for (const bool own_first : {true, false}) {
    SCOPED_TRACE(own_first ? "the object with a material first" : "the object with a material second");
    const SceneGeometry g = own_first ? LoadScene(dir, {{"a", "part.gltf", "pla"}, {"b", "part.gltf", ""}}, "look.png")
                                      : LoadScene(dir, {{"b", "part.gltf", ""}, {"a", "part.gltf", "pla"}}, "look.png");
    ASSERT_EQ(g.instances.size(), 2u);
    const SceneInstance& a = g.instances[own_first ? 0 : 1];
    const SceneInstance& other = g.instances[own_first ? 1 : 0];
    EXPECT_EQ(g.materials[g.MaterialOf(a, 0)].name, "pla");
    EXPECT_EQ(g.meshes[a.mesh].texcoords, set0);
    EXPECT_EQ(g.materials[g.MaterialOf(other, 0)].name, "look");
    EXPECT_EQ(g.meshes[other.mesh].texcoords, set1);
    EXPECT_EQ(g.InstancedTriangleCount(), 4u);
    EXPECT_TRUE(g.warnings.empty()) << AllWarnings(g.warnings);  // the second load repeats none
    EXPECT_EQ(g.materials.size(), 2u);                            // "pla", "look": no ids for the second load
    EXPECT_EQ(g.meshes.size(), 2u);                               // the second load's mesh
  }
  // Without a texture nothing reads the object's texture coordinates: it shares the
  // file's one load (before, a second load of the geometry alone, its mesh counted
  // again in info's unique triangles).
  for (const bool own_first : {true, false}) {
    SCOPED_TRACE(own_first ? "untextured, the object with a material first" : "untextured, the object second");
    const SceneGeometry g = own_first ? LoadScene(dir, {{"a", "part.gltf", "pla"}, {"b", "part.gltf", ""}})
                                      : LoadScene(dir, {{"b", "part.gltf", ""}, {"a", "part.gltf", "pla"}});
    ASSERT_EQ(g.instances.size(), 2u);
    EXPECT_EQ(g.meshes.size(), 1u);
    EXPECT_EQ(g.instances[0].mesh, g.instances[1].mesh);
    const SceneInstance& a = g.instances[own_first ? 0 : 1];
    const SceneInstance& other = g.instances[own_first ? 1 : 0];
    EXPECT_EQ(g.materials[g.MaterialOf(a, 0)].name, "pla");
    EXPECT_EQ(g.materials[g.MaterialOf(other, 0)].name, "look");
    EXPECT_EQ(g.UniqueTriangleCount(), 2u);
    EXPECT_EQ(g.InstancedTriangleCount(), 4u);
    EXPECT_TRUE(g.warnings.empty()) << AllWarnings(g.warnings);
  }
  // A file whose materials read TEXCOORD_0 is still loaded once for both.
  TexturedSquare("look.png").WriteGltf(dir / "part.gltf", false);
  EXPECT_EQ(LoadScene(dir, {{"a", "part.gltf", "pla"}, {"b", "part.gltf", ""}}).meshes.size(), 1u);
}

void ExpectSameGeometry(const GltfAsset& with, const GltfAsset& without) {
  ASSERT_EQ(with.meshes.size(), without.meshes.size());
  for (size_t i = 0; i < with.meshes.size(); ++i) {
    const Mesh& a = with.meshes[i];
    const Mesh& b = without.meshes[i];
    EXPECT_EQ(a.indices, b.indices) << i;
    ASSERT_EQ(a.positions.size(), b.positions.size()) << i;
    EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * sizeof(a.positions[0])), 0)
        << i;
    EXPECT_EQ(a.normals, b.normals) << i;
    EXPECT_EQ(a.texcoords, b.texcoords) << i;  // TEXCOORD_0 both ways: the files' materials read set 0
    EXPECT_EQ(a.colors, b.colors) << i;
    EXPECT_EQ(b.triangle_material, std::vector<uint32_t>(b.TriangleCount(), 0u)) << i;
  }
  ASSERT_EQ(with.instances.size(), without.instances.size());
  for (size_t i = 0; i < with.instances.size(); ++i) {
    EXPECT_EQ(with.instances[i].mesh, without.instances[i].mesh);
    EXPECT_EQ(with.instances[i].node_name, without.instances[i].node_name);
    EXPECT_TRUE(with.instances[i].file_from_mesh.matrix() == without.instances[i].file_from_mesh.matrix()) << i;
  }
  EXPECT_EQ(with.degenerate_triangles, without.degenerate_triangles);
  ASSERT_EQ(without.materials.size(), 1u);  // the placeholder
  EXPECT_FALSE(without.uses_default_material);
  EXPECT_TRUE(without.metallic_by_default.empty());
}

TEST(GltfMaterialOverride, GeometryIsReadAsWithMaterials) {
  TempDir dir;
  WriteImage(dir / "look.png", Image<uint8_t>(1, 1, 4, 255));
  GltfBuilder b = TexturedSquare("look.png");
  b.AddNode("second", 0, {1e-3, 2.5, -0.25});
  b.WriteGltf(dir / "part.gltf", true);
  GltfLoadOptions geometry_only;
  geometry_only.materials = false;
  ExpectSameGeometry(LoadGltf(dir / "part.gltf"), LoadGltf(dir / "part.gltf", "", geometry_only));
  // The demo's part, as written by the generator (a GLB with materials).
  const std::filesystem::path demo = std::filesystem::path(LT_SOURCE_DIR) / "scenes/demo/test_part.glb";
  ExpectSameGeometry(LoadGltf(demo), LoadGltf(demo, "", geometry_only));

  // Through a scene: the same triangle counts and exact bounds.
  const SceneGeometry own = LoadScene(dir, {{"part", "part.gltf", ""}});
  const SceneGeometry pla = LoadScene(dir, {{"part", "part.gltf", "pla"}});
  EXPECT_EQ(own.InstancedTriangleCount(), 4u);
  EXPECT_EQ(pla.InstancedTriangleCount(), own.InstancedTriangleCount());
  EXPECT_EQ(pla.UniqueTriangleCount(), own.UniqueTriangleCount());
  EXPECT_TRUE(pla.WorldBounds().min() == own.WorldBounds().min());
  EXPECT_TRUE(pla.WorldBounds().max() == own.WorldBounds().max());
}

}  // namespace
}  // namespace lt
