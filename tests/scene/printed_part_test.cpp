// The printed part growing along a gcode motion (scene/printed_part.h): chunking,
// rebuilding only what changed, ray casts against the beads over time, and the
// scene file's "print" key.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scene/bead_geometry.h"
#include "scene/embree_scene.h"
#include "scene/printed_part.h"
#include "scene/scene_file.h"
#include "scene/scene_geometry.h"
#include "test_util.h"

namespace lt {
namespace {

using test::ErrorOf;
using test::TempDir;
using test::WriteText;
using ::testing::HasSubstr;

// Two 20 mm lines at z = 0.2 mm, 10 mm apart, at 20 mm/s with travels between
// them: line A from (0,0) to (20,0) during [0.01, 1.01] s, line B from (0,10) to
// (20,10) during [2.51, 3.51] s.
const char* kTwoLines = R"(;Layer height: 0.2
G0 F1200 Z0.2
G1 X20 E0.8
G0 Y10
G0 X0
G1 X20 Y10 E1.6
)";

std::string SceneText(const std::string& motion_type, const std::string& print) {
  return std::string(R"({"objects": [{"name": "bed", "gltf": ")") + LT_SOURCE_DIR +
         R"(/scenes/demo/print_bed.glb"}],
  "materials": {"pla": {"base_color": [0.8, 0.8, 0.8], "roughness": 0.5}},
  "sensor": {"camera": {"resolution": [32, 24], "pixel_pitch_um": 10, "focal_length_mm": 8, "f_number": 4}},
  "motion": )" + (motion_type == "gcode" ? std::string(R"({"type": "gcode", "file": "part.gcode"})")
                                                  : std::string(R"({"type": "static"})")) +
         (print.empty() ? "" : ", \"print\": " + print) + "}";
}

struct PrintWorld {
  TempDir dir;
  SceneFile scene;
  std::shared_ptr<SceneGeometry> geometry;
  std::unique_ptr<EmbreeScene> embree;
  std::unique_ptr<PrintedPart> part;

  explicit PrintWorld(const std::string& print = R"({"material": "pla", "chunk_moves": 1})") {
    WriteText(dir / "part.gcode", kTwoLines);
    scene = ParseSceneText(SceneText("gcode", print), "scene.json", dir.path());
    geometry = std::make_shared<SceneGeometry>(LoadSceneGeometry(scene));
    embree = std::make_unique<EmbreeScene>(geometry);
    part = std::make_unique<PrintedPart>(std::get<GcodeMotion>(scene.motion), *scene.print, geometry->print_meshes);
  }
  // What a ray straight down at bed point (x, y) mm of the G-code frame hits:
  // its height in mm and instance id.
  std::pair<double, uint32_t> Down(double x_mm, double y_mm) const {
    Ray ray;
    ray.origin = Eigen::Vector3d(x_mm * 1e-3, y_mm * 1e-3, 0.05);
    ray.direction = -Eigen::Vector3d::UnitZ();
    auto hit = embree->Intersect(ray);
    EXPECT_TRUE(hit);
    return hit ? std::make_pair(hit->position.z() * 1e3, hit->instance_id) : std::make_pair(-1.0, 0u);
  }
};

TEST(PrintedPart, ChunksCutAtTravelsAndPartitionTheFullMesh) {
  PrintWorld w;
  const Toolpath& path = std::get<GcodeMotion>(w.scene.motion).toolpath->path();
  // Moves: travel, line A, travel, travel, line B: with chunk_moves 1 the cuts come
  // after each move that does not extrude (before A, before B's travel... ).
  const auto& chunks = w.part->chunks();
  ASSERT_EQ(chunks.size(), w.geometry->print_meshes.size());
  ASSERT_GE(chunks.size(), 2u);
  size_t triangles = 0;
  double volume = 0;
  for (size_t c = 0; c < chunks.size(); ++c) {
    Mesh m = w.part->ChunkMesh(c, path.Duration());
    triangles += m.TriangleCount();
    volume += MeshVolume(m);
    if (c > 0) {
      EXPECT_EQ(chunks[c].first_segment, chunks[c - 1].end_segment);
    }
  }
  EXPECT_EQ(chunks.back().end_segment, path.segments.size());
  BeadOptions options;
  options.points_per_half_disc = w.scene.print->points_per_half_disc;
  Mesh full = BeadMeshUpTo(path, path.Duration(), options);
  EXPECT_EQ(triangles, full.TriangleCount());
  EXPECT_EQ(PrintTrianglesWhenComplete(path, *w.scene.print), full.TriangleCount());
  PrintSettings one_chunk = *w.scene.print;
  one_chunk.chunk_moves = 1000;
  EXPECT_EQ(PrintTrianglesWhenComplete(path, one_chunk), full.TriangleCount());
  EXPECT_NEAR(volume, MeshVolume(full), 1e-6 * MeshVolume(full));
  // Two beads of 0.8 mm of 1.75 mm filament each (volume conserved up to float rounding).
  EXPECT_NEAR(volume, 2 * M_PI * 0.25 * 1.75e-3 * 1.75e-3 * 0.8e-3, 1e-5 * volume);
}

TEST(PrintedPart, BeadsAppearInTheSceneAfterTheirTimeOnly) {
  PrintWorld w;
  const std::vector<size_t>& meshes = w.geometry->print_meshes;
  auto is_print = [&](uint32_t instance) { return w.geometry->instances[instance].object == w.scene.objects.size(); };
  // t = 0.51 s: the nozzle is half way along line A (at x = 10 mm).
  PrintUpdate u = w.part->UpdateTo(*w.embree, 0.51);
  EXPECT_GT(u.triangles, 0u);
  auto [z, inst] = w.Down(5, 0);  // printed already: the bead's top, 0.2 mm
  EXPECT_NEAR(z, 0.2, 1e-6);
  EXPECT_TRUE(is_print(inst));
  EXPECT_NEAR(w.Down(15, 0).first, 0.0, 1e-9);  // not yet printed: the bed
  EXPECT_NEAR(w.Down(5, 10).first, 0.0, 1e-9);  // line B not started
  // The same time again: nothing to rebuild.
  u = w.part->UpdateTo(*w.embree, 0.51);
  EXPECT_EQ(u.chunks_rebuilt, 0u);
  EXPECT_EQ(u.triangles_rebuilt, 0u);
  // t = 3 s: line A complete, line B printed up to x = 9.8 mm.
  u = w.part->UpdateTo(*w.embree, 3.0);
  EXPECT_EQ(u.chunks_rebuilt, 2u);  // A completes, B starts growing
  EXPECT_NEAR(w.Down(15, 0).first, 0.2, 1e-6);
  EXPECT_NEAR(w.Down(5, 10).first, 0.2, 1e-6);
  EXPECT_NEAR(w.Down(15, 10).first, 0.0, 1e-9);
  // t = 3.2 s: only the growing chunk (B) is rebuilt; A never again.
  u = w.part->UpdateTo(*w.embree, 3.2);
  EXPECT_EQ(u.chunks_rebuilt, 1u);
  EXPECT_EQ(u.triangles_rebuilt, w.geometry->meshes[meshes.back()].TriangleCount());
  EXPECT_LT(u.triangles_rebuilt, u.triangles);
  EXPECT_NEAR(w.Down(15, 10).first, 0.0, 1e-9);  // x = 15 mm is reached at 3.26 s
  EXPECT_NEAR(w.Down(13, 10).first, 0.2, 1e-6);
  // Back in time (frames rendered out of order): line B disappears again.
  u = w.part->UpdateTo(*w.embree, 0.51);
  EXPECT_NEAR(w.Down(5, 10).first, 0.0, 1e-9);
  EXPECT_NEAR(w.Down(15, 0).first, 0.0, 1e-9);
  // The bounds grew to hold the beads (top at 0.2 mm).
  EXPECT_NEAR(w.embree->bounds().max().z(), 0.2e-3, 1e-9);
}

TEST(PrintedPart, DefaultMaterialIsSubsurfacePla) {
  PrintWorld w(R"({})");
  const SceneInstance& inst = w.geometry->instances.back();
  ASSERT_GE(inst.material_override, 0);
  const Material& m = w.geometry->materials[size_t(inst.material_override)];
  EXPECT_EQ(m.name, "print_pla");
  ASSERT_TRUE(m.subsurface);
  EXPECT_DOUBLE_EQ(m.subsurface->mean_free_path_laser_m, 0.35e-3);
  EXPECT_EQ(w.scene.resolved["print"]["chunk_moves"], 200);
  EXPECT_EQ(w.geometry->object_names.back(), "print");
}

TEST(PrintedPart, SceneKeyErrors) {
  TempDir dir;
  WriteText(dir / "part.gcode", kTwoLines);
  auto error = [&](const std::string& motion, const std::string& print) {
    return ErrorOf([&] { ParseSceneText(SceneText(motion, print), "scene.json", dir.path()); });
  };
  EXPECT_THAT(error("static", "{}"), HasSubstr("scene.json: /print: needs a \"gcode\" motion"));
  EXPECT_THAT(error("gcode", R"({"material": "abs"})"), HasSubstr("/print/material: unknown material \"abs\""));
  EXPECT_THAT(error("gcode", R"({"chunk_moves": 0})"), HasSubstr("/print/chunk_moves"));
  EXPECT_THAT(error("gcode", R"({"layer_height_mm": -1})"), HasSubstr("/print/layer_height_mm"));
  EXPECT_THAT(error("gcode", R"({"colour": 1})"), HasSubstr("/print/colour"));
}

TEST(EmbreeScene, ReplaceMeshNeedsMutableGeometry) {
  auto g = std::make_shared<const SceneGeometry>();
  EmbreeScene scene(g);
  EXPECT_FALSE(scene.mutable_geometry());
  EXPECT_THROW(scene.ReplaceMesh(0, Mesh{}), std::logic_error);
  EmbreeScene mutable_scene(std::make_shared<SceneGeometry>());
  EXPECT_THROW(mutable_scene.ReplaceMesh(0, Mesh{}), std::out_of_range);
}

}  // namespace
}  // namespace lt
