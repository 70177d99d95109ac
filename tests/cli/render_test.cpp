// `lasertwin render` end to end on a tiny scene: the run folder's files, resume,
// and clean errors (exit 2) for bad input.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "cli_util.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kScene = fs::path(LT_SOURCE_DIR) / "tests/data/scenes/tiny_scan.json";

std::vector<nlohmann::json> Manifest(const fs::path& dir) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(ReadFile(dir / "manifest.jsonl"));
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

TEST(RenderCommand, WritesTheRunFolderAndResumes) {
  fs::path dir = TestFolder("render_resume");
  CliResult r = RunCli("render " + Quoted(kScene) + " --out " + Quoted(dir) + " --frames 0:2 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");  // --quiet
  auto lines = Manifest(dir);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0]["label"], "bright");
  EXPECT_EQ(lines[1]["label"], "dim");
  for (const auto& l : lines) {
    for (auto& [k, v] : l["files"].items()) EXPECT_TRUE(fs::exists(dir / v.get<std::string>())) << v;
  }
  EXPECT_TRUE(fs::exists(dir / "scene.json"));
  EXPECT_TRUE(fs::exists(dir / "rig.json"));
  EXPECT_FALSE(lines[0]["files"].contains("centers"));  // the laser is off in the bright frame
  EXPECT_GT(lines[1]["stripe_centers"].get<int>(), 40);
  // Where the frame's pixels saturate: full well above the black level, within the ADC's range.
  for (const auto& l : lines) {
    const double sat = l["saturation_dn"].get<double>();
    EXPECT_GT(sat, 0.0);
    EXPECT_LE(sat, std::ldexp(1.0, l["bit_depth"].get<int>()) - 1);
  }
  // The frame's time and its parts: each part within the whole, the samples' pass
  // a part of it.
  for (const auto& l : lines) {
    const auto& stats = l["stats"];
    const double render_ms = stats["render_ms"].get<double>();
    double parts = 0;
    for (const char* k : {"chief_rays", "entry_trees", "budgets", "samples", "light_paths", "film_and_sensor"}) {
      ASSERT_TRUE(stats["pass_ms"].contains(k)) << k;
      EXPECT_GE(stats["pass_ms"][k].get<double>(), 0.0) << k;
      parts += stats["pass_ms"][k].get<double>();
    }
    EXPECT_GT(stats["pass_ms"]["samples"].get<double>(), 0.0);
    EXPECT_LE(parts, render_ms * (1 + 1e-9));
  }
  auto first_write = fs::last_write_time(dir / "frames/000001.png");

  // Without --resume an existing run is refused; with it, only new frames render.
  r = RunCli("render " + Quoted(kScene) + " --out " + Quoted(dir) + " --quiet");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("already holds a run"));
  // A range past the scene's end renders what there is, and says so.
  r = RunCli("render " + Quoted(kScene) + " --out " + Quoted(dir) + " --resume --frames 0:100");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("note: --frames 0:100: the scene has 4 frames; rendering 0..3"));
  EXPECT_THAT(r.err, HasSubstr("rendered 2 frames"));
  EXPECT_THAT(r.err, HasSubstr("2 already complete"));
  EXPECT_EQ(Manifest(dir).size(), 4u);
  EXPECT_EQ(fs::last_write_time(dir / "frames/000001.png"), first_write);
  // A different seed is a different scene: resume refuses it.
  r = RunCli("render " + Quoted(kScene) + " --out " + Quoted(dir) + " --resume --seed 9");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("different scene"));
  // No temporary files are left behind.
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }
  fs::remove_all(dir);
}

// tiny_scan.json with its objects' paths made absolute and `edit` applied, written to `path`.
void WriteEditedScene(const fs::path& path, const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json scene = nlohmann::json::parse(ReadFile(kScene));
  for (auto& o : scene["objects"]) o["gltf"] = (kScene.parent_path() / o["gltf"].get<std::string>()).lexically_normal().string();
  edit(scene);
  std::ofstream(path) << scene.dump(2);
}

// A run without radiance and ground truth has no radiance/ or gt/ folder; a
// scene the renderer refuses (more sheets than a rig holds) leaves no folder.
TEST(RenderCommand, WritesOnlyWhatTheSceneAsksFor) {
  fs::path dir = TestFolder("render_outputs");
  fs::create_directories(dir);
  WriteEditedScene(dir / "frames_only.json", [](nlohmann::json& s) {
    s["output"]["write_radiance"] = false;
    s["output"]["write_ground_truth"] = false;
  });
  CliResult r = RunCli("render " + Quoted(dir / "frames_only.json") + " --out " + Quoted(dir / "run") +
                       " --frames 1:2 --spp 1 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "run/frames/000001.png"));
  EXPECT_FALSE(fs::exists(dir / "run/radiance"));
  EXPECT_FALSE(fs::exists(dir / "run/gt"));

  WriteEditedScene(dir / "too_many_sheets.json", [](nlohmann::json& s) {
    auto& laser = s["sensor"]["lasers"][0];
    laser["sheet_count"] = 65;
    laser["sheet_spacing_deg"] = 0.5;
  });
  r = RunCli("render " + Quoted(dir / "too_many_sheets.json") + " --out " + Quoted(dir / "refused") + " --quiet");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("/sensor/lasers/0/sheet_count: must be <= 64"));
  EXPECT_FALSE(fs::exists(dir / "refused"));
  fs::remove_all(dir);
}

TEST(RenderCommand, BadInputIsExitCodeTwo) {
  fs::path dir = TestFolder("render_bad");
  struct Case {
    std::string args, message;
  } cases[] = {
      {"render /no/such/scene.json --out " + Quoted(dir), "/no/such/scene.json"},
      {"render " + Quoted(kScene) + " --out " + Quoted(dir) + " --frames 7:9", "selects no frame"},
      {"render " + Quoted(kScene) + " --out " + Quoted(dir) + " --frames 3:1", "empty frame range"},
      {"render " + Quoted(kScene) + " --out " + Quoted(dir) + " --frames x", "--frames"},
      {"render " + Quoted(kScene) + " --out " + Quoted(dir) + " --spp 0", "spp"},
      {"render " + Quoted(kScene), "--out"},
  };
  for (const auto& c : cases) {
    CliResult r = RunCli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args;
    EXPECT_THAT(r.err, HasSubstr(c.message)) << c.args;
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lt::test
