// glTF loading: every supported feature on small files built in the test.
#include "scene/gltf_loader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/image_io.h"
#include "scene/embree_scene.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::EndsWith;
using ::testing::HasSubstr;

enum class Format { kGlb, kGltfExternal, kGltfEmbedded };

GltfAsset LoadBuilt(const GltfBuilder& b, const TempDir& dir, Format format, const std::string& stem = "model") {
  std::filesystem::path path;
  switch (format) {
    case Format::kGlb:
      path = dir / (stem + ".glb");
      b.WriteGlb(path);
      break;
    case Format::kGltfExternal:
      path = dir / (stem + ".gltf");
      b.WriteGltf(path, false);
      break;
    case Format::kGltfEmbedded:
      path = dir / (stem + ".gltf");
      b.WriteGltf(path, true);
      break;
  }
  return LoadGltf(path);
}

// The three corners of triangle t.
std::array<Eigen::Vector3f, 3> Corners(const Mesh& m, size_t t) {
  return {m.positions[m.indices[3 * t]], m.positions[m.indices[3 * t + 1]], m.positions[m.indices[3 * t + 2]]};
}

Eigen::Vector3d UnitFaceNormal(const Mesh& m, size_t t) {
  auto c = Corners(m, t);
  return FaceNormal(c[0], c[1], c[2]).normalized();
}

class GltfFormats : public ::testing::TestWithParam<Format> {};

TEST_P(GltfFormats, LoadsIndexedSquareWithNormalsAndTexcoords) {
  TempDir dir;
  GltfAsset a = LoadBuilt(test::SquareBuilder(true, true), dir, GetParam());
  ASSERT_EQ(a.meshes.size(), 1u);
  ASSERT_EQ(a.instances.size(), 1u);
  const Mesh& m = a.meshes[0];
  EXPECT_EQ(m.name, "square");
  EXPECT_EQ(m.TriangleCount(), 2u);
  EXPECT_EQ(m.VertexCount(), 4u);  // shared vertices kept when normals are given
  EXPECT_EQ(m.indices, test::SquareIndices());
  EXPECT_EQ(m.positions[2], Eigen::Vector3f(1, 1, 0));
  EXPECT_EQ(m.normals[3], Eigen::Vector3f(0, 0, 1));
  ASSERT_EQ(m.texcoords.size(), 4u);
  EXPECT_EQ(m.texcoords[1], Eigen::Vector2f(1, 1));
  EXPECT_EQ(a.instances[0].node_name, "square_node");
  EXPECT_TRUE(a.instances[0].file_from_mesh.matrix().isIdentity());
  EXPECT_EQ(a.degenerate_triangles, 0u);
  // No material in the file: the glTF default material is appended and used.
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_EQ(a.materials[0].name, "default");
  EXPECT_EQ(m.triangle_material, (std::vector<uint32_t>{0, 0}));
}

INSTANTIATE_TEST_SUITE_P(AllContainers, GltfFormats,
                         ::testing::Values(Format::kGlb, Format::kGltfExternal, Format::kGltfEmbedded));

class GltfIndexTypes : public ::testing::TestWithParam<int> {};

TEST_P(GltfIndexTypes, ReadsIndicesOfEveryWidth) {
  GltfBuilder b;
  int pos = b.AddFloats(test::SquarePositions(), "VEC3");
  int idx = b.AddIndices({0, 1, 2, 0, 2, 3}, GetParam());
  b.json()["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", pos}}}, {"indices", idx}}}}});
  b.AddNode("n", 0);
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].TriangleCount(), 2u);
  EXPECT_EQ(a.meshes[0].name, "mesh 0");
  // No normals: flat normals, so each triangle has its own three vertices.
  EXPECT_EQ(a.meshes[0].VertexCount(), 6u);
  auto c = Corners(a.meshes[0], 1);
  EXPECT_EQ(c[0], Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(c[1], Eigen::Vector3f(1, 1, 0));
  EXPECT_EQ(c[2], Eigen::Vector3f(0, 1, 0));
}

INSTANTIATE_TEST_SUITE_P(U8U16U32, GltfIndexTypes, ::testing::Values(5121, 5123, 5125));

TEST(GltfLoader, NonIndexedTrianglesGetFlatNormals) {
  GltfBuilder b;
  // Two triangles at different tilts, no normals, no indices.
  int mesh = b.AddTriangleMesh("tilted", {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 1}, {}, {}, {});
  b.AddNode("n", mesh);
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  const Mesh& m = a.meshes[0];
  ASSERT_EQ(m.TriangleCount(), 2u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(m.normals[m.indices[k]].isApprox(Eigen::Vector3f(0, 0, 1))) << k;
    EXPECT_TRUE(m.normals[m.indices[3 + k]].isApprox(Eigen::Vector3f(1, 0, 0))) << k;
  }
}

TEST(GltfLoader, TriangleStripFollowsGltfWinding) {
  GltfBuilder b;
  // Strip v0..v4: triangles {0,1,2}, {1,3,2}, {2,3,4} (glTF 2.0 3.7.2.1), all facing -z.
  std::vector<float> p = {0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0};
  int mesh = b.AddTriangleMesh("strip", p, {}, {}, {}, -1, 5);
  b.AddNode("n", mesh);
  TempDir dir;
  const Mesh m = LoadBuilt(b, dir, Format::kGlb).meshes[0];
  ASSERT_EQ(m.TriangleCount(), 3u);
  auto at = [&](int i) { return Eigen::Vector3f(p[3 * i], p[3 * i + 1], p[3 * i + 2]); };
  const int expected[3][3] = {{0, 1, 2}, {1, 3, 2}, {2, 3, 4}};
  for (size_t t = 0; t < 3; ++t) {
    auto c = Corners(m, t);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(c[k], at(expected[t][k])) << t << " " << k;
    EXPECT_TRUE(UnitFaceNormal(m, t).isApprox(Eigen::Vector3d(0, 0, -1)));
  }
}

TEST(GltfLoader, TriangleFanFollowsGltfWinding) {
  GltfBuilder b;
  // Fan around v0: triangles {1,2,0}, {2,3,0}, {3,4,0}, all facing +z.
  std::vector<float> p = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 1, 0};
  int mesh = b.AddTriangleMesh("fan", p, {}, {}, {0, 1, 2, 3, 4}, -1, 6);
  b.AddNode("n", mesh);
  TempDir dir;
  const Mesh m = LoadBuilt(b, dir, Format::kGltfEmbedded).meshes[0];
  ASSERT_EQ(m.TriangleCount(), 3u);
  auto at = [&](int i) { return Eigen::Vector3f(p[3 * i], p[3 * i + 1], p[3 * i + 2]); };
  const int expected[3][3] = {{1, 2, 0}, {2, 3, 0}, {3, 4, 0}};
  for (size_t t = 0; t < 3; ++t) {
    auto c = Corners(m, t);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(c[k], at(expected[t][k])) << t << " " << k;
    EXPECT_TRUE(UnitFaceNormal(m, t).isApprox(Eigen::Vector3d(0, 0, 1)));
  }
}

TEST(GltfLoader, NormalizedAccessors) {
  GltfBuilder b;
  // Positions as normalized signed shorts (KHR_mesh_quantization style): -32768
  // and -32767 both map to -1, 32767 to 1, 16384 to 16384/32767.
  std::vector<int16_t> pos = {-32768, 0, 0, 32767, 0, 0, 16384, -32767, 0, 0};  // 3 x VEC3, padded to 4 bytes
  int pv = b.AddBufferView(pos.data(), 9 * sizeof(int16_t));
  int pa = b.AddAccessor(pv, 5122, 3, "VEC3", true);
  // Texture coordinates as normalized unsigned bytes, VEC2 with a 4-byte stride.
  std::vector<uint8_t> uv = {0, 255, 0, 0, 255, 128, 0, 0, 51, 0, 0, 0};
  int uvv = b.AddBufferView(uv.data(), uv.size(), 4);
  int uva = b.AddAccessor(uvv, 5121, 3, "VEC2", true);
  b.json()["meshes"].push_back(
      {{"name", "q"}, {"primitives", {{{"attributes", {{"POSITION", pa}, {"TEXCOORD_0", uva}}}}}}});
  b.AddNode("n", 0);
  TempDir dir;
  const Mesh m = LoadBuilt(b, dir, Format::kGlb).meshes[0];
  ASSERT_EQ(m.TriangleCount(), 1u);
  EXPECT_EQ(m.positions[0], Eigen::Vector3f(-1, 0, 0));
  EXPECT_EQ(m.positions[1], Eigen::Vector3f(1, 0, 0));
  EXPECT_FLOAT_EQ(m.positions[2].x(), 16384.0f / 32767.0f);
  EXPECT_EQ(m.positions[2].y(), -1.0f);
  EXPECT_EQ(m.texcoords[0], Eigen::Vector2f(0, 1));
  EXPECT_FLOAT_EQ(m.texcoords[1].x(), 1.0f);
  EXPECT_FLOAT_EQ(m.texcoords[1].y(), 128.0f / 255.0f);
  EXPECT_FLOAT_EQ(m.texcoords[2].x(), 51.0f / 255.0f);
}

TEST(GltfLoader, SparseAccessorReplacesValues) {
  GltfBuilder b;
  int pa = b.AddFloats(test::SquarePositions(), "VEC3");
  std::vector<uint16_t> idx = {2, 0};  // one index, padded
  std::vector<float> val = {3, 4, 0};
  int iv = b.AddBufferView(idx.data(), 2);
  int vv = b.AddBufferView(val.data(), 12);
  b.json()["accessors"][size_t(pa)]["sparse"] = {
      {"count", 1}, {"indices", {{"bufferView", iv}, {"componentType", 5123}}}, {"values", {{"bufferView", vv}}}};
  int ia = b.AddIndices(test::SquareIndices());
  b.json()["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", pa}}}, {"indices", ia}}}}});
  b.AddNode("n", 0);
  TempDir dir;
  const Mesh m = LoadBuilt(b, dir, Format::kGlb).meshes[0];
  // Triangle 0 is {0, 1, 2} with vertex 2 moved to (3, 4, 0).
  auto c = Corners(m, 0);
  EXPECT_EQ(c[0], Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(c[1], Eigen::Vector3f(1, 0, 0));
  EXPECT_EQ(c[2], Eigen::Vector3f(3, 4, 0));
}

TEST(GltfLoader, SparseAccessorWithoutBufferViewStartsFromZeros) {
  GltfBuilder b;
  std::vector<uint8_t> idx = {1, 2, 3, 0};
  std::vector<float> val = {1, 0, 0, 1, 1, 0, 0, 1, 0};
  int iv = b.AddBufferView(idx.data(), 3);
  int vv = b.AddBufferView(val.data(), val.size() * 4);
  b.json()["accessors"].push_back({{"componentType", 5126},
                                   {"count", 4},
                                   {"type", "VEC3"},
                                   {"sparse",
                                    {{"count", 3},
                                     {"indices", {{"bufferView", iv}, {"componentType", 5121}}},
                                     {"values", {{"bufferView", vv}}}}}});
  int ia = b.AddIndices(test::SquareIndices());
  b.json()["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", ia}}}}});
  b.AddNode("n", 0);
  TempDir dir;
  const Mesh m = LoadBuilt(b, dir, Format::kGlb).meshes[0];
  ASSERT_EQ(m.TriangleCount(), 2u);
  auto c = Corners(m, 1);  // {0, 2, 3}
  EXPECT_EQ(c[0], Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(c[1], Eigen::Vector3f(1, 1, 0));
  EXPECT_EQ(c[2], Eigen::Vector3f(0, 1, 0));
}

// An accessor with neither a bufferView nor sparse values is all zeros (glTF 2.0 3.6.2.1).
TEST(GltfLoader, AccessorWithoutBufferViewOrSparseIsZeros) {
  GltfBuilder b = test::SquareBuilder(true, false);
  b.json()["accessors"].push_back({{"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
  b.json()["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = b.json()["accessors"].size() - 1;
  TempDir dir;
  const Mesh m = LoadBuilt(b, dir, Format::kGlb).meshes[0];
  ASSERT_EQ(m.TriangleCount(), 2u);
  ASSERT_EQ(m.texcoords.size(), 4u);
  for (const auto& uv : m.texcoords) EXPECT_EQ(uv, Eigen::Vector2f(0, 0));
}

// Exporters write float matrices: a last row off by float noise is accepted (and
// made exactly 0 0 0 1); a really projective one is refused (gltf_malformed_test).
TEST(GltfLoader, MatrixWithFloatNoiseInTheLastRowIsAccepted) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["nodes"][0]["matrix"] = {2, 0, 0, 1e-7, 0, 2, 0, -1e-7, 0, 0, 2, 2e-7, 5, 6, 7, 1.0000001};
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.instances.size(), 1u);
  Eigen::Matrix4d expected;
  expected << 2, 0, 0, 5, 0, 2, 0, 6, 0, 0, 2, 7, 0, 0, 0, 1;
  EXPECT_EQ(a.instances[0].file_from_mesh.matrix(), expected);
}

// glTF 2.0 asks only that an external buffer file is not shorter than byteLength.
TEST(GltfLoader, ExternalBufferLongerThanByteLengthIsAccepted) {
  TempDir dir;
  test::SquareBuilder(true, true).WriteGltf(dir / "m.gltf", false);
  const auto size = std::filesystem::file_size(dir / "m.bin");
  std::filesystem::resize_file(dir / "m.bin", size + 4);
  GltfAsset a = LoadGltf(dir / "m.gltf");
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].indices, test::SquareIndices());
  EXPECT_EQ(a.meshes[0].positions[2], Eigen::Vector3f(1, 1, 0));
}

TEST(GltfLoader, NodeHierarchyComposesTrsAndMatrixTransforms) {
  GltfBuilder b = test::SquareBuilder();
  // Root (translation) -> child (rotation + scale) -> the square's node becomes a
  // grandchild; a second root holds the same transform as one matrix.
  auto& nodes = b.json()["nodes"];
  const double s = std::sqrt(0.5);
  nodes[0]["name"] = "leaf";
  nodes.push_back({{"name", "child"}, {"rotation", {0, 0, s, s}}, {"scale", {2, 2, 2}}, {"children", {0}}});
  nodes.push_back({{"name", "root"}, {"translation", {10, 0, 0}}, {"children", {1}}});
  Eigen::Affine3d expected = Eigen::Translation3d(10, 0, 0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                             Eigen::Scaling(2.0);
  std::vector<double> column_major(expected.matrix().data(), expected.matrix().data() + 16);
  nodes.push_back({{"name", "matrix_node"}, {"matrix", column_major}, {"mesh", 0}});
  b.json()["scenes"][0]["nodes"] = {2, 3};
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.meshes.size(), 1u);  // one mesh, used by two nodes: loaded once
  ASSERT_EQ(a.instances.size(), 2u);
  EXPECT_EQ(a.instances[0].node_name, "leaf");
  EXPECT_EQ(a.instances[1].node_name, "matrix_node");
  EXPECT_EQ(a.instances[0].mesh, a.instances[1].mesh);
  for (const auto& inst : a.instances) {
    EXPECT_TRUE(inst.file_from_mesh.matrix().isApprox(expected.matrix(), 1e-12)) << inst.node_name;
    // The square's corner (1, 0, 0) lands at (10, 2, 0).
    EXPECT_TRUE((inst.file_from_mesh * Eigen::Vector3d(1, 0, 0)).isApprox(Eigen::Vector3d(10, 2, 0), 1e-12));
  }
}

TEST(GltfLoader, UsesTheDefaultSceneOnly) {
  GltfBuilder b = test::SquareBuilder();
  b.AddNode("other", 0, {5, 0, 0}, false);
  b.json()["scenes"].push_back({{"nodes", {1}}});
  b.json()["scene"] = 1;
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.instances.size(), 1u);
  EXPECT_EQ(a.instances[0].node_name, "other");
  EXPECT_EQ(a.instances[0].file_from_mesh.translation(), Eigen::Vector3d(5, 0, 0));
}

TEST(GltfLoader, SeveralPrimitivesKeepTheirMaterials) {
  GltfBuilder b;
  int red = b.AddMaterial("red", {1, 0, 0, 1}, 0, 0.5);
  int steel = b.AddMaterial("steel", {0.6, 0.6, 0.6, 1}, 1, 0.2);
  int p0 = b.AddFloats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  int p1 = b.AddFloats({0, 0, 1, 1, 0, 1, 0, 1, 1}, "VEC3");
  int p2 = b.AddFloats({0, 0, 2, 1, 0, 2, 0, 1, 2}, "VEC3");
  b.json()["meshes"].push_back({{"name", "multi"},
                                {"primitives",
                                 {{{"attributes", {{"POSITION", p0}}}, {"material", steel}},
                                  {{"attributes", {{"POSITION", p1}}}},
                                  {{"attributes", {{"POSITION", p2}}}, {"material", red}}}}});
  b.AddNode("n", 0);
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.meshes.size(), 1u);
  ASSERT_EQ(a.materials.size(), 3u);
  EXPECT_EQ(a.materials[0].name, "red");
  EXPECT_EQ(a.materials[1].name, "steel");
  EXPECT_EQ(a.materials[2].name, "default");
  EXPECT_EQ(a.meshes[0].triangle_material, (std::vector<uint32_t>{1, 2, 0}));
  EXPECT_EQ(Corners(a.meshes[0], 2)[0].z(), 2.0f);
  const Material& steel_m = a.materials[1];
  EXPECT_FLOAT_EQ(steel_m.base_color.x(), 0.6f);
  EXPECT_EQ(steel_m.metallic, 1.0f);
  EXPECT_FLOAT_EQ(steel_m.roughness, 0.2f);
  EXPECT_EQ(a.materials[2].metallic, 1.0f);  // glTF default material
}

TEST(GltfLoader, PointsAndLinesAreSkippedWithAWarningNamingTheMesh) {
  GltfBuilder b;
  int p = b.AddFloats({0, 0, 0, 1, 0, 0, 0, 1, 0}, "VEC3");
  b.json()["meshes"].push_back({{"name", "wire"},
                                {"primitives",
                                 {{{"attributes", {{"POSITION", p}}}, {"mode", 0}},
                                  {{"attributes", {{"POSITION", p}}}, {"mode", 1}},
                                  {{"attributes", {{"POSITION", p}}}}}}});
  b.json()["meshes"].push_back({{"name", "dots"}, {"primitives", {{{"attributes", {{"POSITION", p}}}, {"mode", 0}}}}});
  b.AddNode("n", 0);
  b.AddNode("m", 1);
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].TriangleCount(), 1u);
  EXPECT_EQ(a.instances.size(), 1u);  // "dots" has no triangles left
  std::string all;
  for (const auto& w : a.warnings) all += w + "\n";
  EXPECT_THAT(all, HasSubstr("mesh \"wire\" primitive 0: points skipped"));
  EXPECT_THAT(all, HasSubstr("mesh \"wire\" primitive 1: lines skipped"));
  EXPECT_THAT(all, HasSubstr("mesh \"dots\" has no triangles"));
}

TEST(GltfLoader, DegenerateTrianglesAreCountedAndDropped) {
  GltfBuilder b;
  // v4 lies on the segment v0-v1: {0,1,4} is collinear; {0,0,1} repeats an index.
  std::vector<float> p = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5f, 0, 0};
  int mesh = b.AddTriangleMesh("d", p, {}, {}, {0, 1, 2, 0, 0, 1, 0, 1, 4, 0, 1, 3});
  b.AddNode("n", mesh);
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  EXPECT_EQ(a.degenerate_triangles, 2u);
  ASSERT_EQ(a.meshes[0].TriangleCount(), 2u);
  EXPECT_EQ(Corners(a.meshes[0], 1)[2], Eigen::Vector3f(0, 0, 1));
}

TEST(GltfLoader, ZeroLengthNormalsAreReplacedByFaceNormals) {
  GltfBuilder b;
  std::vector<float> n = {0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 1};  // vertex 1 has a zero normal
  int mesh = b.AddTriangleMesh("z", test::SquarePositions(), n, {}, test::SquareIndices());
  b.AddNode("n", mesh);
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  EXPECT_TRUE(a.meshes[0].normals[1].isApprox(Eigen::Vector3f(0, 0, 1)));
  ASSERT_FALSE(a.warnings.empty());
  EXPECT_THAT(a.warnings[0], HasSubstr("1 zero-length normals replaced"));
}

TEST(GltfLoader, EmissiveFactorWithStrengthExtension) {
  GltfBuilder b = test::SquareBuilder();
  int mat = b.AddMaterial("lamp", {1, 1, 1, 1}, 0, 1, {1, 0.5, 0});
  b.json()["materials"][size_t(mat)]["extensions"] = {{"KHR_materials_emissive_strength", {{"emissiveStrength", 5}}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.materials.size(), 1u);
  EXPECT_TRUE(a.materials[0].emissive.isApprox(Eigen::Vector3f(5, 2.5, 0)));
}

// A 2x2 RGBA PNG: red, green / blue, white (sRGB 8-bit), alpha 255.
std::vector<uint8_t> TexturePng(const TempDir& dir) {
  Image<uint8_t> img(2, 2, 4, 255);
  const uint8_t colours[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) img.At(i % 2, i / 2, c) = colours[i][c];
  }
  WriteImage(dir / "tex.png", img);
  std::ifstream in(dir / "tex.png", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void AddTexturedMaterial(GltfBuilder& b, int image) {
  b.json()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33648}}};
  b.json()["textures"] = {{{"source", image}, {"sampler", 0}}};
  int mat = b.AddMaterial("painted", {1, 1, 1, 1}, 0, 0.8);
  b.json()["materials"][size_t(mat)]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
  b.json()["meshes"][0]["primitives"][0]["material"] = mat;
}

// The square with the 2x2 texture (TexturePng) in its binary buffer as its base colour.
GltfBuilder SquareWithEmbeddedTexture(const TempDir& dir) {
  std::vector<uint8_t> png = TexturePng(dir);
  GltfBuilder b = test::SquareBuilder(true, true);
  int view = b.AddBufferView(png.data(), png.size());
  b.json()["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}}};
  AddTexturedMaterial(b, 0);
  return b;
}

void CheckTexture(const GltfAsset& a) {
  ASSERT_EQ(a.materials.size(), 1u);
  ASSERT_TRUE(a.materials[0].base_color_texture);
  const Texture& t = *a.materials[0].base_color_texture;
  EXPECT_EQ(t.image.width, 2);
  EXPECT_EQ(t.wrap_s, WrapMode::kClampToEdge);
  EXPECT_EQ(t.wrap_t, WrapMode::kMirroredRepeat);
  // Texel centres: (0.25, 0.25) red, (0.75, 0.25) green, (0.25, 0.75) blue.
  EXPECT_TRUE(t.Sample({0.25f, 0.25f}).isApprox(Eigen::Vector4f(1, 0, 0, 1)));
  EXPECT_TRUE(t.Sample({0.75f, 0.25f}).isApprox(Eigen::Vector4f(0, 1, 0, 1)));
  EXPECT_TRUE(a.materials[0].BaseColorAt({0.25f, 0.75f}).isApprox(Eigen::Vector3f(0, 0, 1)));
}

TEST(GltfLoader, BaseColorTextureInBufferView) {
  TempDir dir;
  GltfBuilder b = SquareWithEmbeddedTexture(dir);
  CheckTexture(LoadBuilt(b, dir, Format::kGlb));
}

TEST(GltfLoader, BaseColorTextureAsExternalFile) {
  TempDir dir;
  TexturePng(dir);
  GltfBuilder b = test::SquareBuilder(true, true);
  b.json()["images"] = {{{"uri", "tex.png"}}};
  AddTexturedMaterial(b, 0);
  CheckTexture(LoadBuilt(b, dir, Format::kGltfExternal));
}

// EXT_texture_webp (or KHR_texture_basisu) with a PNG fallback: the texture's
// `source` is used and the WebP image, which is not decoded, is no error.
TEST(GltfLoader, ExtensionImageWithPngFallbackUsesTheFallback) {
  TempDir dir;
  std::vector<uint8_t> png = TexturePng(dir);
  GltfBuilder b = test::SquareBuilder(true, true);
  int view = b.AddBufferView(png.data(), png.size());
  const char webp[] = "RIFF\x10\0\0\0WEBPVP8 ";
  int webp_view = b.AddBufferView(webp, sizeof webp - 1);
  b.json()["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}},
                        {{"bufferView", webp_view}, {"mimeType", "image/webp"}}};
  b.json()["extensionsUsed"] = {"EXT_texture_webp"};
  AddTexturedMaterial(b, 0);
  b.json()["textures"][0]["extensions"] = {{"EXT_texture_webp", {{"source", 1}}}};
  CheckTexture(LoadBuilt(b, dir, Format::kGlb));
}

// KHR_texture_transform, uv' = T * R * S * uv. With scale (0.5, 0.25), rotation
// 90 degrees (counter-clockwise in u-right v-down UV space: (u, v) -> (v, -u)) and
// offset (0, 1), uv maps to (v / 4, 1 - u / 2): each lookup below lands on the
// centre of one texel of the 2x2 texture (red, green / blue, white).
TEST(GltfLoader, TextureTransformMovesTheLookup) {
  TempDir dir;
  GltfBuilder b = SquareWithEmbeddedTexture(dir);
  b.json()["extensionsUsed"] = {"KHR_texture_transform"};
  b.json()["extensionsRequired"] = {"KHR_texture_transform"};
  auto& info = b.json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"];
  info["extensions"]["KHR_texture_transform"] = {
      {"offset", {0, 1}}, {"rotation", M_PI / 2}, {"scale", {0.5, 0.25}}};
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.materials.size(), 1u);
  const Material& m = a.materials[0];
  EXPECT_TRUE(m.BaseColorAt({0.5f, 1.0f}).isApprox(Eigen::Vector3f(0, 0, 1), 1e-5f));  // -> (0.25, 0.75) blue
  EXPECT_TRUE(m.BaseColorAt({0.5f, 3.0f}).isApprox(Eigen::Vector3f(1, 1, 1), 1e-5f));  // -> (0.75, 0.75) white
  EXPECT_TRUE(m.BaseColorAt({1.5f, 1.0f}).isApprox(Eigen::Vector3f(1, 0, 0), 1e-5f));  // -> (0.25, 0.25) red
  EXPECT_TRUE(m.BaseColorAt({1.5f, 3.0f}).isApprox(Eigen::Vector3f(0, 1, 0), 1e-5f));  // -> (0.75, 0.25) green
  EXPECT_TRUE(a.warnings.empty());

  // Offset only (what the probe's files use): the halves swap.
  info["extensions"]["KHR_texture_transform"] = {{"offset", {0.5, 0}}};
  const Material m2 = LoadBuilt(b, dir, Format::kGlb).materials[0];
  EXPECT_TRUE(m2.BaseColorAt({0.25f, 0.25f}).isApprox(Eigen::Vector3f(0, 1, 0), 1e-5f));

  // A texCoord override naming a set the primitive lacks falls back to TEXCOORD_0
  // (gltf_exporters_test.cpp: sets the primitive has are read).
  info["extensions"]["KHR_texture_transform"]["texCoord"] = 1;
  GltfAsset a3 = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a3.warnings.size(), 1u);
  EXPECT_THAT(a3.warnings[0], HasSubstr("material \"painted\" reads TEXCOORD_1, which the primitive does not have; "
                                        "TEXCOORD_0 is used"));

  info["extensions"]["KHR_texture_transform"] = {{"scale", {1}}};
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb); }),
              HasSubstr("model.glb: /materials/0/pbrMetallicRoughness/baseColorTexture/extensions/"
                        "KHR_texture_transform/scale: must be an array of 2 numbers"));
}

// KHR_materials_pbrSpecularGlossiness is converted: diffuse -> base colour,
// roughness = 1 - glossiness, metallic 0, with a warning.
TEST(GltfLoader, SpecularGlossinessIsConvertedWithAWarning) {
  TempDir dir;
  GltfBuilder b = SquareWithEmbeddedTexture(dir);
  b.json()["materials"][0]["pbrMetallicRoughness"].erase("baseColorTexture");
  b.json()["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {
      {"diffuseFactor", {0.5, 0.25, 1, 1}}, {"glossinessFactor", 0.75}, {"diffuseTexture", {{"index", 0}}}};
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.materials.size(), 1u);
  const Material& m = a.materials[0];
  EXPECT_EQ(m.base_color, Eigen::Vector3f(0.5f, 0.25f, 1));
  EXPECT_EQ(m.metallic, 0.0f);
  EXPECT_FLOAT_EQ(m.roughness, 0.25f);
  ASSERT_TRUE(m.base_color_texture);
  EXPECT_TRUE(m.BaseColorAt({0.25f, 0.75f}).isApprox(Eigen::Vector3f(0, 0, 1)));  // blue texel times (.5, .25, 1)
  ASSERT_EQ(a.warnings.size(), 1u);
  EXPECT_THAT(a.warnings[0], HasSubstr("model.glb: material \"painted\": KHR_materials_pbrSpecularGlossiness "
                                       "converted to metallic-roughness"));
  EXPECT_THAT(a.warnings[0], HasSubstr("the specular colour is approximated"));
  // A diffuseFactor entry that is no number is named as such (it read "must be in
  // [0, 1], got nan").
  b.json()["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"]["diffuseFactor"][1] = "0.25";
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb); }),
              HasSubstr("KHR_materials_pbrSpecularGlossiness/diffuseFactor/1: must be a number"));
}

// Features that are not rendered are reported, never silently dropped.
TEST(GltfLoader, IgnoredExtensionsAreWarned) {
  GltfBuilder b = test::SquareBuilder();
  int glass = b.AddMaterial("glass", {1, 1, 1, 1}, 0, 0);
  int bottle = b.AddMaterial("bottle", {1, 1, 1, 1}, 0, 0);
  b.json()["materials"][size_t(glass)]["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                                                        {"KHR_materials_ior", {{"ior", 1.5}}}};
  b.json()["materials"][size_t(bottle)]["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = glass;
  b.json()["meshes"][0]["primitives"].push_back(b.json()["meshes"][0]["primitives"][0]);
  b.json()["meshes"][0]["primitives"][1]["material"] = bottle;  // used (unused materials are not read: GltfUnused)
  TempDir dir;
  b.WriteGlb(dir / "model.glb");
  GltfAsset a = LoadGltf(dir / "model.glb", "model.glb");
  EXPECT_THAT(a.warnings, ::testing::UnorderedElementsAre(
                              "model.glb: KHR_materials_ior ignored (not rendered), used by material \"glass\"",
                              "model.glb: KHR_materials_transmission: transmitted light is not traced; the diffuse "
                              "share it takes is removed (base colour times 1 - transmissionFactor), materials "
                              "\"glass\", \"bottle\""));
}

// COLOR_0 (Meshroom, Open3D and trimesh meshes carry their colour only so):
// RGB or RGBA, float or normalised integers, read as linear RGB per vertex
// (alpha dropped) into Mesh::colors, which multiply the base colour
// (scene/embree_scene.h BaseColorAt; tests/scene/embree_scene_test.cpp).
TEST(GltfLoader, VertexColoursAreRead) {
  {
    GltfBuilder b = test::SquareBuilder();
    const std::vector<float> rgba = {1, 0, 0, 0.5f, 0, 1, 0, 1, 0, 0, 1, 1, 0.25f, 0.5f, 0.75f, 0};
    b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = b.AddFloats(rgba, "VEC4");
    TempDir dir;
    b.WriteGlb(dir / "model.glb");
    const GltfAsset a = LoadGltf(dir / "model.glb", "model.glb");
    EXPECT_TRUE(a.warnings.empty()) << a.warnings[0];
    ASSERT_EQ(a.meshes.size(), 1u);
    const Mesh& m = a.meshes[0];
    ASSERT_EQ(m.colors.size(), m.positions.size());
    for (size_t v = 0; v < m.positions.size(); ++v) {
      // The loader keeps the file's vertex order for the square (all used).
      EXPECT_EQ(m.colors[v], Eigen::Vector3f(rgba[4 * v], rgba[4 * v + 1], rgba[4 * v + 2])) << v;
    }
  }
  {
    // Normalised unsigned bytes, RGB, on a primitive without normals (flat:
    // each triangle gets its own corners, which keep their colours).
    GltfBuilder b = test::SquareBuilder(false);
    // Each element padded to 4 bytes, as glTF aligns vertex attributes.
    const std::vector<uint8_t> rgb = {255, 0, 0, 0, 255, 0, 0, 0, 255, 51, 102, 204};
    std::vector<uint8_t> padded;
    for (size_t v = 0; v < 4; ++v) padded.insert(padded.end(), {rgb[3 * v], rgb[3 * v + 1], rgb[3 * v + 2], 0});
    const int view = b.AddBufferView(padded.data(), padded.size(), 4);
    const int acc = b.AddAccessor(view, 5121, 4, "VEC3", true);
    b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = acc;
    TempDir dir;
    b.WriteGlb(dir / "model.glb");
    const GltfAsset a = LoadGltf(dir / "model.glb", "model.glb");
    const Mesh& m = a.meshes.at(0);
    ASSERT_EQ(m.colors.size(), 6u);
    const std::vector<uint32_t> corners = test::SquareIndices();
    for (size_t k = 0; k < 6; ++k) {
      const uint32_t v = corners[k];
      EXPECT_TRUE(m.colors[k].isApprox(Eigen::Vector3f(rgb[3 * v], rgb[3 * v + 1], rgb[3 * v + 2]) / 255.0f))
          << k << ": " << m.colors[k].transpose();
    }
  }
}

// Adds JOINTS_0 (unsigned bytes) and WEIGHTS_0 (floats) to primitive 0 of mesh 0.
void AddSkinAttributes(GltfBuilder& b, const std::vector<uint8_t>& joints, const std::vector<float>& weights) {
  const int jv = b.AddBufferView(joints.data(), joints.size());
  const int ja = b.AddAccessor(jv, 5121, joints.size() / 4, "VEC4");
  auto& attributes = b.json()["meshes"][0]["primitives"][0]["attributes"];
  attributes["JOINTS_0"] = ja;
  attributes["WEIGHTS_0"] = b.AddFloats(weights, "VEC4");
}

// A skinned mesh (Blender's armatures) is posed by its joints: glTF ignores the
// skinned node's own transform. Joint "hip" stands at z = 2; joint "arm" (bound
// at y = 1) is turned 90 degrees about x. Corners 0 and 1 follow the hip, corner
// 2 the arm, corner 3 both, half each.
TEST(GltfLoader, SkinnedMeshIsPosedByItsJointsNotItsNode) {
  GltfBuilder b = test::SquareBuilder();
  AddSkinAttributes(b, {0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0},
                    {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0});
  const double s = std::sqrt(0.5);
  auto& nodes = b.json()["nodes"];
  nodes[0]["translation"] = {100, 0, 0};  // ignored
  nodes[0]["skin"] = 0;
  nodes.push_back({{"name", "hip"}, {"translation", {0, 0, 2}}, {"children", {2}}});
  nodes.push_back({{"name", "arm"}, {"translation", {0, 1, 0}}, {"rotation", {s, 0, 0, s}}});
  b.json()["scenes"][0]["nodes"] = {1, 0};
  // Inverse bind matrices: identity for the hip, translation (0, -1, 0) for the arm.
  const int ibm = b.AddFloats({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                               1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1},
                              "MAT4");
  b.json()["skins"] = {{{"joints", {1, 2}}, {"inverseBindMatrices", ibm}}};
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.instances.size(), 1u);
  EXPECT_TRUE(a.instances[0].file_from_mesh.matrix().isIdentity());
  const Mesh& m = a.meshes[0];
  ASSERT_EQ(m.VertexCount(), 4u);
  const Eigen::Affine3d hip(Eigen::Translation3d(0, 0, 2));
  const Eigen::Affine3d arm = hip * Eigen::Translation3d(0, 1, 0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()) *
                              Eigen::Translation3d(0, -1, 0);
  const std::vector<float> p = test::SquarePositions();
  const double w_hip[4] = {1, 1, 0, 0.5};
  for (size_t v = 0; v < 4; ++v) {
    const Eigen::Vector3d mesh_p(p[3 * v], p[3 * v + 1], p[3 * v + 2]);
    const Eigen::Matrix3d linear = w_hip[v] * hip.linear() + (1 - w_hip[v]) * arm.linear();
    const Eigen::Vector3d expected = w_hip[v] * (hip * mesh_p) + (1 - w_hip[v]) * (arm * mesh_p);
    const Eigen::Vector3d normal = (linear.inverse().transpose() * Eigen::Vector3d::UnitZ()).normalized();
    EXPECT_TRUE(m.positions[v].cast<double>().isApprox(expected, 1e-6)) << v << ": " << m.positions[v].transpose();
    EXPECT_TRUE(m.normals[v].cast<double>().isApprox(normal, 1e-6)) << v << ": " << m.normals[v].transpose();
  }
  EXPECT_TRUE(m.positions[2].cast<double>().isApprox(Eigen::Vector3d(1, 1, 2), 1e-6));  // the arm's corner
  EXPECT_TRUE(m.normals[2].cast<double>().isApprox(Eigen::Vector3d(0, -1, 0), 1e-6));

  // A joint index past the skin's joints is an error naming the accessor.
  b.json()["skins"][0]["joints"] = {1};
  b.json()["skins"][0].erase("inverseBindMatrices");
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb, "bad"); }),
              HasSubstr("bad.glb: /accessors/3: joint 1 of vertex 2 is past the 1 joints of /skins/0"));
}

// A skin that mirrors turns the triangles round, as a mirroring node does: the
// winding and the normals agree, with and without NORMAL.
TEST(GltfLoader, MirroringSkinKeepsWindingAndNormalsTogether) {
  for (bool normals : {true, false}) {
    GltfBuilder b = test::SquareBuilder(normals);
    AddSkinAttributes(b, std::vector<uint8_t>(16, 0), {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
    b.json()["nodes"][0]["skin"] = 0;
    b.json()["nodes"].push_back({{"name", "mirror"}, {"scale", {-1, 1, 1}}});
    b.json()["skins"] = {{{"joints", {1}}}};
    TempDir dir;
    GltfAsset a = LoadBuilt(b, dir, Format::kGltfEmbedded);
    const Mesh& m = a.meshes[0];
    ASSERT_EQ(m.TriangleCount(), 2u);
    for (size_t t = 0; t < 2; ++t) {
      EXPECT_TRUE(UnitFaceNormal(m, t).isApprox(Eigen::Vector3d(0, 0, 1), 1e-9)) << normals << " " << t;
      EXPECT_LE(Corners(m, t)[1].x(), 0.0f);
    }
    for (const auto& n : m.normals) EXPECT_TRUE(n.isApprox(Eigen::Vector3f(0, 0, 1))) << normals;
  }
}

// Mirroring and non-uniformly scaling nodes, as loaded and ray traced: the
// geometric normal (from the winding) and the shading normal (the file's normals
// by the inverse transpose) agree and stand perpendicular to the placed square.
TEST(GltfLoader, MirroredAndNonUniformlyScaledNodesRenderWithConsistentNormals) {
  GltfBuilder b = test::SquareBuilder();
  auto& nodes = b.json()["nodes"];
  const double s = std::sqrt(0.5);
  nodes[0]["translation"] = {0.5, 0, 0};
  nodes.push_back({{"name", "mirror"}, {"scale", {-1, 1, 1}}, {"children", {0}}});
  nodes.push_back({{"name", "squash"}, {"translation", {0, 0, -5}}, {"scale", {1, 1, 4}}, {"mesh", 0},
                   {"rotation", {0, s, 0, s}}});  // turned 90 deg about y, then stretched 4x along z
  nodes.push_back({{"name", "tilt"}, {"translation", {5, 0, 0}}, {"scale", {1, 1, 3}}, {"children", {4}}});
  nodes.push_back({{"name", "tilted"}, {"rotation", {0, 0.3826834, 0, 0.9238795}}, {"mesh", 0}});
  b.json()["scenes"][0]["nodes"] = {1, 2, 3};
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.instances.size(), 3u);
  auto g = std::make_shared<SceneGeometry>();
  g->meshes = a.meshes;
  g->materials = a.materials;
  for (const auto& inst : a.instances) g->instances.push_back({inst.mesh, 0, inst.file_from_mesh, -1, inst.node_name});
  EmbreeScene scene(g);
  // The mirrored square covers x in [-1.5, -0.5], its front (+z) towards the ray.
  auto mirrored = scene.Intersect({{-1, 0.5, 1}, {0, 0, -1}});
  ASSERT_TRUE(mirrored);
  EXPECT_TRUE(mirrored->geometric_normal.isApprox(Eigen::Vector3d(0, 0, 1), 1e-9));
  EXPECT_TRUE(mirrored->shading_normal.isApprox(Eigen::Vector3d(0, 0, 1), 1e-6));
  EXPECT_TRUE(mirrored->front_face);
  // The tilted square (45 deg about y, then 3x along z): its plane is x = z / 3 ... rotated;
  // the normal is the inverse transpose's image of +z, not the stretched +z.
  const Eigen::Affine3d tilt = a.instances[2].file_from_mesh;
  const Eigen::Vector3d expected = (tilt.linear().inverse().transpose() * Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d centre = tilt * Eigen::Vector3d(0.5, 0.5, 0);
  auto tilted = scene.Intersect({centre + 2 * expected, -expected});
  ASSERT_TRUE(tilted);
  EXPECT_EQ(a.instances[tilted->instance_id].node_name, "tilted");
  EXPECT_TRUE(tilted->geometric_normal.isApprox(expected, 1e-9)) << tilted->geometric_normal.transpose();
  EXPECT_TRUE(tilted->shading_normal.isApprox(expected, 1e-6)) << tilted->shading_normal.transpose();
  EXPECT_GT(std::abs(expected.dot((tilt.linear() * Eigen::Vector3d::UnitZ()).normalized()) - 1), 0.1);
  // Both square edges lie in the plane the normal is perpendicular to.
  EXPECT_NEAR(expected.dot(tilt.linear() * Eigen::Vector3d::UnitX()), 0, 1e-12);
  EXPECT_NEAR(expected.dot(tilt.linear() * Eigen::Vector3d::UnitY()), 0, 1e-12);
}

// Draco (KHR_draco_mesh_compression) not required: the uncompressed attributes
// are read. Without them (accessors without a bufferView) the primitive cannot
// be read and is refused naming the extension, not loaded as zeros.
TEST(GltfLoader, OptionalDracoUsesTheUncompressedFallback) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.json()["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"] = {
      {"bufferView", 0}, {"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}};
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].positions[2], Eigen::Vector3f(1, 1, 0));
  b.json()["accessors"][0].erase("bufferView");
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb, "draco"); }),
              EndsWith("/draco.glb: /meshes/0/primitives/0: compressed with KHR_draco_mesh_compression, which is not supported, "
            "and accessor 0 (its attributes/POSITION) has no uncompressed data to fall back on (no bufferView); "
            "write the file without Draco"));
}

// EXT_meshopt_compression not required, with an uncompressed fallback buffer
// (gltfpack -cf): the bufferViews' own buffer is read. A fallback buffer without
// data is refused (tinygltf would have handed it the GLB's compressed BIN chunk).
TEST(GltfLoader, OptionalMeshoptReadsTheFallbackAndRefusesAnEmptyOne) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensionsUsed"] = {"EXT_meshopt_compression"};
  for (auto& view : b.json()["bufferViews"]) {
    view["extensions"]["EXT_meshopt_compression"] = {
        {"buffer", 1}, {"byteOffset", 0}, {"byteLength", 4}, {"byteStride", 4}, {"count", 1}, {"mode", "ATTRIBUTES"}};
  }
  b.json()["buffers"] = {{{"byteLength", b.bin().size()}},
                         {{"byteLength", 4}, {"uri", "data:application/octet-stream;base64,AAAAAA=="}}};
  TempDir dir;
  GltfAsset a = LoadBuilt(b, dir, Format::kGlb);
  EXPECT_EQ(a.meshes.at(0).positions[2], Eigen::Vector3f(1, 1, 0));

  // gltfpack -cf into a GLB: the views point into a uri-less buffer 1 marked "fallback".
  b.json()["buffers"][1] = {{"byteLength", b.bin().size()},
                            {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}};
  for (auto& view : b.json()["bufferViews"]) view["buffer"] = 1;
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb, "fallback"); }),
              EndsWith("/fallback.glb: /buffers/1: the buffer holds no data: it is the fallback buffer of EXT_meshopt_compression, "
            "whose compressed data is not supported (write the file without meshopt compression, e.g. gltfpack "
            "without -c/-cc)"));
}

TEST(GltfLoader, UnsupportedRequiredExtensionIsAnError) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  TempDir dir;
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb); }),
              HasSubstr("model.glb: /extensionsRequired/0: required extension \"KHR_draco_mesh_compression\" is not "
                        "supported (the meshes are Draco-compressed: write or convert the file without compression)"));
}

}  // namespace
}  // namespace lt
