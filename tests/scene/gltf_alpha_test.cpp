// glTF alphaMode (3.9.4) as every ray of the Embree scene sees it: MASK cuts holes
// where alpha (baseColorFactor[3] x the base-colour texture's alpha x COLOR_0's
// alpha) is below alphaCutoff, BLEND is covered with probability alpha, OPAQUE
// ignores alpha. They rendered opaque before (surfaces where the file has none,
// blocking camera, laser and ground-truth rays alike).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>

#include "core/image_io.h"
#include "scene/embree_scene.h"
#include "scene/gltf_loader.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using ::testing::HasSubstr;

// The unit square (z = 0, u = x, v = 1 - y) with material 0, and an opaque
// floor of material 1 at z = -1 under all of it ([-1, 2]^2).
GltfBuilder QuadOverFloor(const std::vector<double>& rgba, const std::string& alpha_mode) {
  GltfBuilder b = test::SquareBuilder(true, true);
  const int quad = b.AddMaterial("quad", rgba, 0, 1);
  b.json()["materials"][size_t(quad)]["alphaMode"] = alpha_mode;
  b.json()["meshes"][0]["primitives"][0]["material"] = quad;
  const int floor_material = b.AddMaterial("floor", {1, 1, 1, 1}, 0, 1);
  std::vector<float> p = test::SquarePositions();
  for (float& x : p) x *= 3;
  const int floor = b.AddTriangleMesh("floor", p, test::SquareNormals(), {}, test::SquareIndices(), floor_material);
  b.AddNode("floor", floor, {-1, -1, -1});
  return b;
}

// A 2x1 RGBA texture with alphas (left, right), clamped at the edges, as texture 0
// of the quad's material: alpha = left for u <= 0.25, right for u >= 0.75, linear between.
void AddAlphaTexture(GltfBuilder* b, const TempDir& dir, uint8_t left, uint8_t right) {
  Image<uint8_t> img(2, 1, 4, 200);
  img.At(0, 0, 3) = left;
  img.At(1, 0, 3) = right;
  WriteImage(dir / "alpha.png", img);
  b->json()["images"] = {{{"uri", "alpha.png"}}};
  b->json()["samplers"] = {{{"wrapS", 33071}, {"wrapT", 33071}}};
  b->json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
  b->json()["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
}

// The Embree scene of a glTF file: its meshes, materials and node instances.
std::unique_ptr<EmbreeScene> Load(const GltfBuilder& b, const TempDir& dir) {
  b.WriteGltf(dir / "model.gltf", false);
  GltfAsset a = LoadGltf(dir / "model.gltf", "model.gltf");
  auto g = std::make_shared<SceneGeometry>();
  g->meshes = std::move(a.meshes);
  g->materials = std::move(a.materials);
  for (const GltfInstance& gi : a.instances) {
    SceneInstance inst;
    inst.mesh = gi.mesh;
    inst.world_from_mesh = gi.file_from_mesh;
    inst.name = gi.node_name;
    g->instances.push_back(inst);
  }
  return std::make_unique<EmbreeScene>(std::shared_ptr<const SceneGeometry>(g));
}

Ray Down(double x, double y) { return {{x, y, 1}, {0, 0, -1}}; }
Ray Up(double x, double y) { return {{x, y, -0.5}, {0, 0, 1}}; }

// The z a ray down at (x, y) stops at: 0 on the quad, -1 on the floor.
double HitZ(const EmbreeScene& s, double x, double y) {
  const auto hit = s.Intersect(Down(x, y));
  return hit ? hit->position.z() : 1.0;
}

// The quad from above and below, by Intersect and by Occluded (a ray ending
// before the floor): each query sees it where `covered`, and the floor through it.
void ExpectSeenWhere(const EmbreeScene& s, const std::function<bool(double x)>& covered) {
  for (double x : {0.05, 0.2, 0.3, 0.45, 0.49, 0.51, 0.55, 0.7, 0.8, 0.95}) {
    for (double y : {0.1, 0.6}) {
      SCOPED_TRACE("x " + std::to_string(x) + " y " + std::to_string(y));
      EXPECT_EQ(HitZ(s, x, y), covered(x) ? 0.0 : -1.0);
      Ray down = Down(x, y);
      down.t_max = 1.5;
      EXPECT_EQ(s.Occluded(down), covered(x));
      EXPECT_EQ(s.Intersect(Up(x, y)).has_value(), covered(x));  // nothing above but the quad
    }
  }
}

TEST(GltfAlpha, MaskTextureCutsHolesForEveryQuery) {
  TempDir dir;
  GltfBuilder b = QuadOverFloor({1, 1, 1, 1}, "MASK");
  AddAlphaTexture(&b, dir, 0, 255);
  const auto s = Load(b, dir);
  EXPECT_EQ(s->alpha_filtered_mesh_count(), 1u);  // the quad, not the floor
  // alpha = 2 (u - 0.25) between the texel centres: 0.5 (the default cutoff) at u = 0.5.
  ExpectSeenWhere(*s, [](double x) { return x > 0.5; });
  // alphaCutoff moves the edge: 0.8 at u = 0.65.
  b.json()["materials"][0]["alphaCutoff"] = 0.8;
  const auto high = Load(b, dir);
  EXPECT_EQ(HitZ(*high, 0.6, 0.5), -1.0);
  EXPECT_EQ(HitZ(*high, 0.7, 0.5), 0.0);
}

TEST(GltfAlpha, MaskFactorBelowTheCutoffWithoutTextureIsInvisible) {
  TempDir dir;
  const auto s = Load(QuadOverFloor({1, 1, 1, 0.3}, "MASK"), dir);
  EXPECT_EQ(s->alpha_filtered_mesh_count(), 1u);
  ExpectSeenWhere(*s, [](double) { return false; });
  // At or above the cutoff it is opaque, and needs no filter.
  GltfBuilder b = QuadOverFloor({1, 1, 1, 0.3}, "MASK");
  b.json()["materials"][0]["alphaCutoff"] = 0.3;
  const auto kept = Load(b, dir);
  EXPECT_EQ(kept->alpha_filtered_mesh_count(), 0u);
  ExpectSeenWhere(*kept, [](double) { return true; });
}

TEST(GltfAlpha, OpaqueIgnoresAlpha) {
  TempDir dir;
  GltfBuilder b = QuadOverFloor({1, 1, 1, 0}, "OPAQUE");
  AddAlphaTexture(&b, dir, 0, 0);
  const auto s = Load(b, dir);
  EXPECT_EQ(s->alpha_filtered_mesh_count(), 0u);
  ExpectSeenWhere(*s, [](double) { return true; });
}

TEST(GltfAlpha, FullyTransparentBlendIsInvisible) {
  TempDir dir;
  const auto s = Load(QuadOverFloor({1, 1, 1, 0}, "BLEND"), dir);
  ExpectSeenWhere(*s, [](double) { return false; });
  // A zero-alpha texture with factor 1, and KHR_materials_pbrSpecularGlossiness's diffuse alpha, too.
  GltfBuilder textured = QuadOverFloor({1, 1, 1, 1}, "BLEND");
  AddAlphaTexture(&textured, dir, 0, 0);
  ExpectSeenWhere(*Load(textured, dir), [](double) { return false; });
  GltfBuilder sg = QuadOverFloor({1, 1, 1, 1}, "BLEND");
  sg.json()["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"] = {{"diffuseFactor", {1, 1, 1, 0}}};
  ExpectSeenWhere(*Load(sg, dir), [](double) { return false; });
  // Alpha 1 everywhere: opaque, no filter.
  const auto full = Load(QuadOverFloor({1, 1, 1, 1}, "BLEND"), dir);
  EXPECT_EQ(full->alpha_filtered_mesh_count(), 0u);
  ExpectSeenWhere(*full, [](double) { return true; });
}

// BLEND alpha 0.3: a ray meets the quad with probability 0.3, decided by the ray
// alone: the same ray gives the same answer again and in Occluded.
TEST(GltfAlpha, BlendCoverageIsTheAlphaAndDeterministic) {
  TempDir dir;
  const auto s = Load(QuadOverFloor({1, 1, 1, 0.3}, "BLEND"), dir);
  const int n = 40;
  int covered = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = (i + 0.5) / n, y = (j + 0.5) / n;
      const bool hit = HitZ(*s, x, y) == 0.0;
      covered += hit;
      EXPECT_EQ(HitZ(*s, x, y) == 0.0, hit);
      Ray down = Down(x, y);
      down.t_max = 1.5;
      EXPECT_EQ(s->Occluded(down), hit);
    }
  }
  // 1600 rays: binomial standard deviation 0.0115 of the fraction.
  EXPECT_NEAR(double(covered) / (n * n), 0.3, 0.05);
}

// COLOR_0's alpha multiplies: alpha 0 at x = 0, 1 at x = 1 (0.5 at x = 0.5).
TEST(GltfAlpha, VertexColourAlphaMultiplies) {
  TempDir dir;
  GltfBuilder b = QuadOverFloor({1, 1, 1, 1}, "MASK");
  const std::vector<float> colours = {1, 1, 1, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0};
  b.json()["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] = b.AddFloats(colours, "VEC4");
  const auto s = Load(b, dir);
  ExpectSeenWhere(*s, [](double x) { return x > 0.5; });
}

// The filter reads the material the instance gives the triangle: two instances of
// one mesh, one overridden by a MASK material below its cutoff.
TEST(GltfAlpha, InstanceMaterialOverridesAreRespected) {
  auto g = std::make_shared<SceneGeometry>();
  Mesh m;
  m.name = "square";
  for (int i = 0; i < 4; ++i) {
    const std::vector<float> p = test::SquarePositions();
    m.positions.emplace_back(p[size_t(3 * i)], p[size_t(3 * i + 1)], p[size_t(3 * i + 2)]);
    m.normals.emplace_back(0, 0, 1);
  }
  m.indices = test::SquareIndices();
  m.triangle_material = {0, 0};
  g->meshes.push_back(m);
  g->materials.resize(2);
  g->materials[1].alpha_mode = AlphaMode::kMask;
  g->materials[1].alpha = 0.2f;
  for (int k = 0; k < 2; ++k) {
    SceneInstance inst;
    inst.world_from_mesh = Eigen::Translation3d(2.0 * k, 0, 0) * Eigen::Affine3d::Identity();
    inst.material_override = k == 0 ? -1 : 1;
    g->instances.push_back(inst);
  }
  const EmbreeScene s{std::shared_ptr<const SceneGeometry>(g)};
  EXPECT_EQ(s.alpha_filtered_mesh_count(), 1u);
  EXPECT_TRUE(s.Intersect(Down(0.5, 0.5)));
  EXPECT_FALSE(s.Intersect(Down(2.5, 0.5)));
  EXPECT_FALSE(s.Occluded(Down(2.5, 0.5)));
}

// ReplaceMesh (a mesh that changes over time) decides the filter again from the new mesh.
TEST(GltfAlpha, ReplacedMeshGetsTheFilterItNeeds) {
  auto g = std::make_shared<SceneGeometry>();
  Mesh m;
  m.name = "square";
  const std::vector<float> p = test::SquarePositions();
  for (size_t i = 0; i < 4; ++i) {
    m.positions.emplace_back(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    m.normals.emplace_back(0, 0, 1);
  }
  m.indices = test::SquareIndices();
  m.triangle_material = {0, 0};
  g->meshes.push_back(m);
  g->materials.resize(1);
  g->materials[0].alpha_mode = AlphaMode::kMask;
  SceneInstance inst;
  inst.world_from_mesh = Eigen::Affine3d::Identity();
  g->instances.push_back(inst);
  EmbreeScene s{g};
  EXPECT_EQ(s.alpha_filtered_mesh_count(), 0u);  // alpha 1 everywhere
  EXPECT_TRUE(s.Intersect(Down(0.5, 0.5)));
  m.alphas = {0, 0, 0, 0};
  s.ReplaceMesh(0, m);
  EXPECT_EQ(s.alpha_filtered_mesh_count(), 1u);
  EXPECT_FALSE(s.Intersect(Down(0.5, 0.5)));
  m.alphas.clear();
  s.ReplaceMesh(0, m);
  EXPECT_EQ(s.alpha_filtered_mesh_count(), 0u);
  EXPECT_TRUE(s.Intersect(Down(0.5, 0.5)));
}

TEST(GltfAlpha, BadAlphaModeAndCutoffAreErrors) {
  TempDir dir;
  GltfBuilder b = QuadOverFloor({1, 1, 1, 1}, "mask");
  b.WriteGltf(dir / "bad.gltf", false);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "bad.gltf", "bad.gltf"); }),
              HasSubstr("bad.gltf: /materials/0/alphaMode: must be \"OPAQUE\", \"MASK\" or \"BLEND\", got \"mask\""));
  GltfBuilder c = QuadOverFloor({1, 1, 1, 1}, "MASK");
  c.json()["materials"][0]["alphaCutoff"] = -0.5;
  c.WriteGltf(dir / "cutoff.gltf", false);
  EXPECT_THAT(ErrorOf([&] { LoadGltf(dir / "cutoff.gltf", "cutoff.gltf"); }),
              HasSubstr("cutoff.gltf: /materials/0/alphaCutoff: must be a number >= 0, got -0.5"));
}

}  // namespace
}  // namespace lt
