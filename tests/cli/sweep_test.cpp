// `lasertwin sweep` on the tiny scan scene with a short ladder: every
// configuration gets a run folder, a CSV row with finite times and errors, and
// the Pareto plot is written. Bad options exit with code 2.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

#include "run_many.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kScene = fs::path(LT_SOURCE_DIR) / "tests/data/scenes/tiny_scan.json";

TEST(SweepCommand, QuickLadder) {
  const fs::path dir = TestFolder("sweep");
  CliResult r = RunCli("sweep " + Quoted(kScene) + " --out " + Quoted(dir) + " --quick --spp 1,2 --methods com,max --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream csv(ReadFile(dir / "sweep.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_THAT(line, HasSubstr("name,factor,spp,adaptive_sampling,max_bounces,subsurface,resolution,method"));
  std::vector<std::string> names;
  while (std::getline(csv, line)) {
    names.push_back(line.substr(0, line.find(',')));
    EXPECT_EQ(line.find("nan"), std::string::npos) << line;
    EXPECT_EQ(line.find(",,"), std::string::npos) << line;  // every value present on this scene
  }
  // spp 1 and 2 with both methods, then adaptive sampling off, 0 bounces,
  // subsurface off and half resolution with the first method.
  EXPECT_EQ(names.size(), 2u * 2 + 4);
  for (const char* run : {"spp1", "spp2", "adaptive_off", "bounces0", "subsurface_off", "half_resolution"}) {
    EXPECT_TRUE(fs::exists(dir / "runs" / run / "metrics_com.json")) << run;
    EXPECT_TRUE(fs::exists(dir / "runs" / run / "centers_com")) << run;
  }
  EXPECT_TRUE(fs::exists(dir / "runs/spp1/report_max.html"));
  EXPECT_FALSE(fs::exists(dir / "runs/bounces0/metrics_max.json"));
  // The half-resolution run renders 48x36 frames on the camera binned 2 x 2:
  // a binned pixel's well holds 4 pixels' charge at a quarter of the gain, so
  // its images keep the full-resolution run's level.
  const nlohmann::json full = nlohmann::json::parse(ReadFile(dir / "runs/spp1/rig.json"));
  const nlohmann::json half = nlohmann::json::parse(ReadFile(dir / "runs/half_resolution/rig.json"));
  EXPECT_EQ(half["camera"]["resolution"], nlohmann::json::array({48, 36}));
  EXPECT_EQ(full["camera"]["resolution"], nlohmann::json::array({96, 72}));
  EXPECT_DOUBLE_EQ(half["image_sensor"]["full_well_e"].get<double>(), 4 * full["image_sensor"]["full_well_e"].get<double>());
  EXPECT_DOUBLE_EQ(half["image_sensor"]["system_gain_dn_per_e"].get<double>(),
                   full["image_sensor"]["system_gain_dn_per_e"].get<double>() / 4);
  const std::string svg = ReadFile(dir / "pareto.svg");
  EXPECT_THAT(svg, HasSubstr("Pareto front"));
  EXPECT_THAT(svg, HasSubstr("half_resolution"));
  // --replot draws the plot again from sweep.csv alone.
  fs::remove(dir / "pareto.svg");
  r = RunCli("sweep " + Quoted(kScene) + " --out " + Quoted(dir) + " --replot");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // (sweep.csv rounds the times: the same points, labels and front.)
  const std::string replotted = ReadFile(dir / "pareto.svg");
  auto count = [](const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count(replotted, "<circle"), count(svg, "<circle"));
  for (const char* label : {"spp1/com", "spp2/max", "half_resolution", "bounces0", "Pareto front"}) {
    EXPECT_EQ(count(replotted, label), count(svg, label)) << label;
  }
}

// A scene with several laser sheets: com and max find one stripe per search
// line, so the default methods are multicom and steger (com led the list, and
// the one-factor configurations took it).
TEST(SweepCommand, SeveralSheetsTakeMultiPeakMethods) {
  const fs::path dir = NewTestFolder("sweep_sheets");
  std::string scene = ReadFile(kScene);
  const std::string laser = "\"fan_angle_deg\": 40,";
  ASSERT_NE(scene.find(laser), std::string::npos);
  scene.replace(scene.find(laser), laser.size(), laser + " \"sheet_count\": 3, \"sheet_spacing_deg\": 2,");
  const std::string glb = "../../../scenes/demo/";
  for (size_t at; (at = scene.find(glb)) != std::string::npos;) {
    scene.replace(at, glb.size(), (fs::path(LT_SOURCE_DIR) / "scenes/demo/").string());
  }
  std::ofstream(dir / "three.json") << scene;
  CliResult r = RunCli("sweep " + Quoted(dir / "three.json") + " --out " + Quoted(dir / "out") + " --quick --spp 1 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string csv = ReadFile(dir / "out/sweep.csv");
  EXPECT_THAT(csv, HasSubstr(",multicom,"));
  EXPECT_THAT(csv, HasSubstr(",steger,"));
  EXPECT_THAT(csv, Not(HasSubstr(",com,")));
  EXPECT_TRUE(fs::exists(dir / "out/runs/bounces0/metrics_multicom.json"));
}

TEST(SweepCommand, BadOptions) {
  const fs::path dir = NewTestFolder("sweep_bad");
  auto results = RunMany({"sweep " + Quoted(kScene) + " --out " + Quoted(dir) + " --methods fastest",
                          "sweep " + Quoted(kScene) + " --out " + Quoted(dir) + " --spp 0,4",
                          "sweep " + Quoted(dir / "none.json") + " --out " + Quoted(dir)});
  EXPECT_EQ(results[0].exit_code, 2);
  EXPECT_THAT(results[0].err, HasSubstr("unknown extraction method 'fastest'"));
  EXPECT_EQ(results[1].exit_code, 2);
  EXPECT_THAT(results[1].err, HasSubstr("--spp: expected positive whole numbers"));
  EXPECT_EQ(results[2].exit_code, 2);
  EXPECT_FALSE(fs::exists(dir / "sweep.csv"));
}

}  // namespace
}  // namespace lt::test
