// Material textures the renderer does not sample (metallic-roughness, emissive,
// specular-glossiness) still scale their factors (glTF 2.0 3.9.2, 3.9.5): each
// factor is multiplied by its texture's mean texel. Blender, Sketchfab and the
// Khronos sample models write factor 1 beside such a texture; the factor alone
// made every painted part a rough metal and a part with a few glowing texels glow
// all over. Expected values below are computed by hand from the 2x2 images.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>

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

// A 2x2 RGBA PNG `name` in dir with the given texels (row by row), as image 0 and texture 0.
GltfBuilder SquareWithTexture(const TempDir& dir, const std::vector<std::array<uint8_t, 4>>& texels) {
  Image<uint8_t> img(2, 2, 4, 0);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 4; ++c) img.At(i % 2, i / 2, c) = texels[size_t(i)][size_t(c)];
  }
  WriteImage(dir / "tex.png", img);
  GltfBuilder b = test::SquareBuilder(true, true);
  b.json()["images"] = {{{"uri", "tex.png"}}};
  b.json()["textures"] = {{{"source", 0}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = 0;
  return b;
}

// Blender's export of a Principled BSDF with a metallic and a roughness map:
// factors 1 and a texture with roughness in G, metallic in B (linear, not sRGB).
TEST(GltfMaterialTextures, MetallicRoughnessTextureScalesTheFactors) {
  TempDir dir;
  GltfBuilder b = SquareWithTexture(dir, {{0, 255, 0, 255}, {0, 128, 0, 255}, {0, 0, 0, 255}, {0, 128, 255, 255}});
  const int mat = b.AddMaterial("painted", {1, 1, 1, 1}, 1, 0.8);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
  const GltfAsset a = LoadWrittenGltf(b, dir);
  ASSERT_EQ(a.materials.size(), 1u);
  // metallic = 1 * mean(B) = 255/255/4; roughness = 0.8 * mean(G) = 0.8 * (255 + 128 + 0 + 128)/255/4.
  EXPECT_FLOAT_EQ(a.materials[0].metallic, 0.25f);
  EXPECT_FLOAT_EQ(a.materials[0].roughness, float(0.8 * 511.0 / 1020.0));
  EXPECT_THAT(AllWarnings(a), HasSubstr("model.gltf: material \"painted\": metallic-roughness texture not sampled, "
                                        "its mean used: metallic 1 x 0.25, roughness 0.8 x 0.501"));
}

// Emission is factor * strength * texture, the texture sRGB-encoded: one white and
// one sRGB-128 texel (linear 0.2158605) of four.
TEST(GltfMaterialTextures, EmissiveTextureScalesTheFactor) {
  TempDir dir;
  GltfBuilder b = SquareWithTexture(dir, {{255, 255, 255, 255}, {0, 0, 0, 255}, {0, 0, 0, 255}, {128, 128, 128, 255}});
  const int mat = b.AddMaterial("lamp", {1, 1, 1, 1}, 0, 0.5, {1, 0.5, 0});
  b.json()["materials"][size_t(mat)]["emissiveTexture"] = {{"index", 0}};
  b.json()["materials"][size_t(mat)]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4}}}};
  const GltfAsset a = LoadWrittenGltf(b, dir);
  const float mean = float((1.0 + 0.2158605) / 4);
  EXPECT_TRUE(a.materials[0].emissive.isApprox(Eigen::Vector3f(4 * mean, 2 * mean, 0), 1e-5f))
      << a.materials[0].emissive.transpose();
  EXPECT_EQ(a.materials[0].metallic, 0.0f);  // no metallic-roughness texture: the factors as written
  EXPECT_EQ(a.materials[0].roughness, 0.5f);
  EXPECT_THAT(AllWarnings(a), HasSubstr("material \"lamp\": emissive texture not sampled, its mean used"));
}

// KHR_materials_pbrSpecularGlossiness: glossiness = glossinessFactor * the texture's
// alpha (linear); its metallic-roughness fallback values are not used.
TEST(GltfMaterialTextures, SpecularGlossinessTextureScalesTheGlossiness) {
  TempDir dir;
  GltfBuilder b = SquareWithTexture(dir, {{10, 10, 10, 255}, {10, 10, 10, 0}, {10, 10, 10, 255}, {10, 10, 10, 0}});
  const int mat = b.AddMaterial("shiny", {1, 1, 1, 1}, 1, 1);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
  b.json()["materials"][size_t(mat)]["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {
      {"glossinessFactor", 0.8}, {"specularGlossinessTexture", {{"index", 0}}}};
  const GltfAsset a = LoadWrittenGltf(b, dir);
  EXPECT_EQ(a.materials[0].metallic, 0.0f);
  EXPECT_FLOAT_EQ(a.materials[0].roughness, 1 - 0.8f * 0.5f);
  EXPECT_THAT(AllWarnings(a), HasSubstr("specular-glossiness texture not sampled, its mean used: glossiness 0.8 x 0.5"));
}

// A texture that cannot be read leaves the factor alone (it was never needed to
// render), with a warning saying why; a texture that does not exist is an error.
TEST(GltfMaterialTextures, UnreadableTextureKeepsTheFactor) {
  TempDir dir;
  GltfBuilder b = SquareWithTexture(dir, {{0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}});
  test::WriteText(dir / "tex.webp", std::string("RIFF\x10\0\0\0WEBPVP8 ", 16));
  b.json()["images"][0]["uri"] = "tex.webp";
  const int mat = b.AddMaterial("rough", {1, 1, 1, 1}, 0.5, 0.7, {0.25, 0.25, 0.25});
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
  b.json()["materials"][size_t(mat)]["emissiveTexture"] = {{"index", 0}};
  const GltfAsset a = LoadWrittenGltf(b, dir);
  EXPECT_EQ(a.materials[0].metallic, 0.5f);
  EXPECT_EQ(a.materials[0].roughness, 0.7f);
  EXPECT_EQ(a.materials[0].emissive, Eigen::Vector3f::Constant(0.25f));
  EXPECT_THAT(AllWarnings(a), HasSubstr("metallic-roughness texture ignored (image 0: cannot decode the image: WebP"));

  b.json()["materials"][size_t(mat)]["emissiveTexture"]["index"] = 3;
  b.WriteGltf(dir / "model.gltf", false);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "model.gltf", "model.gltf"); }),
              HasSubstr("model.gltf: /materials/0/emissiveTexture/index: texture 3 does not exist (1 textures)"));
}

}  // namespace
}  // namespace lt
