// glTF loading: every supported feature on small files built in the test.
#include "scene/gltf_loader.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "core/image_io.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
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

  // A texCoord override naming another set is reported (only TEXCOORD_0 is loaded).
  info["extensions"]["KHR_texture_transform"]["texCoord"] = 1;
  GltfAsset a3 = LoadBuilt(b, dir, Format::kGlb);
  ASSERT_EQ(a3.warnings.size(), 1u);
  EXPECT_THAT(a3.warnings[0], HasSubstr("material \"painted\": base colour texture reads TEXCOORD_1 "
                                        "(KHR_texture_transform's texCoord), which is not loaded; TEXCOORD_0 is used"));

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
}

// Features that are not rendered are reported, never silently dropped.
TEST(GltfLoader, IgnoredExtensionsAndVertexColoursAreWarned) {
  GltfBuilder b = test::SquareBuilder();
  int glass = b.AddMaterial("glass", {1, 1, 1, 1}, 0, 0);
  int bottle = b.AddMaterial("bottle", {1, 1, 1, 1}, 0, 0);
  b.json()["materials"][size_t(glass)]["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}},
                                                        {"KHR_materials_ior", {{"ior", 1.5}}}};
  b.json()["materials"][size_t(bottle)]["extensions"] = {{"KHR_materials_transmission", {{"transmissionFactor", 1}}}};
  b.json()["meshes"][0]["primitives"][0]["material"] = glass;
  std::vector<float> colours(16, 1.0f);
  b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = b.AddFloats(colours, "VEC4");
  b.json()["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
  b.json()["nodes"][0]["extensions"] = {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", 0}}}}}};
  TempDir dir;
  b.WriteGlb(dir / "model.glb");
  GltfAsset a = LoadGltf(dir / "model.glb", "model.glb");
  EXPECT_THAT(a.warnings, ::testing::UnorderedElementsAre(
                              "model.glb: KHR_materials_ior ignored (not rendered), used by material \"glass\"",
                              "model.glb: KHR_materials_transmission ignored (not rendered), used by materials "
                              "\"glass\", \"bottle\"",
                              "model.glb: mesh \"square\": COLOR_0 vertex colours ignored (not rendered)",
                              "model.glb: node \"square_node\": EXT_mesh_gpu_instancing ignored: its instances are "
                              "not created (only the node's own mesh is placed)"));
}

TEST(GltfLoader, UnsupportedRequiredExtensionIsAnError) {
  GltfBuilder b = test::SquareBuilder();
  b.json()["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  TempDir dir;
  EXPECT_THAT(ErrorOf([&] { LoadBuilt(b, dir, Format::kGlb); }),
              HasSubstr("model.glb: /extensionsRequired/0: required extension \"KHR_draco_mesh_compression\" is not supported"));
}

}  // namespace
}  // namespace lt
