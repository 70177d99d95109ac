// `lasertwin eval` end to end: render tests/data/scenes/tiny_scan.json (a 96x72
// camera over the demo's slot test part, one laser sheet), scan it, evaluate
// it; metrics.json must be finite and plausible and report.html self-contained.
// Bad input gives exit code 2 and a message naming the file.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

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
