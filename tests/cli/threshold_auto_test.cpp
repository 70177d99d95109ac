// `--threshold auto` end to end: extract names each image's threshold and
// finds a dim stripe the default (10% of full scale) misses; scan and
// calibrate laser take it too, scan names it in its summary; a bad value is
// refused naming the option.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/image.h"
#include "core/image_io.h"
#include "pipeline/synthetic_stripes.h"
#include "plane_scene.h"
#include "run_many.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// 8-bit, 640x64 (the stripe's 12 px are 2% of a line: they hardly move the
// medians): background 5 DN, noise sigma 1.5 DN, a stripe 13 DN high
// (under the default threshold, 25.5, everywhere: 18 DN and the noise).
fs::path DimNoisyImage(const fs::path& dir) {
  SyntheticFrame f;
  f.width = 640;
  f.height = 64;
  f.background = 5;
  f.noise_sigma = 1.5;
  f.seed = 3;
  SyntheticStripe s;
  s.u0 = 320.3, s.v0 = 32, s.sigma = 2, s.amplitude = 13;
  f.stripes.push_back(s);
  const fs::path p = dir / "dim.png";
  WriteImage(p, QuantizeImage<uint8_t>(RenderSyntheticFrame(f)));
  return p;
}

int Lines(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }

// The number after "threshold auto: " in `err` (NaN when absent).
double NotedThreshold(const std::string& err) {
  const std::string key = "threshold auto: ";
  const size_t at = err.find(key);
  return at == std::string::npos ? std::nan("") : std::stod(err.substr(at + key.size()));
}

TEST(ThresholdAuto, ExtractNamesTheThresholdAndFindsADimStripe) {
  const fs::path dir = NewTestFolder("threshold_auto_extract");
  const fs::path p = DimNoisyImage(dir);
  const std::vector<CliResult> r = RunMany({"extract " + Quoted(p), "extract " + Quoted(p) + " --threshold auto",
                                            "extract " + Quoted(p) + " --threshold autox",
                                            "extract " + Quoted(p) + " --threshold auto --background local"});
  EXPECT_EQ(r[0].exit_code, 0) << r[0].err;
  EXPECT_EQ(Lines(r[0].out), 1);  // the header: nothing above 25.5
  ASSERT_EQ(r[1].exit_code, 0) << r[1].err;
  EXPECT_EQ(Lines(r[1].out), 1 + 64);  // a point in every row
  // background 5 + 6 x (1.5 DN and the rounding's 1/12 DN^2: 1.53) = 14.2
  EXPECT_THAT(r[1].err, HasSubstr("lasertwin: note: " + p.string() + ": threshold auto: "));
  EXPECT_THAT(r[1].err, HasSubstr(" + 6 x noise 1.5"));
  EXPECT_NEAR(NotedThreshold(r[1].err), 14.2, 0.4);
  EXPECT_EQ(r[2].exit_code, 2);
  EXPECT_EQ(r[2].out, "");
  EXPECT_THAT(r[2].err, HasSubstr("--threshold: expected a finite number or 'auto', got 'autox'"));
  ASSERT_EQ(r[3].exit_code, 0) << r[3].err;
  EXPECT_GE(Lines(r[3].out), 1 + 60);  // the local line's noise loses a row or two
  EXPECT_THAT(r[3].err, HasSubstr("(a height above the background: 6 x noise 1.5"));
  EXPECT_NEAR(NotedThreshold(r[3].err), 9.2, 0.4);
}

// " auto" (blanks around it) is read as ParseThreshold reads it (the option's
// check refused it before); a flat 8-bit frame's dim-image note names the
// measured threshold (5 + the quantization floor 6/sqrt 12 = 6.732) in 4
// significant digits, as the auto note (before: 6.732050807568877).
TEST(ThresholdAuto, BlanksAroundAutoAndTheDimNotesPrecision) {
  const fs::path dir = NewTestFolder("threshold_auto_blanks");
  const fs::path p = dir / "flat.png";
  WriteImage(p, Image<uint8_t>(64, 16, 1, 5));
  const std::vector<CliResult> r =
      RunMany({"extract " + Quoted(p) + " --threshold auto", "extract " + Quoted(p) + " --threshold ' auto '"});
  for (const CliResult& c : r) {
    ASSERT_EQ(c.exit_code, 0) << c.err;
    EXPECT_EQ(Lines(c.out), 1);
    EXPECT_THAT(c.err, HasSubstr("threshold auto: 6.732 (background 5 + quantization floor 1.732"));
    EXPECT_THAT(c.err, HasSubstr("its brightest pixel is 5, below the threshold 6.732\n"));
  }
}

// Two rendered frames of a plane lit by one laser sheet: scan with auto names
// the median frame's threshold and the range (4 digits) in its summary and triangulates as many points as the default or
// more; scan and calibrate laser refuse "autox" alike.
TEST(ThresholdAuto, ScanNamesTheThreshold) {
  const fs::path dir = NewTestFolder("threshold_auto_scan");
  const nlohmann::json laser = {{"power_mw", 3}, {"wavelength_nm", 650}, {"divergence_deg", 1},
                                {"cam_from_projector",
                                 {{"translation_m", {0, 0.04, 0}}, {"rotation_rpy_deg", {std::atan(0.4) * 180 / M_PI, 0, 0}}}}};
  nlohmann::json scene = PlaneScene(nlohmann::json::array({laser}));
  scene["render"]["frames"] = 2;  // the summary gives the median frame's threshold and the range
  std::ofstream(dir / "scene.json") << scene.dump();
  const fs::path run = dir / "run";
  ASSERT_EQ(RunCli("render " + Quoted(dir / "scene.json") + " --out " + Quoted(run) + " --quiet").exit_code, 0);
  const CliResult fixed = RunCli("scan " + Quoted(run));
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  const CliResult automatic = RunCli("scan " + Quoted(run) + " --threshold auto");
  ASSERT_EQ(automatic.exit_code, 0) << automatic.err;
  EXPECT_THAT(automatic.err, ::testing::ContainsRegex("\nthreshold auto: [0-9.]+ \\(background [0-9.]+ \\+ [^\n]*\\) "
                                                      "on the median frame; [0-9.]{1,6} to [0-9.]{1,6} over 2 frames\n"));
  EXPECT_THAT(fixed.err, ::testing::Not(HasSubstr("threshold auto: ")));
  auto triangulated = [](const std::string& err) {
    const size_t at = err.find(" triangulated");
    const size_t start = err.rfind(' ', at - 1);
    return std::stoi(err.substr(start + 1, at - start - 1));
  };
  EXPECT_GT(triangulated(fixed.err), 30);
  EXPECT_GE(triangulated(automatic.err), triangulated(fixed.err));
  const std::vector<CliResult> bad = RunMany({"scan " + Quoted(run) + " --threshold autox",
                                              "calibrate laser " + Quoted(run) + " --threshold autox --out " +
                                                  Quoted(dir / "c.yaml")});
  for (const CliResult& b : bad) {
    EXPECT_EQ(b.exit_code, 2);
    EXPECT_THAT(b.err, HasSubstr("--threshold: expected a finite number or 'auto', got 'autox'"));
  }
}

}  // namespace
}  // namespace lt::test
