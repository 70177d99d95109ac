// Rays cast into Embree scenes built from meshes and instances hit where the
// geometry is, with the right normals, texture coordinates and ids.
#include "scene/embree_scene.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "test_util.h"

namespace lt {
namespace {

// The unit square of test_util.h as a mesh with material 0.
Mesh SquareMesh() {
  Mesh m;
  m.name = "square";
  auto p = test::SquarePositions(), n = test::SquareNormals(), uv = test::SquareTexcoords();
  for (size_t i = 0; i < 4; ++i) {
    m.positions.emplace_back(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    m.normals.emplace_back(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
    m.texcoords.emplace_back(uv[2 * i], uv[2 * i + 1]);
  }
  m.indices = test::SquareIndices();
  m.triangle_material = {0, 0};
  return m;
}

std::shared_ptr<SceneGeometry> Geometry(std::vector<Eigen::Affine3d> transforms, std::vector<int32_t> overrides = {}) {
  auto g = std::make_shared<SceneGeometry>();
  g->meshes.push_back(SquareMesh());
  g->materials = {Material{}, Material{}};
  g->materials[0].name = "a";
  g->materials[1].name = "b";
  for (size_t i = 0; i < transforms.size(); ++i) {
    SceneInstance inst;
    inst.mesh = 0;
    inst.world_from_mesh = transforms[i];
    inst.material_override = i < overrides.size() ? overrides[i] : -1;
    inst.name = std::string("i").append(std::to_string(i));
    g->instances.push_back(inst);
  }
  return g;
}

Ray Down(double x, double y, double z = 1) { return {{x, y, z}, {0, 0, -1}}; }

TEST(EmbreeScene, HitsTheSquareWhereItIs) {
  EmbreeScene scene(Geometry({Eigen::Affine3d::Identity()}));
  EXPECT_EQ(scene.triangle_count(), 2u);
  EXPECT_EQ(scene.instance_count(), 1u);
  EXPECT_TRUE(scene.bounds().min().isApprox(Eigen::Vector3d(0, 0, 0)));
  EXPECT_TRUE(scene.bounds().max().isApprox(Eigen::Vector3d(1, 1, 0)));
  EXPECT_TRUE(scene.render_origin().isApprox(Eigen::Vector3d(0.5, 0.5, 0)));

  auto hit = scene.Intersect(Down(0.25, 0.5, 2));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.0, 1e-15);
  EXPECT_LT((hit->position - Eigen::Vector3d(0.25, 0.5, 0)).norm(), 1e-15);
  EXPECT_TRUE(hit->geometric_normal.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(hit->shading_normal.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_TRUE(hit->front_face);
  EXPECT_EQ(hit->primitive_id, 1u);  // above the diagonal: triangle {0, 2, 3}
  EXPECT_EQ(hit->instance_id, 0u);
  EXPECT_EQ(hit->material_id, 0u);
  EXPECT_NEAR(hit->uv.x(), 0.25, 1e-6);  // u = x, v = 1 - y
  EXPECT_NEAR(hit->uv.y(), 0.5, 1e-6);

  EXPECT_FALSE(scene.Intersect(Down(1.5, 0.5)));                   // beside it
  EXPECT_FALSE(scene.Intersect({{0.5, 0.5, 1}, {0, 0, 1}}));       // pointing away
  auto back = scene.Intersect({{0.75, 0.25, -1}, {0, 0, 2}});       // from below, unnormalised
  ASSERT_TRUE(back);
  EXPECT_FALSE(back->front_face);
  EXPECT_NEAR(back->t, 0.5, 1e-6);
  EXPECT_EQ(back->primitive_id, 0u);
}

// Vertex colours are interpolated at the hit and multiply the material's base
// colour. Colours affine in x and y over the square are exact under the
// barycentric interpolation anywhere on it.
TEST(EmbreeScene, VertexColoursMultiplyTheBaseColour) {
  auto g = Geometry({Eigen::Affine3d::Identity()});
  auto colour = [](double x, double y) { return Eigen::Vector3f(float(0.2 + 0.6 * x), float(0.3 + 0.4 * y), 0.9f); };
  Mesh& m = g->meshes[0];
  for (const Eigen::Vector3f& p : m.positions) m.colors.push_back(colour(p.x(), p.y()));
  m.Validate();
  g->materials[0].base_color = {0.5f, 0.8f, 1.0f};
  const EmbreeScene scene(g);
  for (auto [x, y] : {std::pair{0.25, 0.5}, {0.8, 0.1}, {0.1, 0.9}}) {
    const auto hit = scene.Intersect(Down(x, y));
    ASSERT_TRUE(hit);
    EXPECT_TRUE(hit->vertex_color.isApprox(colour(x, y), 1e-6f)) << hit->vertex_color.transpose();
    EXPECT_TRUE(BaseColorAt(g->materials[0], *hit).isApprox(colour(x, y).cwiseProduct(Eigen::Vector3f(0.5f, 0.8f, 1.0f)), 1e-6f));
  }
  // Without colours: white, the material's colour as it is.
  const EmbreeScene plain(Geometry({Eigen::Affine3d::Identity()}));
  EXPECT_EQ(plain.Intersect(Down(0.25, 0.5))->vertex_color, Eigen::Vector3f::Ones());
}

TEST(EmbreeScene, RespectsTheRayInterval) {
  EmbreeScene scene(Geometry({Eigen::Affine3d::Identity()}));
  Ray r = Down(0.5, 0.25, 1);
  r.t_max = 0.9;
  EXPECT_FALSE(scene.Intersect(r));
  EXPECT_FALSE(scene.Occluded(r));
  r.t_max = 1.1;
  EXPECT_TRUE(scene.Intersect(r));
  EXPECT_TRUE(scene.Occluded(r));
  r.t_min = 1.05;
  EXPECT_FALSE(scene.Intersect(r));
  EXPECT_FALSE(scene.Occluded(r));
}

TEST(EmbreeScene, InstancesCarryTheirTransformsAndMaterials) {
  // Instance 1: rotated 90 degrees about x (the square stands in the x-z plane at
  // y = 3, facing -y), scaled by 2. Instance 2: mirrored in x and moved to z = -5.
  Eigen::Affine3d standing =
      Eigen::Translation3d(0, 3, 0) * Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()) * Eigen::Scaling(2.0);
  Eigen::Affine3d mirrored = Eigen::Translation3d(0, 0, -5) * Eigen::Scaling(-1.0, 1.0, 1.0);
  EmbreeScene scene(Geometry({Eigen::Affine3d::Identity(), standing, mirrored}, {-1, 1, -1}));
  EXPECT_EQ(scene.triangle_count(), 6u);
  EXPECT_EQ(scene.unique_triangle_count(), 2u);

  // Mesh point (0.5, 0.5, 0) of `standing` is at world (1, 3, 1).
  auto hit = scene.Intersect({{1, 0, 1}, {0, 1, 0}});
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->instance_id, 1u);
  EXPECT_EQ(hit->material_id, 1u);  // override
  EXPECT_TRUE(hit->position.isApprox(Eigen::Vector3d(1, 3, 1), 1e-7));
  EXPECT_TRUE(hit->geometric_normal.isApprox(Eigen::Vector3d(0, -1, 0), 1e-9));
  EXPECT_TRUE(hit->shading_normal.isApprox(Eigen::Vector3d(0, -1, 0), 1e-6));
  EXPECT_TRUE(hit->front_face);

  // The mirrored copy covers x in [-1, 0]; its front still faces +z.
  auto m = scene.Intersect(Down(-0.25, 0.5, -4));
  ASSERT_TRUE(m);
  EXPECT_EQ(m->instance_id, 2u);
  EXPECT_EQ(m->material_id, 0u);
  EXPECT_TRUE(m->position.isApprox(Eigen::Vector3d(-0.25, 0.5, -5), 1e-7));
  EXPECT_TRUE(m->geometric_normal.isApprox(Eigen::Vector3d(0, 0, 1), 1e-9));
  EXPECT_NEAR(m->uv.x(), 0.25, 1e-6);

  // From above, the identity instance at z = 0 is hit first.
  auto first = scene.Intersect(Down(0.5, 0.25, 10));
  ASSERT_TRUE(first);
  EXPECT_EQ(first->instance_id, 0u);
}

TEST(EmbreeScene, InterpolatesShadingNormals) {
  auto g = Geometry({Eigen::Affine3d(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))});
  // Tilt vertex normals: corners 1 and 2 lean toward +x.
  g->meshes[0].normals[1] = Eigen::Vector3f(1, 0, 1).normalized();
  g->meshes[0].normals[2] = Eigen::Vector3f(1, 0, 1).normalized();
  EmbreeScene scene(g);
  // World point (-0.25, 0.75, 0) is mesh point (0.75, 0.25, 0): triangle {0,1,2},
  // barycentrics (u, v) = (0.5, 0.25) for corners 1 and 2, weight 0.25 for corner 0.
  auto hit = scene.Intersect(Down(-0.25, 0.75));
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->primitive_id, 0u);
  EXPECT_NEAR(hit->barycentric.x(), 0.5, 1e-6);
  EXPECT_NEAR(hit->barycentric.y(), 0.25, 1e-6);
  Eigen::Vector3d n_mesh = 0.25 * Eigen::Vector3d(0, 0, 1) + 0.75 * Eigen::Vector3d(1, 0, 1).normalized();
  Eigen::Vector3d expected = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) * n_mesh).normalized();
  EXPECT_TRUE(hit->shading_normal.isApprox(expected, 1e-6)) << hit->shading_normal.transpose();
  EXPECT_TRUE(hit->geometric_normal.isApprox(Eigen::Vector3d(0, 0, 1), 1e-9));
}

// Millimetre geometry 1 km from the origin: a 1 mm square at (1000, -1000, 500) m.
// A ray 5 um inside an edge hits, 5 um outside misses, and the hit point is exact
// to well under a micrometre. In a float world frame the spacing of floats near
// 1000 m is 61 um, so neither would be resolved; the render-frame offset makes it work.
TEST(EmbreeScene, MillimetreGeometryOneKilometreAway) {
  const Eigen::Vector3d corner(1000.0, -1000.0, 500.0);
  Eigen::Affine3d world_from_mesh = Eigen::Translation3d(corner) * Eigen::Scaling(1e-3);
  EmbreeScene scene(Geometry({world_from_mesh}));
  EXPECT_TRUE(scene.render_origin().isApprox(corner + Eigen::Vector3d(0.5e-3, 0.5e-3, 0), 1e-15));
  const double inside = 5e-6;
  for (int edge = 0; edge < 4; ++edge) {
    Eigen::Vector3d in = corner, out = corner;
    double c = 0.5e-3;
    switch (edge) {
      case 0: in += Eigen::Vector3d(inside, c, 0); out += Eigen::Vector3d(-inside, c, 0); break;
      case 1: in += Eigen::Vector3d(1e-3 - inside, c, 0); out += Eigen::Vector3d(1e-3 + inside, c, 0); break;
      case 2: in += Eigen::Vector3d(c, inside, 0); out += Eigen::Vector3d(c, -inside, 0); break;
      case 3: in += Eigen::Vector3d(c, 1e-3 - inside, 0); out += Eigen::Vector3d(c, 1e-3 + inside, 0); break;
    }
    auto hit = scene.Intersect({in + Eigen::Vector3d(0, 0, 0.1), {0, 0, -1}});
    ASSERT_TRUE(hit) << edge;
    EXPECT_LT((hit->position - in).norm(), 1e-12) << edge;  // double precision near 1 km: 1e-13
    EXPECT_NEAR(hit->t, 0.1, 1e-12);
    EXPECT_FALSE(scene.Intersect({out + Eigen::Vector3d(0, 0, 0.1), {0, 0, -1}})) << edge;
  }
}

TEST(EmbreeScene, IntersectManyMatchesIntersect) {
  Eigen::Affine3d tilted = Eigen::Translation3d(0, 0, 0.5) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
  EmbreeScene scene(Geometry({Eigen::Affine3d::Identity(), tilted}));
  std::vector<Ray> rays;
  for (int i = 0; i < 40; ++i) {
    for (int j = 0; j < 40; ++j) rays.push_back(Down(-0.2 + i * 0.035, -0.2 + j * 0.035, 3));
  }
  std::vector<std::optional<Hit>> hits(rays.size());
  scene.IntersectMany(rays, hits);
  int n_hits = 0;
  for (size_t k = 0; k < rays.size(); ++k) {
    auto single = scene.Intersect(rays[k]);
    ASSERT_EQ(single.has_value(), hits[k].has_value()) << k;
    if (single) {
      ++n_hits;
      EXPECT_EQ(single->instance_id, hits[k]->instance_id);
      EXPECT_EQ(single->position, hits[k]->position);
    }
  }
  EXPECT_GT(n_hits, 800);
}

TEST(EmbreeScene, EmptySceneHitsNothing) {
  EmbreeScene scene(Geometry({}));
  EXPECT_TRUE(scene.bounds().isEmpty());
  EXPECT_FALSE(scene.Intersect(Down(0.5, 0.5)));
  EXPECT_FALSE(scene.Occluded(Down(0.5, 0.5)));
}

TEST(EmbreeScene, InvalidRaysAreRejected) {
  EmbreeScene scene(Geometry({Eigen::Affine3d::Identity()}));
  EXPECT_THROW(scene.Intersect({{0, 0, 1}, {0, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(scene.Intersect({{std::nan(""), 0, 1}, {0, 0, -1}}), std::invalid_argument);
}

TEST(EmbreeScene, DeviceErrorsBecomeExceptions) {
  EmbreeScene scene(Geometry({Eigen::Affine3d::Identity()}));
  EXPECT_NO_THROW(scene.CheckDevice());
  // Refit is not a valid build quality for a scene: Embree reports an invalid argument.
  rtcSetSceneBuildQuality(scene.handle(), RTC_BUILD_QUALITY_REFIT);
  try {
    scene.CheckDevice();
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("Embree error while using the scene: unknown error: invalid build quality"));
  }
}

}  // namespace
}  // namespace lt
