// Materials and textures: sRGB decoding, bilinear filtering and wrap modes against
// closed forms.
#include "scene/material.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scene/mesh.h"

namespace lt {
namespace {

TEST(Srgb, MatchesTheStandardTransferFunction) {
  EXPECT_EQ(SrgbToLinear(0), 0.0f);
  EXPECT_EQ(SrgbToLinear(255), 1.0f);
  EXPECT_NEAR(SrgbToLinear(10), 10 / 255.0 / 12.92, 1e-7);  // linear segment below 0.04045
  EXPECT_NEAR(SrgbToLinear(128), std::pow((128 / 255.0 + 0.055) / 1.055, 2.4), 1e-7);
  EXPECT_NEAR(SrgbToLinear(188), 0.5, 0.003);  // sRGB 188 is about half intensity
}

// A 4x1 texture whose red channel is 0, 255, 0, 255 (so its linear value is 0 or 1).
Texture Stripes(WrapMode s, WrapMode t) {
  Texture tex;
  tex.image = Image<uint8_t>(4, 1, 4, 255);
  for (int x = 0; x < 4; ++x) tex.image.At(x, 0, 0) = x % 2 ? 255 : 0;
  tex.wrap_s = s;
  tex.wrap_t = t;
  return tex;
}

TEST(Texture, BilinearBetweenTexelCentres) {
  Texture tex = Stripes(WrapMode::kClampToEdge, WrapMode::kClampToEdge);
  // Texel x has its centre at u = (x + 0.5) / 4.
  EXPECT_FLOAT_EQ(tex.Sample({0.125f, 0.5f}).x(), 0.0f);
  EXPECT_FLOAT_EQ(tex.Sample({0.375f, 0.5f}).x(), 1.0f);
  // A quarter of the way from texel 0 to texel 1: linear weights, in linear space.
  EXPECT_NEAR(tex.Sample({0.125f + 0.0625f, 0.5f}).x(), 0.25, 1e-6);
  EXPECT_NEAR(tex.Sample({0.25f, 0.5f}).x(), 0.5, 1e-6);
  EXPECT_FLOAT_EQ(tex.Sample({0.25f, 0.5f}).w(), 1.0f);  // alpha is linear
}

TEST(Texture, WrapModes) {
  // Repeat: u and u + 1 agree; between the last and the first texel it blends them.
  Texture rep = Stripes(WrapMode::kRepeat, WrapMode::kRepeat);
  EXPECT_NEAR(rep.Sample({0.375f + 1.0f, 0.5f}).x(), 1.0, 1e-5);
  EXPECT_NEAR(rep.Sample({0.375f - 3.0f, 0.5f}).x(), 1.0, 1e-5);
  EXPECT_NEAR(rep.Sample({0.0f, 0.5f}).x(), 0.5, 1e-6);  // half texel 3 (1), half texel 0 (0)
  // Clamp: beyond the edge the edge texel.
  Texture clamp = Stripes(WrapMode::kClampToEdge, WrapMode::kClampToEdge);
  EXPECT_FLOAT_EQ(clamp.Sample({-5.0f, 0.5f}).x(), 0.0f);
  EXPECT_FLOAT_EQ(clamp.Sample({7.0f, 0.5f}).x(), 1.0f);
  EXPECT_FLOAT_EQ(clamp.Sample({1e30f, 0.5f}).x(), 1.0f);
  // Mirrored repeat: u in [1, 2] reads the texture backwards, so the centre of
  // texel 3 repeats at u = 1.125 and texel 2 at u = 1.375.
  Texture mirror = Stripes(WrapMode::kMirroredRepeat, WrapMode::kMirroredRepeat);
  EXPECT_FLOAT_EQ(mirror.Sample({1.125f, 0.5f}).x(), 1.0f);   // texel 3
  EXPECT_FLOAT_EQ(mirror.Sample({1.375f, 0.5f}).x(), 0.0f);   // texel 2
  EXPECT_FLOAT_EQ(mirror.Sample({-0.125f, 0.5f}).x(), 0.0f);  // texel 0 mirrored
  EXPECT_FLOAT_EQ(mirror.Sample({1.0f, 0.5f}).x(), 1.0f);     // between texel 3 and its mirror
  // Non-finite coordinates do not crash and give a texel value.
  float v = rep.Sample({std::nanf(""), 0.5f}).x();
  EXPECT_TRUE(v >= 0.0f && v <= 1.0f);
}

TEST(Material, BaseColourTimesTexture) {
  Material m;
  m.base_color = {0.5f, 1.0f, 1.0f};
  EXPECT_EQ(m.BaseColorAt({0.3f, 0.3f}), m.base_color);
  m.base_color_texture = std::make_shared<Texture>(Stripes(WrapMode::kRepeat, WrapMode::kRepeat));
  EXPECT_FLOAT_EQ(m.BaseColorAt({0.375f, 0.5f}).x(), 0.5f);
  EXPECT_FLOAT_EQ(m.BaseColorAt({0.125f, 0.5f}).x(), 0.0f);
}

TEST(Material, CheckRejectsOutOfRangeValues) {
  Material m;
  EXPECT_NO_THROW(m.Check());
  m.roughness = 1.5f;
  EXPECT_THROW(m.Check(), std::invalid_argument);
  m.roughness = 0.5f;
  m.emissive.x() = -1;
  EXPECT_THROW(m.Check(), std::invalid_argument);
  m.emissive.x() = 0;
  m.subsurface = Subsurface{Eigen::Vector3d(1e-3, 0, 1e-3), 1e-3};
  EXPECT_THROW(m.Check(), std::invalid_argument);
  m.subsurface->mean_free_path_m.y() = 1e-3;
  EXPECT_NO_THROW(m.Check());
}

TEST(Mesh, DegenerateTriangles) {
  Eigen::Vector3f a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_FALSE(IsDegenerateTriangle(a, b, c));
  EXPECT_TRUE(IsDegenerateTriangle(a, a, c));
  EXPECT_TRUE(IsDegenerateTriangle(a, b, Eigen::Vector3f(2, 0, 0)));  // collinear
  EXPECT_TRUE(IsDegenerateTriangle(a, a, a));
  // A thin but real sliver (height 1e-4 of its length) is kept.
  EXPECT_FALSE(IsDegenerateTriangle(a, b, Eigen::Vector3f(0.5f, 1e-4f, 0)));
  EXPECT_TRUE(FaceNormal(a, b, c).isApprox(Eigen::Vector3d(0, 0, 1)));
}

}  // namespace
}  // namespace lt
