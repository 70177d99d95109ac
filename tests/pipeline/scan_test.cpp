// ScanRun on synthetic run folders whose stripes are known in closed form: a
// distorted camera looks at a tilted plane lit by one or three laser sheets;
// for every image column the exact row where each sheet's stripe crosses it is
// found by bisection on the real camera model, and the frame is drawn as a
// pixel-integrated Gaussian around it. The triangulated points must match the
// exact surface points; plane numbers must match the sheet each stripe came
// from; outputs and errors are checked.
#include <algorithm>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "scan_test_util.h"

namespace lt {
namespace {

using namespace scan_test;
using ::testing::HasSubstr;

TEST(Scan, SingleSheetPointsLieOnTheSurface) {
  SyntheticRun run = MakeRun("single", 1);
  std::vector<std::string> warnings;
  ScanOptions o;
  o.extraction.method = ExtractionMethod::kCom;
  ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(s.laser_frames, 1);
  EXPECT_EQ(s.other_frames, 1);
  EXPECT_TRUE(s.world_frame);
  EXPECT_EQ(s.plane_source, run.dir / "rig.json");
  ASSERT_TRUE(fs::exists(run.dir / "centers/000000.csv"));
  EXPECT_FALSE(fs::exists(run.dir / "centers/000001.csv"));
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  // One point per column except the first and last (com's window must stay inside).
  EXPECT_GE(int(points.size()), 150);
  EXPECT_EQ(s.points, int(points.size()));
  EXPECT_EQ(s.triangulated, int(points.size()));
  double worst = 0;
  for (const ScanPoint& p : points) {
    ASSERT_EQ(p.pixel.plane, 0);
    ASSERT_TRUE(p.p_in_cam && p.p_in_world);
    // On the laser plane exactly (it is a ray-plane intersection; the CSV's 10
    // significant digits allow ~1e-11 m).
    EXPECT_NEAR(run.sheets[0].SignedDistance(*p.p_in_cam), 0.0, 1e-10);
    EXPECT_LT((*p.p_in_world - run.world_from_cam * *p.p_in_cam).norm(), 1e-10);
    worst = std::max(worst, ErrorInPixels(run, 0, p));
  }
  // Noise-free com on a pixel-integrated Gaussian of sigma 1.2 px: the window
  // truncation bias is at most 0.012 px (docs/extraction.md), and rounding to
  // whole DN moves the centroid by well under 0.002 px at a peak of 1000 DN;
  // so the point is within 0.015 px (along the column) of the exact one.
  EXPECT_LT(worst, 0.015);
  // The cloud holds every triangulated point.
  std::ifstream ply(run.dir / "cloud.ply", std::ios::binary);
  std::string header;
  for (std::string line; std::getline(ply, line) && line != "end_header";) header += line + "\n";
  EXPECT_THAT(header, HasSubstr("element vertex " + std::to_string(points.size()) + "\n"));
  EXPECT_THAT(header, HasSubstr("world frame"));
  EXPECT_THAT(header, ::testing::Not(HasSubstr("red")));
}

// The raw frames of a colour sensor are demosaiced before extraction: on the
// raw mosaic every peak of the red stripe is narrower than --min-width.
// A stripe clipped where the sensor saturates is counted, for scan's note: at
// the ADC's full scale (1023 DN of 10 bits) when the manifest does not say,
// or at the manifest's saturation_dn (a full well below the ADC's range); one
// below it is not.
TEST(Scan, PointsOnSaturatedPixelsAreCounted) {
  for (double level : {1023.0, 900.0}) {
    SyntheticRun clipped = MakeRun("saturated_" + std::to_string(int(level)), 1, false, ColorFilter::kMono, 3000, level);
    ScanSummary s = ScanRun(clipped.dir, ScanOptions{});
    ASSERT_GT(s.stats.points, 100);
    EXPECT_EQ(s.saturated_points, s.stats.points) << level;
  }
  SyntheticRun below = MakeRun("not_saturated", 1);
  ScanSummary t = ScanRun(below.dir, ScanOptions{});
  ASSERT_GT(t.stats.points, 100);
  EXPECT_EQ(t.saturated_points, 0);
}

TEST(Scan, BayerFramesAreDemosaiced) {
  SyntheticRun run = MakeRun("bayer", 1, false, ColorFilter::kGRBG);
  ScanOptions o;
  o.extraction.method = ExtractionMethod::kCom;
  o.extraction.threshold = 100;  // the weighted R, G, B peak between 430 (their mean) and 1000 DN
  ScanSummary s = ScanRun(run.dir, o);
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  EXPECT_GE(int(points.size()), 150);
  double worst = 0;
  double worst_border = 0;
  for (const ScanPoint& p : points) {
    const bool border = p.pixel.u < 1 || p.pixel.u > run.camera.width() - 2;
    (border ? worst_border : worst) = std::max(border ? worst_border : worst, ErrorInPixels(run, 0, p));
  }
  // sigma 1.2 px, the red pixels every second row: within 0.05 px
  // (tests/pipeline/demosaic_test.cpp). A border column without red pixels
  // takes its red from the next column, where the stripe (slope 0.07 px per
  // column there) is elsewhere: 0.14 px measured.
  EXPECT_LT(worst, 0.05);
  EXPECT_LT(worst_border, 0.2);
  // The same frame read as a mono image finds (almost) nothing.
  SyntheticRun mono = MakeRun("bayer_as_mono", 1, false, ColorFilter::kGRBG);
  std::ofstream(mono.dir / "rig.json") << SensorRigToJson([&] {
    SensorRig rig;
    rig.camera = mono.camera;
    rig.lasers.push_back(TestLaser(1));
    return rig;
  }()).dump(2);
  EXPECT_LT(ScanRun(mono.dir, o).points, 50);
  EXPECT_GE(s.points, 150);
}

TEST(Scan, ThresholdFollowsTheFramesBitDepth) {
  // 10-bit DN (peak 1000) in a 16-bit PNG: 10% of 65535 would find nothing.
  SyntheticRun with = MakeRun("bits10", 1);
  SyntheticRun without = with;
  without.dir = with.dir.parent_path() / "bits_unknown";
  fs::remove_all(without.dir);
  fs::copy(with.dir, without.dir, fs::copy_options::recursive);
  std::ofstream(without.dir / "manifest.jsonl")
      << R"({"index":0,"shutter":{"laser_on":true},"files":{"image":"frames/000000.png"},"png_bit_depth":16})" << "\n";
  // Neither the manifest nor the rig gives the bit depth (with the rig's, see
  // ManifestWithoutBitDepthTakesTheRigsBitDepth).
  nlohmann::json rig = nlohmann::json::parse(std::ifstream(without.dir / "rig.json"));
  rig["image_sensor"].erase("bit_depth");
  std::ofstream(without.dir / "rig.json") << rig.dump(2);
  ScanOptions o;
  EXPECT_GT(ScanRun(with.dir, o).points, 150);
  std::vector<std::string> warnings;
  EXPECT_EQ(ScanRun(without.dir, o, [&](const std::string& w) { warnings.push_back(w); }).points, 0);
  // The user is told why and what to give.
  const std::vector<float>& pixels = ReadImageFloat(without.dir / "frames/000000.png").pixels;
  const double peak = *std::max_element(pixels.begin(), pixels.end());
  ASSERT_GT(peak, 511);  // 10-bit DN
  ASSERT_LT(peak, 1024);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("000000.png: no stripe point in a 16-bit image of unknown bit depth"));
  EXPECT_THAT(warnings[0], HasSubstr("its brightest sample, " + FormatNumber(peak) + ", fits in 10 bits"));
  EXPECT_THAT(warnings[0], HasSubstr("need --bit-depth with its ADC's bits (or bit_depth in the manifest), or --threshold"));
  o.extraction.threshold = 100;  // explicit DN threshold
  EXPECT_GT(ScanRun(without.dir, o).points, 150);
}

// steger's expected width is reported per frame: the one measured on the
// frame (the stripe's FWHM: sigma 1.2 px blurred by the pixel, 2.35 *
// sqrt(1.2^2 + 1/12) = 2.91 px; the measurement reads pixel samples, so
// within 0.5 px), or --width as given; NaN for the other methods.
TEST(Scan, StegerWidthOfEachFrameIsReported) {
  SyntheticRun run = MakeRun("steger_width", 1);
  ScanOptions o;
  o.extraction.method = ExtractionMethod::kSteger;
  ScanSummary s = ScanRun(run.dir, o);
  ASSERT_EQ(s.frames.size(), 1u);
  EXPECT_NEAR(s.frames[0].steger_width_px, 2.91, 0.5);
  EXPECT_GT(s.points, 150);
  o.extraction.expected_width = 6;
  s = ScanRun(run.dir, o);
  EXPECT_EQ(s.frames[0].steger_width_px, 6);
  o.extraction.method = ExtractionMethod::kCom;
  EXPECT_TRUE(std::isnan(ScanRun(run.dir, o).frames[0].steger_width_px));
}

TEST(Scan, ThreeSheetsAreIdentifiedAndTriangulated) {
  // Upside down: sheet 2 is the top stripe, so plane identification's top to
  // bottom numbering must be mapped to the sheet numbers.
  SyntheticRun run = MakeRun("three", 3, true);
  std::vector<std::pair<double, int>> rows;
  for (int k = 0; k < 3; ++k) rows.push_back({run.Row(k, 80), k});
  std::sort(rows.begin(), rows.end());
  ASSERT_EQ(rows[0].second, 2);
  ASSERT_EQ(rows[2].second, 0);
  ASSERT_GT(rows[1].first - rows[0].first, 8);  // well separated stripes
  ASSERT_GT(rows[2].first - rows[1].first, 8);
  // Largest error along the column, pixels: multicom's centroid of the profile
  // clipped at the threshold (10% of the peak) is biased by up to ~0.04 px at
  // sigma 1.2 px (docs/extraction.md: 0.028 px at sigma 1 on straight lines);
  // steger's Newton-refined centre only by rounding to whole DN.
  for (auto [method, tolerance] : {std::pair{ExtractionMethod::kMultiCom, 0.05}, std::pair{ExtractionMethod::kSteger, 0.01}}) {
    ScanOptions o;
    o.extraction.method = method;
    o.extraction.expected_width = 2.83;  // FWHM of sigma 1.2
    std::vector<std::string> warnings;
    ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
    EXPECT_TRUE(warnings.empty()) << (warnings.empty() ? "" : warnings[0]);
    ASSERT_EQ(s.frames.size(), 1u);
    EXPECT_TRUE(s.frames[0].identified) << s.frames[0].identification_error;
    std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
    EXPECT_GT(int(points.size()), 3 * 130) << MethodName(method);
    double worst = 0;
    for (const ScanPoint& p : points) {
      ASSERT_GE(p.pixel.plane, 0);
      // The global sheet number is the sheet whose exact stripe is nearest.
      int nearest = -1;
      double best = 1e9;
      for (int k = 0; k < 3; ++k) {
        double d = std::abs(run.Row(k, p.pixel.u) - p.pixel.v);
        if (d < best) best = d, nearest = k;
      }
      ASSERT_EQ(p.pixel.plane, nearest) << p.pixel.u << "," << p.pixel.v;
      ASSERT_TRUE(p.p_in_cam);
      worst = std::max(worst, ErrorInPixels(run, nearest, p));
    }
    EXPECT_LT(worst, tolerance) << MethodName(method);
  }
  // com finds one stripe per column: the scan says which methods see all three.
  ScanOptions com;
  com.extraction.method = ExtractionMethod::kCom;
  std::vector<std::string> warnings;
  ScanRun(run.dir, com, [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_FALSE(warnings.empty());
  EXPECT_THAT(warnings[0], HasSubstr("com finds one stripe per search line, but there are 3 laser planes: use "
                                     "--method multicom or steger"));
  // Without a chosen method (`scan` without --method) the scan takes multicom
  // for the three planes: every stripe, numbered, and no warning.
  ScanOptions unchosen;
  unchosen.method_from_planes = true;
  warnings.clear();
  const ScanSummary s = ScanRun(run.dir, unchosen, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.method, ExtractionMethod::kMultiCom);
  EXPECT_TRUE(warnings.empty()) << warnings[0];
  EXPECT_TRUE(s.frames[0].identified) << s.frames[0].identification_error;
  EXPECT_GT(s.triangulated, 3 * 130);
}

TEST(Scan, CalibrationFileReplacesThePlanes) {
  SyntheticRun run = MakeRun("calib", 1);
  CalibrationFile cal;
  Plane shifted = run.sheets[0];
  shifted.d += 0.0005;  // half a millimetre
  cal.laser_planes = {shifted};
  cal.camera = CalibratedCamera::From(run.camera);
  const fs::path file = run.dir / "calib.yml";
  WriteCalibrationFile(file, cal);
  ScanOptions o;
  o.calibration = file;
  ScanSummary s = ScanRun(run.dir, o);
  EXPECT_EQ(s.plane_source, file);
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_GT(points.size(), 100u);
  for (const ScanPoint& p : points) {
    ASSERT_TRUE(p.p_in_cam);
    EXPECT_NEAR(shifted.SignedDistance(*p.p_in_cam), 0.0, 1e-10);
    EXPECT_GT(std::abs(run.sheets[0].SignedDistance(*p.p_in_cam)), 4e-4);
  }
  // A calibrated camera of another size does not fit the run.
  cal.camera->width = 320;
  WriteCalibrationFile(file, cal);
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), file.string());
    EXPECT_THAT(e.message(), HasSubstr("the calibrated camera is 320x120 but the run's camera"));
  }
  // A file without planes cannot replace them; a missing file is named.
  cal.camera->width = 160;
  cal.laser_planes.clear();
  WriteCalibrationFile(file, cal);
  EXPECT_THROW(ScanRun(run.dir, o), InputError);
  o.calibration = run.dir / "missing.yml";
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (run.dir / "missing.yml").string() + ": cannot open file");
  }
}

// scan says what the calibration file's readers say, as calibrate does
// (CalibrationFileWarnings): the ignored keys on one line, then another tool's
// notes (a ROS file's stereo rectification), before it refuses a file without
// laser planes. (Before: the notes were dropped, and every ignored key listed.)
TEST(Scan, CalibrationFileWarningsAsCalibrate) {
  SyntheticRun run = MakeRun("calib_warnings", 1);
  CalibrationFile cal;
  cal.laser_planes = run.sheets;
  std::string text = FormatCalibrationFile(cal);
  for (int k = 0; k < 10; ++k) text += "extra_" + std::to_string(k) + ": " + std::to_string(k) + "\n";
  const fs::path file = run.dir / "calib.yml";
  std::ofstream(file) << text;
  ScanOptions o;
  o.calibration = file;
  std::vector<std::string> warnings;
  const auto warn = [&](const std::string& w) { warnings.push_back(w); };
  EXPECT_GT(ScanRun(run.dir, o, warn).points, 100);
  EXPECT_EQ(warnings, std::vector<std::string>{file.string() + ": 10 keys (extra_0, extra_1, extra_2, extra_3, extra_4, "
                                                               "extra_5, extra_6, extra_7 and 2 more) are ignored"});
  const fs::path ost = run.dir / "ost.yaml";
  std::ofstream(ost) << "image_width: 160\nimage_height: 120\ncamera_name: left\ncamera_matrix:\n  rows: 3\n"
                        "  cols: 3\n  data: [462.97, 0, 79.5, 0, 462.97, 59.5, 0, 0, 1]\ndistortion_model: plumb_bob\n"
                        "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n"
                        "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [0.9998, 0.0175, 0, -0.0175, 0.9998, 0, "
                        "0, 0, 1]\n";
  o.calibration = ost;
  warnings.clear();
  try {
    ScanRun(run.dir, o, warn);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.message(), HasSubstr("holds no laser_planes"));
  }
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0], ost.string() + ": 2 keys (camera_name, rectification_matrix) are ignored");
  EXPECT_THAT(warnings[1], HasSubstr(ost.string() + ":13: rectification_matrix is not the identity"));
}

// A calibration file with a hand-eye pose: the cloud is stitched with
// world_from_tool · tool_from_cam (what a real scanner on a robot knows), not
// the manifest's world_from_cam; a run without tool poses keeps world_from_cam
// and says that tool_from_cam went unused.
TEST(Scan, HandEyePoseWithToolPosesPlacesTheCloud) {
  SyntheticRun run = MakeRun("hand_eye", 1);
  Pose tool_from_cam = Pose::Identity();
  tool_from_cam.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 0.2, 0).normalized()).toRotationMatrix();
  tool_from_cam.translation() = Eigen::Vector3d(0.02, -0.01, 0.07);
  // The calibrated hand-eye pose is off by 1 mm along x from the one the tool
  // poses were made with, so the cloud must move by exactly that.
  Pose calibrated = tool_from_cam;
  calibrated.translation().x() += 0.001;
  const Pose world_from_tool = run.world_from_cam * tool_from_cam.inverse();
  CalibrationFile cal;
  cal.laser_planes = run.sheets;
  cal.tool_from_cam = calibrated;
  const fs::path file = run.dir / "calib.yml";
  WriteCalibrationFile(file, cal);
  ScanOptions o;
  o.calibration = file;

  // Without tool poses in the manifest: world_from_cam, and a warning.
  std::vector<std::string> warnings;
  ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.pose_source, "world_from_cam");
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("tool_from_cam is not used: the run's frames have no world_from_tool"));

  // With them: world_from_tool · tool_from_cam.
  std::ifstream in(run.dir / "manifest.jsonl");
  std::string manifest((std::istreambuf_iterator<char>(in)), {});
  in.close();
  const std::string key = "\"gt_axis\"";
  manifest.replace(manifest.find(key), key.size(), "\"world_from_tool\":" + PoseToJson(world_from_tool).dump() + "," + key);
  std::ofstream(run.dir / "manifest.jsonl") << manifest;
  warnings.clear();
  s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(s.world_frame);
  EXPECT_EQ(s.pose_source, "world_from_tool · tool_from_cam of " + file.string());
  const Pose world_from_cam_measured = world_from_tool * calibrated;
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_GT(points.size(), 100u);
  for (const ScanPoint& p : points) {
    ASSERT_TRUE(p.p_in_cam && p.p_in_world);
    EXPECT_LT((*p.p_in_world - world_from_cam_measured * *p.p_in_cam).norm(), 1e-9);
    // The hand-eye error moves the point by 1 mm along the tool's x axis.
    const Eigen::Vector3d moved = *p.p_in_world - run.world_from_cam * *p.p_in_cam;
    EXPECT_NEAR((moved - world_from_tool.linear() * Eigen::Vector3d(0.001, 0, 0)).norm(), 0.0, 1e-9);
  }

  // Tool poses without a hand-eye pose: the cloud keeps the manifest's camera poses.
  cal.tool_from_cam.reset();
  WriteCalibrationFile(file, cal);
  s = ScanRun(run.dir, o);
  EXPECT_EQ(s.pose_source, "world_from_cam");
}

TEST(Scan, BadRunsGiveInputErrors) {
  SyntheticRun run = MakeRun("bad", 1);
  ScanOptions o;
  // The laser frame's image is missing: the error names it and the manifest line.
  fs::rename(run.dir / "frames/000000.png", run.dir / "frames/moved.png");
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), (run.dir / "frames/000000.png").string());
    EXPECT_THAT(e.message(), HasSubstr("(frame 0, " + (run.dir / "manifest.jsonl").string() + ":1)"));
  }
  // An image of the wrong size.
  WriteImage(run.dir / "frames/000000.png", Image<uint16_t>(80, 60, 1));
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the image is 80x60 but the camera"));
  }
  // Only frames without laser light.
  o.frames_begin = 1;
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              (run.dir / "manifest.jsonl").string() + ": no laser frame to scan (only frames without laser light)");
  }
  o.frames_begin = 0;
  o.frames_end = 0;
  EXPECT_THROW(ScanRun(run.dir, o), InputError);
  // An empty manifest (blank lines only) is named as such, not as an empty range.
  std::ofstream(run.dir / "manifest.jsonl") << "\n\r\n";
  try {
    ScanRun(run.dir, ScanOptions{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), (run.dir / "manifest.jsonl").string() +
                                         ": holds no frame (expected one JSON object per line)");
  }
  EXPECT_THROW(ScanRun(run.dir / "nowhere", ScanOptions{}), InputError);
}

}  // namespace
}  // namespace lt
