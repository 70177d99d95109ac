// `lasertwin eval` end to end: render tests/data/scenes/tiny_scan.json (a 96x72
// camera over the demo's slot test part, one laser sheet), scan it, evaluate
// it; metrics.json must be finite and plausible and report.html self-contained.
// Bad input gives exit code 2 and a message naming the file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "pipeline/run_folder_reader.h"
#include "pipeline/scan_output.h"
#include "run_many.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kScene = fs::path(LT_SOURCE_DIR) / "tests/data/scenes/tiny_scan.json";

// Every number in the document is finite (nlohmann cannot parse NaN, but check
// the values anyway) and every statistic is a number or null.
void ExpectFinite(const nlohmann::json& j, const std::string& where) {
  if (j.is_number()) {
    EXPECT_TRUE(std::isfinite(j.get<double>())) << where;
  }
  if (j.is_object()) {
    for (auto& [k, v] : j.items()) ExpectFinite(v, where + "/" + k);
  }
  if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) ExpectFinite(j[i], where + "/" + std::to_string(i));
  }
}

TEST(EvalCommand, RenderScanEval) {
  const fs::path dir = TestFolder("eval_run");
  CliResult r = RunCli("render " + Quoted(kScene) + " --out " + Quoted(dir) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Before scanning: a clean error that says what to do.
  r = RunCli("eval " + Quoted(dir));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr((dir / "centers").string() + ": no measured centres: run `lasertwin scan"));
  // The tiny camera's 48 um pixels make the stripe narrower than com's default
  // minimum width (1.5 px FWHM), which would drop a third of the columns.
  r = RunCli("scan " + Quoted(dir) + " --min-width 0 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = RunCli("eval " + Quoted(dir));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("stripe centre error  rms"));
  EXPECT_THAT(r.out, HasSubstr("report " + (dir / "report.html").string()));

  const nlohmann::json m = nlohmann::json::parse(ReadFile(dir / "metrics.json"));
  ExpectFinite(m, "");
  EXPECT_EQ(m["frames_evaluated"].get<int>(), 2);  // frames 1 and 3 are the laser frames of 4
  ASSERT_EQ(m["frames"].size(), 2u);
  // A 4 spp render of a matte part with a 10-bit sensor: com finds the stripe
  // on nearly every scan line, to a few tenths of a pixel at this coarse
  // resolution (measured: rms 0.30 px, detection 0.99); these bounds catch a
  // broken comparison (wrong axis, wrong frame, unit errors), not noise.
  EXPECT_GT(m["stripe_center_error_px"]["n"].get<int>(), 100);
  EXPECT_LT(m["stripe_center_error_px"]["rms"].get<double>(), 1.0);
  EXPECT_GT(m["detection_rate"].get<double>(), 0.9);
  EXPECT_DOUBLE_EQ(m["plane_id_accuracy"].get<double>(), 1.0);  // one sheet
  // One pixel is about 0.45 mm on the part here (measured median 0.11 mm).
  EXPECT_GT(m["point_error_mm"]["n"].get<int>(), 100);
  EXPECT_LT(m["point_error_mm"]["median"].get<double>(), 0.3);
  // scan placed the points with the manifest's poses: the stitched world points score the same.
  EXPECT_THAT(r.out, HasSubstr("stitched point error rms"));
  EXPECT_EQ(m["stitched_point_error_mm"]["n"], m["point_error_mm"]["n"]);
  EXPECT_NEAR(m["stitched_point_error_mm"]["max"].get<double>(), m["point_error_mm"]["max"].get<double>(), 1e-9);
  EXPECT_GT(m["completeness"].get<double>(), 0.0);
  EXPECT_LE(m["completeness"].get<double>(), 1.0);

  const std::string html = ReadFile(dir / "report.html");
  EXPECT_THAT(html, HasSubstr("<svg"));
  EXPECT_THAT(html, HasSubstr("data:image/png;base64,"));
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);

  // Options: a frame range, and a tighter completeness can only lower completeness.
  r = RunCli("eval " + Quoted(dir) + " --frames 3 --completeness-mm 0.001 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  const nlohmann::json one = nlohmann::json::parse(ReadFile(dir / "metrics.json"));
  EXPECT_EQ(one["frames_evaluated"].get<int>(), 1);
  EXPECT_EQ(one["frames"][0]["index"].get<int>(), 3);
  EXPECT_LE(one["completeness"].get<double>(), m["completeness"].get<double>());
}

// A box (10 x 10 x 10 mm: its top and its +x side wall, made of the unit
// square tests/data/gltf/square.gltf) on a 40 mm bed, under tiny_scan's camera
// 83 mm above its centre. The side wall faces away from the camera and lies
// under the top's edge: no pixel sees it. A measured point 0.5 mm beside the
// wall, halfway up, projects beyond the top's silhouette onto the bed, 5 mm
// below it. Its distance to the true surface is 0.5 mm (to the wall); the
// ground-truth buffers, which hold only the top and the bed, put it about 5 mm
// away (the tangent planes of the bed and of the top, both 5 mm off).
TEST(EvalCommand, APointNearAFaceNoPixelSeesScoresItsDistanceToTheScene) {
  const fs::path dir = NewTestFolder("eval_hidden_face");
  const std::string square = (fs::path(LT_SOURCE_DIR) / "tests/data/gltf/square.gltf").string();
  nlohmann::json scene = nlohmann::json::parse(ReadFile(kScene));
  scene["objects"] = {
      {{"name", "bed"}, {"gltf", square}, {"scale", 4},
       {"world_from_object", {{"translation_m", {-0.02, -0.02, 0}}}}},
      {{"name", "top"}, {"gltf", square}, {"material", "pla"},
       {"world_from_object", {{"translation_m", {-0.005, -0.005, 0.01}}}}},
      // (x, y, 0) -> (0, y, x): the plane x = 5 mm, y in [-5, 5] mm, z in [0, 10] mm.
      {{"name", "wall"}, {"gltf", square}, {"material", "pla"},
       {"world_from_object", {{"translation_m", {0.005, -0.005, 0}}, {"rotation_rpy_deg", {0, -90, 0}}}}}};
  scene["render"]["frames"] = 2;
  const fs::path scene_file = dir / "box.json";
  std::ofstream(scene_file) << scene.dump(2);
  const fs::path run = dir / "run";
  CliResult r = RunCli("render " + Quoted(scene_file) + " --out " + Quoted(run) + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  // Two measured points of laser frame 1: the one beside the hidden wall, and
  // a true stripe point (on the visible top or bed, so 0 by either method).
  const std::vector<RunFrame> frames = ReadRunManifest(run);
  ASSERT_EQ(frames.size(), 2u);
  ASSERT_TRUE(frames[1].world_from_cam && frames[1].gt_centers);
  const Pose cam_from_world = frames[1].world_from_cam->inverse();
  const RunRig rig = ReadRunRig(run);
  const Eigen::Vector3d beside_wall = cam_from_world * Eigen::Vector3d(0.0055, -0.002, 0.005);
  const Eigen::Vector2d pixel = *rig.camera.Project(beside_wall);
  ASSERT_TRUE(rig.camera.InImage(pixel));
  const std::string truth = ReadFile(*frames[1].gt_centers);
  const size_t second_line = truth.find('\n') + 1;
  ASSERT_LT(second_line, truth.size()) << "no stripe centre in frame 1";
  std::istringstream row(truth.substr(second_line));
  double u = 0, v = 0, x = 0, y = 0, z = 0;
  int plane = 0;
  char comma = 0;
  row >> u >> comma >> v >> comma >> plane >> comma >> x >> comma >> y >> comma >> z;
  ScanPoint hidden, visible;
  hidden.pixel = {std::round(pixel.x()), pixel.y(), 2.0, 500.0, 0};  // on a whole column: the run scans columns
  hidden.p_in_cam = beside_wall;
  visible.pixel = {u, v, 2.0, 500.0, 0};
  visible.p_in_cam = Eigen::Vector3d(x, y, z);
  fs::create_directories(run / "centers");
  WriteScanCsv(run / "centers/000001.csv", {hidden, visible});

  r = RunCli("eval " + Quoted(run) + " --frames 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("point error measured to the scene's surfaces (scene.json)"));
  const nlohmann::json m = nlohmann::json::parse(ReadFile(run / "metrics.json"));
  EXPECT_EQ(m["point_error_method"], "scene");
  EXPECT_EQ(m["point_error_mm"]["n"].get<int>(), 2);
  // The wall is at x = 5 mm exactly (float corners of 0.01 m squares: ~1e-9 m);
  // the points went through the CSV with 10 digits (1e-11 m).
  EXPECT_NEAR(m["point_error_mm"]["max"].get<double>(), 0.5, 1e-5);
  // The true stripe point is on a triangle: rms sqrt((0.5^2 + e^2) / 2) with e < 1e-5 mm.
  EXPECT_NEAR(m["point_error_mm"]["rms"].get<double>(), std::sqrt(0.125), 1e-5);
  EXPECT_EQ(m["counts"]["points_off_surface"].get<int>(), 0);

  // The buffers (as before, and still for a run without scene.json): 5 mm.
  r = RunCli("eval " + Quoted(run) + " --frames 1 --gt-buffers");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("point error measured to the surfaces the pixels see (ground-truth buffers)"));
  const nlohmann::json b = nlohmann::json::parse(ReadFile(run / "metrics.json"));
  EXPECT_EQ(b["point_error_method"], "gt_buffers");
  EXPECT_NEAR(b["point_error_mm"]["max"].get<double>(), 5.0, 0.5);
  const fs::path moved = dir / "scene.json.moved";
  fs::rename(run / "scene.json", moved);
  r = RunCli("eval " + Quoted(run) + " --frames 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr((run / "scene.json").string() + ": no such file (a recorded run)"));
  const nlohmann::json none = nlohmann::json::parse(ReadFile(run / "metrics.json"));
  EXPECT_EQ(none["point_error_method"], "gt_buffers");
  EXPECT_THAT(none["point_error_note"].get<std::string>(), HasSubstr("no such file"));

  // A scene.json that cannot be loaded (here: its glTF moved away) leaves the
  // buffers too, and says why, naming the file.
  nlohmann::json broken = nlohmann::json::parse(ReadFile(moved));
  broken["objects"][2]["gltf"] = (dir / "gone.gltf").string();
  std::ofstream(run / "scene.json") << broken.dump();
  r = RunCli("eval " + Quoted(run) + " --frames 1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr((dir / "gone.gltf").string()));
  EXPECT_THAT(r.out, HasSubstr("the run's scene could not be loaded"));
  EXPECT_EQ(nlohmann::json::parse(ReadFile(run / "metrics.json"))["point_error_method"], "gt_buffers");
}

TEST(EvalCommand, BadInput) {
  const fs::path dir = NewTestFolder("eval_bad");
  auto results = RunMany({"eval " + Quoted(dir / "nowhere"), "eval " + Quoted(dir) + " --max-match-px 0",
                          "eval " + Quoted(dir) + " --frames 5:2"});
  EXPECT_EQ(results[0].exit_code, 2);
  EXPECT_THAT(results[0].err, HasSubstr((dir / "nowhere").string() + ": run folder not found"));
  EXPECT_EQ(results[1].exit_code, 2);
  EXPECT_THAT(results[1].err, HasSubstr("max_match_px: must be a finite number > 0"));
  EXPECT_EQ(results[2].exit_code, 2);
  EXPECT_THAT(results[2].err, HasSubstr("--frames: empty frame range"));
}

}  // namespace
}  // namespace lt::test
