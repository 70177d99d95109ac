// `calibrate laser` extracts the dim frames with scan's extraction options
// (tools/lasertwin/extraction_args.h): a real camera's black level, a colour
// (Bayer) sensor, a threshold, on the small session of calibrate_test.cpp
// turned into a capture and its frames rewritten as such a camera records them.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <variant>
#include <vector>

#include "calib_session_util.h"
#include "core/image.h"
#include "core/image_io.h"
#include "pipeline/calib_geometry.h"
#include "pipeline/calib_laser_plane.h"
#include "pipeline/calibration_file.h"
#include "png_chunk_util.h"
#include "run_many.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kDeg = M_PI / 180.0;

// Rewrites every frame of `folder` (16-bit PNGs of 10-bit DN, in name order,
// bright first) whose position is dim (odd) or, with `bright_too`, any:
// sample (x, y) becomes f(x, y, sample), clipped to the 10-bit range.
void RewriteFrames(const fs::path& folder, bool bright_too, const std::function<double(int, int, double)>& f) {
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder)) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  for (size_t i = 0; i < files.size(); ++i) {
    if (i % 2 == 0 && !bright_too) continue;
    Image<uint16_t> im = std::get<Image<uint16_t>>(ReadImage(files[i]));
    for (int y = 0; y < im.height; ++y) {
      for (int x = 0; x < im.width; ++x) {
        im.At(x, y) = uint16_t(std::clamp(std::lround(f(x, y, im.At(x, y))), 0L, 1023L));
      }
    }
    WriteImage(files[i], im);
  }
}

struct Capture {
  fs::path dir, capture, camera;
  std::string args;  // the capture's options: shutter, bit depth, board, camera, one plane
};

// The session as a capture (no manifest, no rig), with the camera calibrated
// from the run (cam.yaml).
Capture MakeCapture(const std::string& name) {
  Capture c;
  fs::path poses;
  c.capture = CaptureOfSession(name, &poses);
  c.dir = c.capture.parent_path();
  c.camera = c.dir / "cam.yaml";
  // The camera from the run, calibrated once.
  static const fs::path camera = [] {
    const fs::path file = NewTestFolder("calib_x_camera") / "cam.yaml";
    const CliResult cam = RunCli("calibrate camera " + Quoted(RenderedSession().run) + " --fix-k3 --quiet --out " +
                                 Quoted(file));
    EXPECT_EQ(cam.exit_code, 0) << cam.err;
    return file;
  }();
  fs::copy_file(camera, c.camera);
  c.args = " --shutter alternate-bright-first --bit-depth 10 --planes 1 --board " +
           Quoted(RenderedSession().dir / "session/checkerboard.json") + " --calib " + Quoted(c.camera);
  return c;
}

Plane LaserPlane(const fs::path& file) { return ReadCalibrationFile(file).laser_planes.at(0); }

std::string Describe(const PlaneError& e) {
  return std::to_string(e.normal_angle_rad / kDeg) + " deg, " + std::to_string(e.offset_m * 1e6) + " um";
}

// The capture's frames as a colour sensor with an RGGB mosaic records them:
// each sample times its colour's gain (R at even x and y, B at odd x and y).
std::function<double(int, int, double)> Mosaic(double r, double g, double b) {
  return [=](int x, int y, double v) { return v * (x % 2 == 0 && y % 2 == 0 ? r : x % 2 == 1 && y % 2 == 1 ? b : g); };
}

Plane PlaneOf(const Capture& c, const std::string& name) { return LaserPlane(c.dir / name); }

// A camera with a black level of 64 DN: every sample of the capture 64 DN
// higher. The threshold is in image DN, as scan's: with --background 64 and
// the threshold raised by the same 64 DN (10% of 1023 + 64) the plane is the
// original's (measured: 0 deg, 5e-10 mm); without --background it moves
// (measured 0.0020 deg, 2.0 um: com's centroid pulled toward its window's
// middle; 0.0156 deg and 9.3 um with a black level of 200).
TEST(CalibrateExtraction, BlackLevelIsSubtractedAsScanDoes) {
  ASSERT_TRUE(RenderedSession().ok);
  const Capture c = MakeCapture("calib_x_black");
  const Capture b = MakeCapture("calib_x_black64");
  RewriteFrames(b.capture / "frames", true, [](int, int, double v) { return v + 64; });
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(c.capture) + c.args + " --quiet --out " + Quoted(c.dir / "plain.yaml"),
      "calibrate laser " + Quoted(b.capture) + b.args + " --background 64 --threshold 166.3 --quiet --out " +
          Quoted(b.dir / "bg64.yaml"),
      "calibrate laser " + Quoted(b.capture) + b.args + " --threshold 166.3 --quiet --out " + Quoted(b.dir / "bg0.yaml"),
  });
  for (const CliResult& x : r) ASSERT_EQ(x.exit_code, 0) << x.err;
  const Plane p0 = PlaneOf(c, "plain.yaml");
  const PlaneError with = ComparePlanes(PlaneOf(b, "bg64.yaml"), p0);
  const PlaneError without = ComparePlanes(PlaneOf(b, "bg0.yaml"), p0);
  // Equal up to rounding (measured 7.6e-9 rad, 5e-13 m).
  EXPECT_LT(with.normal_angle_rad, 1e-7) << Describe(with);
  EXPECT_LT(with.offset_m, 1e-9) << Describe(with);
  EXPECT_GT(without.normal_angle_rad, 1e-5) << Describe(without);
  EXPECT_GT(without.offset_m, 1e-6) << Describe(without);
}

// A camera tool's 16-bit PNGs of 10-bit DN with an sBIT chunk of 10, and no
// --bit-depth: the laser step takes the 10 bits as scan does (threshold 10% of
// 1023) and gives the plane of --bit-depth 10; without the chunk 10% of 65535
// finds no stripe (refused). The frames stored as grey+alpha (opaque): the
// alpha is left out as scan leaves it out, the same plane (before, a
// two-channel image: refused for want of --channel).
TEST(CalibrateExtraction, SbitAndAlphaAsScan) {
  ASSERT_TRUE(RenderedSession().ok);
  const Capture c = MakeCapture("calib_x_plain10");
  const Capture s = MakeCapture("calib_x_sbit");
  const Capture a = MakeCapture("calib_x_alpha");
  const std::string depth = " --bit-depth 10";
  std::string no_depth = s.args;
  ASSERT_NE(no_depth.find(depth), std::string::npos);
  no_depth.erase(no_depth.find(depth), depth.size());
  for (const auto& e : fs::directory_iterator(s.capture / "frames")) {
    InsertPngChunk(e.path(), "sBIT", std::string(1, char(10)));
  }
  for (const auto& e : fs::directory_iterator(a.capture / "frames")) {
    const Image<uint16_t> grey = std::get<Image<uint16_t>>(ReadImage(e.path()));
    Image<uint16_t> ga(grey.width, grey.height, 2, 65535);
    for (int y = 0; y < grey.height; ++y)
      for (int x = 0; x < grey.width; ++x) ga.At(x, y, 0) = grey.At(x, y);
    WriteImage(e.path(), ga);
  }
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(c.capture) + c.args + " --quiet --out " + Quoted(c.dir / "plain.yaml"),
      "calibrate laser " + Quoted(s.capture) + no_depth + " --quiet --out " + Quoted(s.dir / "sbit.yaml"),
      "calibrate laser " + Quoted(c.capture) + no_depth + " --quiet --out " + Quoted(c.dir / "none.yaml"),
      "calibrate laser " + Quoted(a.capture) + a.args + " --quiet --out " + Quoted(a.dir / "alpha.yaml"),
  });
  ASSERT_EQ(r[0].exit_code, 0) << r[0].err;
  ASSERT_EQ(r[1].exit_code, 0) << r[1].err;
  EXPECT_EQ(r[2].exit_code, 2) << r[2].err;
  ASSERT_EQ(r[3].exit_code, 0) << r[3].err;
  const Plane p0 = PlaneOf(c, "plain.yaml");
  for (const PlaneError& e : {ComparePlanes(PlaneOf(s, "sbit.yaml"), p0), ComparePlanes(PlaneOf(a, "alpha.yaml"), p0)}) {
    EXPECT_LT(e.normal_angle_rad, 1e-7) << Describe(e);
    EXPECT_LT(e.offset_m, 1e-9) << Describe(e);
  }
}

// A run whose rig.json gives the black level: the laser step subtracts it by
// default, as scan does (before, it took background 0 whatever rig.json said:
// the plane of --background 0, not of --background 64).
TEST(CalibrateExtraction, RigBlackLevelIsTheDefaultBackground) {
  ASSERT_TRUE(RenderedSession().ok);
  const fs::path dir = NewTestFolder("calib_x_rig_black");
  const fs::path run = dir / "run";
  fs::copy(RenderedSession().run, run, fs::copy_options::recursive);
  RewriteFrames(run / "frames", true, [](int, int, double v) { return v + 64; });
  nlohmann::json rig = nlohmann::json::parse(ReadFile(run / "rig.json"));
  rig["image_sensor"]["black_level_dn"] = 64.0;
  std::ofstream(run / "rig.json") << rig.dump(2);
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(run) + " --quiet --out " + Quoted(dir / "default.yaml"),
      "calibrate laser " + Quoted(run) + " --background 64 --quiet --out " + Quoted(dir / "bg64.yaml"),
      "calibrate laser " + Quoted(run) + " --background 0 --quiet --out " + Quoted(dir / "bg0.yaml"),
  });
  for (const CliResult& x : r) ASSERT_EQ(x.exit_code, 0) << x.err;
  const Plane def = LaserPlane(dir / "default.yaml"), bg64 = LaserPlane(dir / "bg64.yaml");
  EXPECT_EQ(def.n, bg64.n);
  EXPECT_EQ(def.d, bg64.d);
  EXPECT_NE(def.d, LaserPlane(dir / "bg0.yaml").d);
}

// A threshold above every stripe: refused, with scan's note on the same
// frames; one too low (0: every search line's brightest sample) still
// calibrates (measured 830 points instead of 375, 0.024 deg and 22 um off:
// the stray points off the stripe are RANSAC's outliers).
TEST(CalibrateExtraction, ThresholdAsScan) {
  ASSERT_TRUE(RenderedSession().ok);
  const Capture c = MakeCapture("calib_x_threshold");
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(c.capture) + c.args + " --threshold 2000 --out " + Quoted(c.dir / "high.yaml"),
      "calibrate laser " + Quoted(c.capture) + c.args + " --quiet --out " + Quoted(c.dir / "plain.yaml"),
      "calibrate laser " + Quoted(c.capture) + c.args + " --threshold 0 --out " + Quoted(c.dir / "low.yaml"),
  });
  EXPECT_EQ(r[0].exit_code, 2);
  EXPECT_THAT(r[0].err, HasSubstr("laser plane calibration refused (0 views with a stripe on the board)"));
  const std::string note = "note: no stripe points found; check --threshold (the default is 10% of the image's full scale)";
  EXPECT_THAT(r[0].err, HasSubstr(note));
  EXPECT_FALSE(fs::exists(c.dir / "high.yaml"));
  ASSERT_EQ(r[1].exit_code, 0) << r[1].err;
  ASSERT_EQ(r[2].exit_code, 0) << r[2].err;
  EXPECT_THAT(r[2].out, HasSubstr("of 830 points inliers"));
  const CliResult scan = RunCli("scan " + Quoted(c.capture) + " --shutter alternate-bright-first --bit-depth 10 --calib " +
                                Quoted(c.dir / "plain.yaml") + " --threshold 2000");
  EXPECT_EQ(scan.exit_code, 0) << scan.err;
  EXPECT_THAT(scan.err, HasSubstr(note));
  const PlaneError low = ComparePlanes(PlaneOf(c, "low.yaml"), PlaneOf(c, "plain.yaml"));
  EXPECT_LT(low.normal_angle_rad, 0.1 * kDeg) << Describe(low);
  EXPECT_LT(low.offset_m, 0.1e-3) << Describe(low);
}

// A colour sensor's raw frames (RGGB) of a red laser (G 5%, B 1% of R): read
// as mono, the stripe lies on every other sample of a search line and no
// point is found (refused); with --bayer rggb --channel 0 the demosaiced R
// gives the plane (measured 0.18 deg and 0.21 mm from the mono frames', 314
// points: R is sampled on a quarter of the pixels and the stripe of this
// binned camera is about 2 px wide). The bright frames stay grey (demosaiced
// with --bayer, CalibColourBoard below). --bayer rggb alone (no rig: no
// weights) takes the mean of R, G and B and says so. Without a rig, the
// sensor taken (black level 0, mono) is said, as scan says it, less what the
// options give.
TEST(CalibrateExtraction, BayerMosaic) {
  ASSERT_TRUE(RenderedSession().ok);
  const Capture c = MakeCapture("calib_x_bayer0");
  const Capture m = MakeCapture("calib_x_bayer");
  RewriteFrames(m.capture / "frames", false, Mosaic(1.0, 0.05, 0.01));
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(c.capture) + c.args + " --quiet --out " + Quoted(c.dir / "mono.yaml"),
      "calibrate laser " + Quoted(m.capture) + m.args + " --out " + Quoted(m.dir / "raw.yaml"),
      "calibrate laser " + Quoted(m.capture) + m.args + " --bayer rggb --channel 0 --out " + Quoted(m.dir / "r.yaml"),
      "calibrate laser " + Quoted(m.capture) + m.args + " --bayer rggb --out " + Quoted(m.dir / "mean.yaml"),
  });
  ASSERT_EQ(r[0].exit_code, 0) << r[0].err;
  EXPECT_EQ(r[1].exit_code, 2);
  EXPECT_THAT(r[1].err, HasSubstr("0 views with a stripe on the board"));
  EXPECT_THAT(r[1].err, HasSubstr("capture holds no rig.json: the camera is " + m.camera.string() +
                                  "'s, the image sensor's black level 0 (--background sets it), mono (--bayer sets a "
                                  "mosaic)\n"));
  EXPECT_THAT(r[2].err, HasSubstr("'s, the image sensor's black level 0 (--background sets it)\n"));
  ASSERT_EQ(r[2].exit_code, 0) << r[2].err;
  EXPECT_THAT(r[2].out, HasSubstr("of 314 points inliers"));
  const PlaneError e = ComparePlanes(PlaneOf(m, "r.yaml"), PlaneOf(c, "mono.yaml"));
  EXPECT_LT(e.normal_angle_rad, 0.3 * kDeg) << Describe(e);
  EXPECT_LT(e.offset_m, 0.3e-3) << Describe(e);
  ASSERT_EQ(r[3].exit_code, 0) << r[3].err;
  EXPECT_THAT(r[3].err, HasSubstr("colour frames are extracted on the mean of R, G and B"));
}

// Bad values are refused with scan's messages (one declaration, one parser),
// before any work; the camera and hand-eye steps warn that they extract no
// stripe; scan's options that calibration has no use for are not offered.
TEST(CalibrateExtraction, BadValuesAsScan) {
  ASSERT_TRUE(RenderedSession().ok);
  const fs::path run = RenderedSession().run;
  const fs::path dir = NewTestFolder("calib_x_bad");
  const std::vector<std::string> bad = {
      "--method centroid", "--background dark", "--roi 1,2,3",         "--weights 1,x,0",
      "--bayer rgbg",      "--threshold -1",    "--threshold 50 --high-threshold 10", "--max-width -1",
      "--link-distance -1", "--threshold nan",
  };
  std::vector<std::string> cmds;
  for (const std::string& b : bad) {
    cmds.push_back("calibrate laser " + Quoted(run) + " " + b + " --out " + Quoted(dir / "c.yaml"));
    cmds.push_back("scan " + Quoted(run) + " " + b);
  }
  cmds.push_back("calibrate camera " + Quoted(run) + " --threshold 50 --bayer rggb --quiet --out " + Quoted(dir / "cam.yaml"));
  cmds.push_back("calibrate laser " + Quoted(run) + " --depth-range 60:120 --out " + Quoted(dir / "c.yaml"));
  const std::vector<CliResult> r = RunMany(cmds);
  for (size_t i = 0; i < bad.size(); ++i) {
    const CliResult &cal = r[2 * i], &scan = r[2 * i + 1];
    EXPECT_EQ(cal.exit_code, scan.exit_code) << bad[i];
    EXPECT_NE(cal.exit_code, 0) << bad[i];
    EXPECT_EQ(cal.err, scan.err) << bad[i];
    EXPECT_THAT(cal.err, ::testing::Not(HasSubstr("warning"))) << bad[i];
  }
  const CliResult& cam = r[2 * bad.size()];
  EXPECT_EQ(cam.exit_code, 0) << cam.err;
  // --bayer is the bright frames' mosaic too (ColourBoardCalibratesTheCamera).
  EXPECT_THAT(cam.err, HasSubstr("warning: --threshold: the camera step extracts no laser stripe"));
  const CliResult& range = r[2 * bad.size() + 1];
  EXPECT_NE(range.exit_code, 0);
  EXPECT_THAT(range.err, HasSubstr("--depth-range"));
  EXPECT_FALSE(fs::exists(dir / "c.yaml"));
}

// A colour sensor's bright frames: the capture's frames as the RGGB mosaic of
// a board of hue R 1, G 0.5, B 0.3. With --bayer rggb the corners are found on
// the white-balanced, demosaiced grey and the camera is the mono frames' (fx,
// fy, cx, cy within 0.35 px; reprojection RMS 0.092 px as mono). Before, the
// camera step ignored --bayer (warned as an extraction option) and the
// detector read the raw mosaic: RMS 0.123 px, fx 3.6 px and cy 2.3 px off the
// mono frames' camera. Without --bayer (and without a rig) the step says it
// takes the sensor as mono.
TEST(CalibrateExtraction, ColourBoardCalibratesTheCamera) {
  ASSERT_TRUE(RenderedSession().ok);
  const Capture m = MakeCapture("calib_x_colour_board");
  RewriteFrames(m.capture / "frames", true, Mosaic(1.0, 0.5, 0.3));
  const std::string args = " --shutter alternate-bright-first --fix-k3 --board " +
                           Quoted(RenderedSession().dir / "session/checkerboard.json");
  const std::vector<CliResult> r = RunMany({
      "calibrate camera " + Quoted(m.capture) + args + " --bayer rggb --quiet --out " + Quoted(m.dir / "rggb.yaml"),
      "calibrate camera " + Quoted(m.capture) + args + " --quiet --out " + Quoted(m.dir / "raw.yaml"),
  });
  ASSERT_EQ(r[0].exit_code, 0) << r[0].err;
  EXPECT_THAT(r[0].err, ::testing::Not(HasSubstr("warning")));
  EXPECT_EQ(r[1].exit_code, 0) << r[1].err;
  EXPECT_THAT(r[1].err, HasSubstr("capture holds no rig.json: the image sensor is mono (--bayer sets a mosaic)"));
  const CalibratedCamera mono = *ReadCalibrationFile(m.camera).camera;
  const CalibratedCamera colour = *ReadCalibrationFile(m.dir / "rggb.yaml").camera;
  EXPECT_NEAR(colour.fx, mono.fx, 1.0);
  EXPECT_NEAR(colour.fy, mono.fy, 1.0);
  EXPECT_NEAR(colour.cx, mono.cx, 1.0);
  EXPECT_NEAR(colour.cy, mono.cy, 1.0);
}

// A laser of three sheets (the demo rig's, with a diffractive element, 3 deg
// apart): without --method the dim frames take multicom, as scan's do, and
// the three planes calibrate (5 of 6 views; one shows two lines on the
// board). com, the default before, finds one stripe per search line: refused
// ("found 1 stripe line(s) on the board, expected 3" and too few points).
TEST(CalibrateExtraction, SeveralSheetsTakeMulticom) {
  const fs::path dir = NewTestFolder("calib_x_sheets");
  std::string scene = ReadFile(kSource / "scenes/demo/scene.json");
  const std::string fan = "\"fan_angle_deg\": 40,";
  ASSERT_NE(scene.find(fan), std::string::npos);
  scene.replace(scene.find(fan), fan.size(), fan + " \"sheet_count\": 3, \"sheet_spacing_deg\": 3,");
  std::ofstream(dir / "rig.json") << scene;
  const CliResult gen = RunCli("calib-session --out " + Quoted(dir / "session") + " --rig " + Quoted(dir / "rig.json") +
                               " --views 6 --binning 4 --spp 2 --quiet");
  ASSERT_EQ(gen.exit_code, 0) << gen.err;
  const CliResult render =
      RunCli("render " + Quoted(dir / "session/scene.json") + " --out " + Quoted(dir / "run") + " --quiet");
  ASSERT_EQ(render.exit_code, 0) << render.err;
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(dir / "run") + " --out " + Quoted(dir / "default.yaml"),
      "calibrate laser " + Quoted(dir / "run") + " --method com --out " + Quoted(dir / "com.yaml"),
  });
  ASSERT_EQ(r[0].exit_code, 0) << r[0].err;
  EXPECT_THAT(r[0].out, HasSubstr("laser planes from 5 views"));
  EXPECT_EQ(ReadCalibrationFile(dir / "default.yaml").laser_planes.size(), 3u);
  EXPECT_EQ(r[1].exit_code, 2);
  EXPECT_THAT(r[1].err, HasSubstr("laser plane calibration refused"));
}

// How many times `what` stands in `text`.
size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Writes every frame of `folder` again as a TIFF with an Orientation tag (as
// a camera's TIFF or a phone's JPEG has it; OpenImageIO writes none in a PNG),
// the pixels as they were.
void TagOrientation(const fs::path& folder, int orientation) {
  std::vector<fs::path> pngs;
  for (const auto& e : fs::directory_iterator(folder)) pngs.push_back(e.path());
  for (const fs::path& png : pngs) {
    const Image<uint16_t> im = std::get<Image<uint16_t>>(ReadImage(png));
    const std::string tif = fs::path(png).replace_extension(".tif").string();
    OIIO::ImageSpec spec(im.width, im.height, 1, OIIO::TypeDesc::UINT16);
    spec.attribute("Orientation", orientation);
    auto out = OIIO::ImageOutput::create(tif);
    ASSERT_TRUE(out && out->open(tif, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT16, im.pixels.data()));
    ASSERT_TRUE(out->close());
    fs::remove(png);
  }
}

// What a frame's file declares and is not applied is said as scan says it
// (pipeline/frame_image_reader.h), once a run, with the count of the other
// frames at the end. An sRGB chunk on every frame: the laser step warns on the
// first dim frame and counts the other 5 (the bright frames' corners need no
// linear values); --transfer linear silences it. An Orientation tag on every
// frame: the laser step warns on the first bright frame and counts the other
// 11; the camera step, on the capture and on its bright frames as a folder of
// photographs, counts the other 5. Before, calibrate said none of this.
TEST(CalibrateExtraction, FileTagsAreSaidOnceAsScanSaysThem) {
  ASSERT_TRUE(RenderedSession().ok);
  const Capture s = MakeCapture("calib_x_srgb_tag");
  for (const auto& e : fs::directory_iterator(s.capture / "frames")) {
    InsertPngChunk(e.path(), "sRGB", std::string(1, char(0)));
  }
  const Capture o = MakeCapture("calib_x_orientation");
  TagOrientation(o.capture / "frames", 6);
  const fs::path photos = o.dir / "photos";
  fs::create_directories(photos);
  for (const char* f : {"000000.tif", "000002.tif", "000004.tif", "000006.tif", "000008.tif", "000010.tif"}) {
    fs::copy_file(o.capture / "frames" / f, photos / f);
  }
  const std::string board = " --fix-k3 --board " + Quoted(RenderedSession().dir / "session/checkerboard.json");
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(s.capture) + s.args + " --quiet --out " + Quoted(s.dir / "srgb.yaml"),
      "calibrate laser " + Quoted(s.capture) + s.args + " --transfer linear --quiet --out " + Quoted(s.dir / "lin.yaml"),
      "calibrate laser " + Quoted(o.capture) + o.args + " --quiet --out " + Quoted(o.dir / "laser.yaml"),
      "calibrate camera " + Quoted(o.capture) + " --shutter alternate-bright-first" + board + " --quiet --out " +
          Quoted(o.dir / "camera.yaml"),
      "calibrate camera " + Quoted(photos) + board + " --quiet --out " + Quoted(o.dir / "photos.yaml"),
  });
  for (const CliResult& x : r) ASSERT_EQ(x.exit_code, 0) << x.err;
  const std::string srgb = "has an sRGB chunk: its values encode light by the sRGB curve, but are read as linear: "
                           "give --transfer srgb to linearize them";
  EXPECT_EQ(Count(r[0].err, srgb), 1u) << r[0].err;
  EXPECT_THAT(r[0].err, HasSubstr("frames/000001.png: " + srgb));
  EXPECT_THAT(r[0].err, HasSubstr("frames/000001.png (has an sRGB chunk) holds for 5 more frames\n"));
  EXPECT_THAT(r[1].err, ::testing::Not(HasSubstr("sRGB")));
  const std::string turned = ": has an Orientation tag of 6 (shown turned 90 degrees clockwise): it is not applied";
  for (const size_t k : {size_t(2), size_t(3), size_t(4)}) {
    EXPECT_EQ(Count(r[k].err, turned), 1u) << r[k].err;
    EXPECT_THAT(r[k].err, HasSubstr("000000.tif" + turned));
    EXPECT_THAT(r[k].err, HasSubstr("000000.tif (has an Orientation tag of 6 (shown turned 90 degrees clockwise)) "
                                    "holds for " + std::string(k == 2 ? "11 more frames" : k == 3 ? "5 more frames"
                                                                                                  : "5 more images")));
  }
}

}  // namespace
}  // namespace lt::test
