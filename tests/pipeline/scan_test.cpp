// ScanRun on synthetic run folders whose stripes are known in closed form: a
// distorted camera looks at a tilted plane lit by one or three laser sheets;
// for every image column the exact row where each sheet's stripe crosses it is
// found by bisection on the real camera model, and the frame is drawn as a
// pixel-integrated Gaussian around it. The triangulated points must match the
// exact surface points; plane numbers must match the sheet each stripe came
// from; outputs and errors are checked.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/image_io.h"
#include "pipeline/calibration_file.h"
#include "pipeline/demosaic.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan.h"
#include "pipeline/scan_output.h"
#include "sensor/rig.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kDeg = M_PI / 180.0;

// Built once: the distortion's domain analysis is costly in sanitizer builds.
const Camera& TestCamera() {
  static const Camera camera = [] {
    CameraParams p;
    p.width = 160;
    p.height = 120;
    p.pixel_pitch_m = 19.2e-6;
    p.fx = p.fy = 462.97;
    p.cx = 79.5;
    p.cy = 59.5;
    p.distortion = DistortionModel::kBrownConrady;
    p.brown_conrady = {-0.2, 0.05, 0.001, -0.0005, 0};
    return Camera(p);
  }();
  return camera;
}

// A projector 40 mm beside the camera (+y), aimed at the optical axis 80 mm
// away. Mounted upside down (turned 180 degrees about its beam), its sheet
// numbers run bottom to top in the image instead of top to bottom.
LaserProjector TestLaser(int sheets, bool upside_down = false) {
  LaserParams lp;
  lp.sheet_angles_rad = EvenSheetAngles(sheets, 3 * kDeg);
  lp.sheet_power.assign(size_t(sheets), 1.0);
  lp.cam_from_projector = Pose::Identity();
  lp.cam_from_projector.translation() = Eigen::Vector3d(0, 0.04, 0);
  lp.cam_from_projector.linear() =
      upside_down ? (Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(-26.565 * kDeg, Eigen::Vector3d::UnitX())).toRotationMatrix()
                  : Eigen::AngleAxisd(26.565 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return LaserProjector(lp);
}

// The object: a plane about 80 mm in front, tilted about both axes.
const Plane kObject = Plane::FromPointNormal({0, 0, 0.08}, {0.15, -0.1, 1});

std::optional<Eigen::Vector3d> SurfacePoint(const Camera& cam, double u, double v) {
  auto ray = cam.Unproject({u, v});
  if (!ray) return std::nullopt;
  return (-kObject.d / kObject.n.dot(*ray)) * *ray;
}

// The row where the sheet's stripe crosses column u (NaN if it does not).
double ExactRow(const Camera& cam, const Plane& sheet, double u) {
  auto g = [&](double v) { return sheet.SignedDistance(*SurfacePoint(cam, u, v)); };
  double a = -0.5, b = cam.height() - 0.5;
  double ga = g(a), gb = g(b);
  if (ga * gb > 0) return std::nan("");
  for (int i = 0; i < 200 && b - a > 1e-12; ++i) {
    double m = 0.5 * (a + b), gm = g(m);
    if ((gm > 0) == (ga > 0)) {
      a = m;
      ga = gm;
    } else {
      b = m;
    }
  }
  return 0.5 * (a + b);
}

double Phi(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

struct SyntheticRun {
  fs::path dir;
  Camera camera = TestCamera();
  std::vector<Plane> sheets;
  Pose world_from_cam = Pose::Identity();
  std::vector<std::vector<double>> rows;  // [sheet][column]: ExactRow at each integer column

  // The exact row of sheet k at column u (points searched along columns have integer u).
  double Row(int k, double u) const {
    const int c = int(u);
    if (double(c) == u && c >= 0 && c < int(rows[size_t(k)].size())) return rows[size_t(k)][size_t(c)];
    return ExactRow(camera, sheets[size_t(k)], u);
  }
};

// Writes a run folder: frame 0 lit by the laser (10-bit DN in a 16-bit PNG),
// frame 1 a bright frame whose image does not exist (a scan must not read it).
// With `mosaic` not kMono, the rig's sensor is a colour one and the frame its
// raw Bayer mosaic of a red laser (R 1.0, G 0.25, B 0.05).
SyntheticRun MakeRun(const std::string& name, int n_sheets, bool upside_down = false,
                     ColorFilter mosaic = ColorFilter::kMono, double peak = 1000, double saturation_dn = 1023) {
  SyntheticRun run;
  run.dir = fs::temp_directory_path() / ("lt_scan_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(run.dir);
  fs::create_directories(run.dir / "frames");
  SensorRig rig;
  rig.camera = run.camera;
  rig.lasers.push_back(TestLaser(n_sheets, upside_down));
  for (int k = 0; k < n_sheets; ++k) run.sheets.push_back(rig.lasers[0].SheetPlane(k));
  nlohmann::json rig_json = SensorRigToJson(rig);
  if (mosaic != ColorFilter::kMono) {
    static const char* const kNames[] = {"mono", "rggb", "bggr", "grbg", "gbrg"};
    rig_json["image_sensor"]["color_filter"] = kNames[int(mosaic)];
    // Quantum efficiency in proportion to the stripe's channel gains below.
    rig_json["image_sensor"]["quantum_efficiency"] = {{"wavelength_nm", {650}}, {"r", {0.8}}, {"g", {0.2}}, {"b", {0.04}}};
  }
  std::ofstream(run.dir / "rig.json") << rig_json.dump(2);
  run.world_from_cam.linear() = Eigen::AngleAxisd(3.0, Eigen::Vector3d(0.1, 1, 0.05).normalized()).toRotationMatrix();
  run.world_from_cam.translation() = Eigen::Vector3d(0.3, -0.1, 0.5);

  // Stripe: Gaussian across it with sigma 1.2 px and peak `peak` DN (clipped at
  // saturation_dn), integrated over each pixel along the column, on a black background.
  const double sigma = 1.2, background = 0;
  Image<float> img(run.camera.width(), run.camera.height(), 1, float(background));
  for (const Plane& sheet : run.sheets) {
    run.rows.emplace_back();
    for (int u = 0; u < img.width; ++u) {
      const double vc = ExactRow(run.camera, sheet, u);
      run.rows.back().push_back(vc);
      if (std::isnan(vc)) continue;
      for (int y = 0; y < img.height; ++y) {
        const double mass = Phi((y + 0.5 - vc) / sigma) - Phi((y - 0.5 - vc) / sigma);
        img.At(u, y) += float(peak * sigma * std::sqrt(2 * M_PI) * mass);
      }
    }
  }
  Image<uint16_t> dn(img.width, img.height, 1);
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    dn.pixels[i] = uint16_t(std::lround(std::min(double(img.pixels[i]), saturation_dn)));
  }
  if (mosaic != ColorFilter::kMono) {
    const double gain[3] = {1.0, 0.25, 0.05};
    for (int y = 0; y < dn.height; ++y)
      for (int x = 0; x < dn.width; ++x)
        dn.At(x, y) = uint16_t(std::lround(std::min(img.At(x, y) * gain[FilterChannel(mosaic, x, y)], 1023.0)));
  }
  WriteImage(run.dir / "frames/000000.png", dn);

  nlohmann::json dim = {{"index", 0},
                        {"shutter", {{"laser_on", true}}},
                        {"files", {{"image", "frames/000000.png"}}},
                        {"world_from_cam", PoseToJson(run.world_from_cam)},
                        {"gt_axis", "cols"},
                        {"png_bit_depth", 16},
                        {"bit_depth", 10}};
  if (saturation_dn < 1023) dim["saturation_dn"] = saturation_dn;
  nlohmann::json bright = {{"index", 1}, {"shutter", {{"laser_on", false}}}, {"files", {{"image", "frames/000001.png"}}}};
  std::ofstream(run.dir / "manifest.jsonl") << dim.dump() << "\n" << bright.dump() << "\n";
  return run;
}

// Distance from the triangulated point to the exact one, in units of the
// surface's displacement per pixel along the column (so the tolerance reads in pixels).
double ErrorInPixels(const SyntheticRun& run, int sheet, const ScanPoint& p) {
  const double vc = run.Row(sheet, p.pixel.u);
  const Eigen::Vector3d exact = *SurfacePoint(run.camera, p.pixel.u, vc);
  const double per_px = (*SurfacePoint(run.camera, p.pixel.u, vc + 0.5) - *SurfacePoint(run.camera, p.pixel.u, vc - 0.5)).norm();
  return (*p.p_in_cam - exact).norm() / per_px;
}

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
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("000000.png: no stripe point in a 16-bit image of unknown bit depth"));
  EXPECT_THAT(warnings[0], HasSubstr("need bit_depth in the manifest, or --threshold"));
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

// A capture tool's manifest gives no bit_depth: the image sensor's (rig.json)
// sets the default threshold, 10% of 1023 for 10-bit DN in 16-bit PNGs, not
// 10% of 65535 (above the stripe's 1000 DN: no point was found).
TEST(Scan, ManifestWithoutBitDepthTakesTheRigsBitDepth) {
  SyntheticRun run = MakeRun("rig_bits", 1);
  nlohmann::json rig = nlohmann::json::parse(std::ifstream(run.dir / "rig.json"));
  rig["image_sensor"]["bit_depth"] = 10;
  std::ofstream(run.dir / "rig.json") << rig.dump(2);
  std::ofstream(run.dir / "manifest.jsonl") << R"({"index":0,"files":{"image":"frames/000000.png"}})" << "\n";
  ScanSummary s = ScanRun(run.dir, ScanOptions{});
  EXPECT_GE(s.triangulated, 150);
  for (const ScanPoint& p : ReadScanCsv(run.dir / "centers/000000.csv")) {
    ASSERT_TRUE(p.p_in_cam);
    EXPECT_LT(ErrorInPixels(run, 0, p), 0.01);
  }
}

// A real capture has no rig.json: the calibration file's camera (lasertwin
// calibrate's) is the camera, its laser planes the planes.
TEST(Scan, CaptureWithoutRigTakesTheCalibrationFilesCamera) {
  SyntheticRun run = MakeRun("calib_only", 1);
  fs::remove(run.dir / "rig.json");
  ScanOptions o;
  try {
    ScanRun(run.dir, o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("holds neither rig.json nor scene.json"));
    EXPECT_THAT(e.what(), HasSubstr("scan --calib"));
  }
  CalibrationFile cal;
  cal.camera = CalibratedCamera::From(run.camera);
  cal.laser_planes = run.sheets;
  const fs::path file = run.dir / "calib.yml";
  WriteCalibrationFile(file, cal);
  o.calibration = file;
  std::vector<std::string> warnings;
  ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.plane_source, file);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("holds no rig.json: the camera is " + file.string() + "'s"));
  EXPECT_THAT(warnings[0], HasSubstr("mono (--bayer sets a mosaic)"));
  EXPECT_TRUE(s.world_frame);
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_GE(points.size(), 150u);
  for (const ScanPoint& p : points) {
    ASSERT_TRUE(p.p_in_cam);
    EXPECT_LT(ErrorInPixels(run, 0, p), 0.01);
  }
  // A calibration file without a camera part cannot stand in for the rig.
  cal.camera.reset();
  WriteCalibrationFile(file, cal);
  EXPECT_THROW(ScanRun(run.dir, o), InputError);
}

// A colour sensor's capture without rig.json (the calibration file's camera):
// color_filter (--bayer) says the frames are raw mosaics; the points are those
// of the same run whose rig.json gives the mosaic.
TEST(Scan, ColorFilterOptionGivesTheMosaicOfARigFromACalibrationFile) {
  SyntheticRun run = MakeRun("bayer_calib", 1, false, ColorFilter::kRGGB);
  ScanOptions o;
  o.extraction.channel_weights = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  ScanRun(run.dir, o);
  const std::vector<ScanPoint> with_rig = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_GE(with_rig.size(), 150u);
  fs::remove(run.dir / "rig.json");
  CalibrationFile cal;
  cal.camera = CalibratedCamera::From(run.camera);
  cal.laser_planes = run.sheets;
  WriteCalibrationFile(run.dir / "calib.yml", cal);
  o.calibration = run.dir / "calib.yml";
  o.color_filter = ColorFilter::kRGGB;
  ScanRun(run.dir, o);
  const std::vector<ScanPoint> with_option = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_EQ(with_option.size(), with_rig.size());
  for (size_t i = 0; i < with_rig.size(); ++i) {
    EXPECT_EQ(with_option[i].pixel.u, with_rig[i].pixel.u);
    EXPECT_EQ(with_option[i].pixel.v, with_rig[i].pixel.v);
  }
}

// Alternating bright and laser frames recorded without shutter keys are all
// scanned as laser frames; the flood-lit ones are named in a warning.
TEST(Scan, FloodLitFramesWithoutShutterKeysAreWarned) {
  SyntheticRun run = MakeRun("no_shutter", 1);
  WriteImage(run.dir / "frames/000001.png", Image<uint16_t>(160, 120, 1, 500));  // LED-lit scene, 500 of 1023 DN
  std::ofstream(run.dir / "manifest.jsonl")
      << R"({"index":0,"files":{"image":"frames/000000.png"},"bit_depth":10})" << "\n"
      << R"({"index":1,"files":{"image":"frames/000001.png"},"bit_depth":10})" << "\n";
  std::vector<std::string> warnings;
  ScanSummary s = ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.laser_frames, 2);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("1 frame (1) with no shutter.laser_on in the manifest have most pixels above"));
  // With the shutter state the bright frame is skipped, and nothing is said.
  std::ofstream(run.dir / "manifest.jsonl")
      << R"({"index":0,"shutter":{"laser_on":true},"files":{"image":"frames/000000.png"},"bit_depth":10})" << "\n"
      << R"({"index":1,"shutter":{"laser_on":false},"files":{"image":"frames/000001.png"},"bit_depth":10})" << "\n";
  warnings.clear();
  s = ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_EQ(s.laser_frames, 1);
  EXPECT_TRUE(warnings.empty());
}

// 10-bit DN stored in the top bits of a 16-bit PNG (MSB-aligned) while the
// manifest says bit_depth 10: the samples above 1023 are named in a warning.
TEST(Scan, SamplesAboveTheBitDepthAreWarned) {
  SyntheticRun run = MakeRun("msb_aligned", 1);
  std::vector<std::string> warnings;
  ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  EXPECT_TRUE(warnings.empty());
  AnyImage any = ReadImage(run.dir / "frames/000000.png");
  Image<uint16_t>& im = std::get<Image<uint16_t>>(any);
  for (uint16_t& v : im.pixels) v = uint16_t(v << 6);
  WriteImage(run.dir / "frames/000000.png", im);
  ScanRun(run.dir, ScanOptions{}, [&](const std::string& w) { warnings.push_back(w); });
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("000000.png: a sample reads "));
  EXPECT_THAT(warnings[0], HasSubstr(", above 1023, the largest 10-bit value: the frames are not raw 10-bit DN"));
}

// A scan that stops on a bad frame leaves no cloud.ply, and no centres of the
// bad frame, of an earlier scan beside its new centres (they would be taken for
// this scan's result).
TEST(Scan, AScanStoppedByABadFrameLeavesNoEarlierCloud) {
  SyntheticRun run = MakeRun("stale_cloud", 1);
  ScanRun(run.dir, ScanOptions{});
  ASSERT_TRUE(fs::exists(run.dir / "cloud.ply"));
  std::ofstream(run.dir / "frames/000002.png") << "not a PNG";
  std::ofstream(run.dir / "centers/000002.csv") << "u,v,width,strength,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world\n";
  std::ofstream(run.dir / "manifest.jsonl", std::ios::app)
      << R"({"index":2,"shutter":{"laser_on":true},"files":{"image":"frames/000002.png"}})" << "\n";
  try {
    ScanRun(run.dir, ScanOptions{});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), (run.dir / "frames/000002.png").string());
    EXPECT_THAT(e.message(), HasSubstr("(frame 2, " + (run.dir / "manifest.jsonl").string() + ":3)"));
  }
  EXPECT_TRUE(fs::exists(run.dir / "centers/000000.csv"));
  EXPECT_FALSE(fs::exists(run.dir / "centers/000002.csv"));  // an earlier scan's (written above)
  EXPECT_FALSE(fs::exists(run.dir / "cloud.ply"));
}

TEST(Scan, CameraFrameCloudWithoutPoses) {
  SyntheticRun run = MakeRun("nopose", 1);
  // Rewrite the manifest without poses.
  std::ofstream(run.dir / "manifest.jsonl")
      << R"({"index":0,"shutter":{"laser_on":true},"files":{"image":"frames/000000.png"},"bit_depth":10})" << "\n";
  ScanSummary s = ScanRun(run.dir, ScanOptions{});
  EXPECT_FALSE(s.world_frame);
  std::vector<ScanPoint> points = ReadScanCsv(run.dir / "centers/000000.csv");
  ASSERT_FALSE(points.empty());
  EXPECT_TRUE(points[0].p_in_cam);
  EXPECT_FALSE(points[0].p_in_world);
  std::ifstream ply(run.dir / "cloud.ply", std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(ply)), {});
  EXPECT_THAT(text, HasSubstr("camera frame"));
}

// A run of `frames` raw Bayer frames (RGGB) exposed by the sensor model
// (EMVA 1288 noise: shot, dark, quantisation): the stripe of MakeRun's laser at
// `wavelength_nm`, a pixel-integrated Gaussian of sigma 1.5 px across it whose
// peak gives `peak_e` photo-electrons in the sensor's most responsive channel.
// The sensor's quantum efficiency is the print scene's (scenes/print); its
// dark noise is 25 e- and K 0.5 DN/e- (10 bits, full well 2000 e-): a small-pixel
// sensor whose noise floor, not the stripe's shot noise, dominates near the
// default threshold.
SyntheticRun MakeSensorRun(const std::string& name, double wavelength_nm, double peak_e, int frames,
                           bool with_wavelength = true) {
  SyntheticRun run;
  run.dir = fs::temp_directory_path() / ("lt_scan_test_" + std::to_string(::getpid())) / name;
  fs::remove_all(run.dir);
  fs::create_directories(run.dir / "frames");
  ImageSensorParams sp;
  sp.color_filter = ColorFilter::kRGGB;
  sp.qe_wavelength_m = {450e-9, 550e-9, 650e-9, 750e-9};
  sp.qe = {{{0.05, 0.1, 0.5, 0.3}, {0.1, 0.55, 0.2, 0.1}, {0.5, 0.1, 0.05, 0.08}}};
  sp.bit_depth = 10;
  sp.full_well_e = 2000;
  sp.system_gain_dn_per_e = 0.5;
  sp.dark_noise_e = 25;
  sp.black_level_dn = 16;
  SensorRig rig;
  rig.camera = run.camera;
  LaserParams lp;
  lp.wavelength_m = wavelength_nm * 1e-9;
  lp.cam_from_projector = TestLaser(1).cam_from_projector();
  rig.lasers.emplace_back(lp);
  rig.image_sensor = ImageSensor(sp);
  run.sheets.push_back(rig.lasers[0].SheetPlane(0));
  nlohmann::json rig_json = SensorRigToJson(rig);
  if (!with_wavelength) rig_json["lasers"][0].erase("wavelength_nm");  // a recorded rig that does not say
  std::ofstream(run.dir / "rig.json") << rig_json.dump(2);

  const double lambda = wavelength_nm * 1e-9;
  double best = 0;
  for (int c = 0; c < 3; ++c) best = std::max(best, rig.image_sensor.QuantumEfficiency(c, lambda));
  const double joules_per_e = kPlanck * kSpeedOfLight / lambda / best;
  const double sigma = 1.5;
  SensorExposure ex;
  ex.width = run.camera.width(), ex.height = run.camera.height();
  ex.exposure_s = 1e-4;
  MonochromaticEnergy mono;
  mono.wavelength_m = lambda;
  mono.energy_j = Image<float>(ex.width, ex.height, 1, 0.0f);
  run.rows.emplace_back();
  for (int u = 0; u < ex.width; ++u) {
    const double vc = ExactRow(run.camera, run.sheets[0], u);
    run.rows.back().push_back(vc);
    if (std::isnan(vc)) continue;
    for (int y = 0; y < ex.height; ++y) {
      const double mass = Phi((y + 0.5 - vc) / sigma) - Phi((y - 0.5 - vc) / sigma);
      mono.energy_j.At(u, y) = float(peak_e * sigma * std::sqrt(2 * M_PI) * mass * joules_per_e);
    }
  }
  ex.monochromatic.push_back(mono);
  std::ofstream manifest(run.dir / "manifest.jsonl");
  for (int f = 0; f < frames; ++f) {
    const std::string image = "frames/" + std::to_string(f) + ".png";
    WriteImage(run.dir / image, rig.image_sensor.Expose(ex, 7, uint64_t(f)));
    manifest << nlohmann::json({{"index", f}, {"shutter", {{"laser_on", true}}}, {"files", {{"image", image}}},
                                {"gt_axis", "cols"}, {"png_bit_depth", 16}, {"bit_depth", 10}})
                    .dump()
             << "\n";
  }
  return run;
}

struct CentreNoise {
  int points = 0;
  double rms = 0;  // px, from the exact rows, columns 2 .. width - 3
};

CentreNoise ScanCentreNoise(const SyntheticRun& run, const ScanOptions& o, std::vector<std::string>* warnings = nullptr) {
  const ScanSummary s = ScanRun(run.dir, o, [&](const std::string& w) {
    if (warnings) warnings->push_back(w);
  });
  CentreNoise out;
  double sum2 = 0;
  int n = 0;
  for (const ScanFrameSummary& f : s.frames) {
    for (const ScanPoint& p : ReadScanCsv(run.dir / ScanCentersName(f.index))) {
      ++out.points;
      if (p.pixel.u < 2 || p.pixel.u > run.camera.width() - 3) continue;
      const double e = p.pixel.v - run.Row(0, p.pixel.u);
      sum2 += e * e;
      ++n;
    }
  }
  out.rms = n > 0 ? std::sqrt(sum2 / n) : NAN;
  return out;
}

// A colour sensor's frames are extracted on the channels that see the laser.
// Matched weights (pipeline/channel_weights.h) against the old default, the
// mean of R, G and B, on frames whose noise floor dominates: a red (650 nm:
// QE 0.5, 0.2, 0.05) and a green laser (532 nm: 0.091, 0.469, 0.172).
TEST(Scan, ColourFramesUseTheLaserChannels) {
  ScanOptions matched;
  ScanOptions mean;
  mean.extraction.channel_weights = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  for (double wavelength_nm : {650.0, 532.0}) {
    SCOPED_TRACE(wavelength_nm);
    const std::string nm = std::to_string(int(wavelength_nm));
    // Centre noise: 8 frames of a stripe at 600 e- (300 DN) in its best channel,
    // which both find whole. Where the floor (25^2 + 1/(12 K^2) = 625 e-^2)
    // dominates, the mean's SNR is 0.82 (red) and 0.67 (green) of the matched
    // weights' (pipeline/channel_weights.h: sum(w QE) / sqrt(sum w^2 / N_c),
    // N_c the colour's pixels per 2x2 tile); the stripe's own shot noise (as
    // large as the floor at the peak in the best channel, less in the tails)
    // and the demosaicing bias bring them nearer. Measured rms 0.112 against
    // 0.130 px (red), 0.098 against 0.124 px (green); below 0.9 of the mean's
    // is asked of both.
    SyntheticRun bright = MakeSensorRun("colour_" + nm, wavelength_nm, 600, 8);
    const CentreNoise a = ScanCentreNoise(bright, matched), b = ScanCentreNoise(bright, mean);
    ASSERT_GE(a.points, 8 * 150);
    ASSERT_GE(b.points, 8 * 150);
    EXPECT_LT(a.rms, 0.9 * b.rms) << "matched " << a.rms << " px, mean " << b.rms << " px";
    // Points at the default threshold (10% of 1023 DN): a stripe at 350 e-
    // (175 DN above black) in its best channel reads 0.67 (red) or 0.82 (green)
    // of that in the matched weighted image, above the threshold, and half of
    // it in the mean, below (found only where the noise lifts it): measured 633
    // against 100 points (red), 640 against 195 (green).
    SyntheticRun faint = MakeSensorRun("faint_" + nm, wavelength_nm, 350, 4);
    const CentreNoise fa = ScanCentreNoise(faint, matched), fb = ScanCentreNoise(faint, mean);
    EXPECT_GE(fa.points, 4 * 140);
    EXPECT_LT(fb.points, fa.points / 2);
  }
}

// A rig that does not give its laser's wavelength keeps the mean of R, G and
// B, and says so.
TEST(Scan, ColourFramesWithoutWavelengthKeepTheMean) {
  SyntheticRun run = MakeSensorRun("colour_no_wavelength", 650, 900, 2, false);
  ScanOptions o;
  std::vector<std::string> warnings;
  const CentreNoise a = ScanCentreNoise(run, o, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("gives no wavelength_nm for laser 0: colour frames are extracted on the mean of R, G and B"));
  o.extraction.channel_weights = {1.0 / 3, 1.0 / 3, 1.0 / 3};
  const CentreNoise b = ScanCentreNoise(run, o);
  EXPECT_EQ(a.points, b.points);
  EXPECT_NEAR(a.rms, b.rms, 1e-6);  // the same extraction (weights 1/3 in float either way)
}

// Three-channel colour frames (a camera that demosaics itself) get the same
// matched weights; without the rig's wavelength they need --channel or --weights.
TEST(Scan, ThreeChannelColourFramesUseTheLaserChannels) {
  for (bool with_wavelength : {true, false}) {
    SyntheticRun run = MakeSensorRun(std::string("colour_rgb_") + (with_wavelength ? "1" : "0"), 650, 600, 2,
                                     with_wavelength);
    for (int f = 0; f < 2; ++f) {
      const fs::path path = run.dir / ("frames/" + std::to_string(f) + ".png");
      const Image<uint16_t> raw = std::get<Image<uint16_t>>(ReadImage(path));
      const Image<float> rgb = DemosaicBilinear(raw.View(), ColorFilter::kRGGB);
      Image<uint16_t> out(rgb.width, rgb.height, 3);
      for (size_t i = 0; i < rgb.pixels.size(); ++i) out.pixels[i] = uint16_t(std::lround(rgb.pixels[i]));
      WriteImage(path, out);
    }
    ScanOptions o;
    if (!with_wavelength) {
      try {
        ScanRun(run.dir, o);
        FAIL();
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr("the image has 3 channels: choose the laser's channel"));
      }
      continue;
    }
    const ScanSummary s = ScanRun(run.dir, o);
    ASSERT_EQ(s.channel_weights.size(), 3u);
    EXPECT_GT(s.channel_weights[0], s.channel_weights[2]);
    EXPECT_NEAR(s.channel_weights[0] + s.channel_weights[1] + s.channel_weights[2], 1.0, 1e-12);
    EXPECT_GE(s.points, 2 * 150);
    o.extraction.channel_weights = s.channel_weights;  // the same, given explicitly
    EXPECT_EQ(ScanRun(run.dir, o).points, s.points);
  }
}

// The default threshold and background follow the channel weights: the
// weighted image's full scale is the frame's times the sum of the positive
// weights, its black level the black level times their sum. Weights 2,0,0 give
// the same points as 1,0,0 (a stripe below the threshold in R is found by
// neither; a brighter one at the same centres).
TEST(Scan, DefaultLevelsFollowTheWeights) {
  for (double peak_e : {150.0, 900.0}) {
    SyntheticRun run = MakeSensorRun("weights_scale_" + std::to_string(int(peak_e)), 650, peak_e, 2);
    ScanOptions one, two;
    one.extraction.channel_weights = {1, 0, 0};
    two.extraction.channel_weights = {2, 0, 0};
    const CentreNoise a = ScanCentreNoise(run, one), b = ScanCentreNoise(run, two);
    EXPECT_EQ(a.points, b.points) << peak_e;
    if (a.points > 0 && b.points > 0) {
      EXPECT_NEAR(a.rms, b.rms, 1e-6) << peak_e;
    }
    if (peak_e < 200) {
      EXPECT_LT(a.points, 2 * 50);  // 75 DN < 102.3: only where the noise lifts it
    } else {
      EXPECT_GE(a.points, 2 * 150);
    }
  }
}

TEST(ScanOutput, CsvRoundTripAndPlyLayout) {
  std::vector<ScanPoint> pts(3);
  pts[0].pixel = {10.25, 3, 4.5, 800, 0};
  pts[0].p_in_cam = Eigen::Vector3d(0.001, -0.002, 0.0812345678);
  pts[0].p_in_world = Eigen::Vector3d(1.5, 2.25, -0.125);
  pts[1].pixel = {11, 3.5, 4, 700, -1};
  pts[2].pixel = {12, 3.75, 4, 700, 1};
  pts[2].p_in_cam = Eigen::Vector3d(0, 0, 0.1);
  const std::string csv = FormatScanCsv(pts);
  EXPECT_THAT(csv, HasSubstr("\n11.00000,3.50000,4.000,700,-1,,,,,,\n"));
  EXPECT_THAT(csv, HasSubstr("\n12.00000,3.75000,4.000,700,1,0,0,0.1,,,\n"));
  fs::path p = fs::temp_directory_path() / ("lt_scan_csv_" + std::to_string(::getpid()) + ".csv");
  WriteScanCsv(p, pts);
  auto back = ReadScanCsv(p);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_EQ(back[0].pixel.u, 10.25);
  EXPECT_EQ(*back[0].p_in_cam, *pts[0].p_in_cam);
  EXPECT_EQ(*back[0].p_in_world, *pts[0].p_in_world);
  EXPECT_FALSE(back[1].p_in_cam || back[1].p_in_world);
  EXPECT_TRUE(back[2].p_in_cam && !back[2].p_in_world);
  fs::remove(p);

  PointCloud cloud;
  cloud.points.push_back({{1, 2, 3}, 7, 1, {10, 20, 30}});
  std::string ply = FormatPly(cloud);
  const std::string end = "end_header\n";
  ASSERT_NE(ply.find(end), std::string::npos);
  EXPECT_EQ(ply.size() - (ply.find(end) + end.size()), 3 * 8 + 2 * 4u);
  cloud.has_colour = true;
  ply = FormatPly(cloud);
  EXPECT_THAT(ply, HasSubstr("property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n"));
  EXPECT_EQ(ply.size() - (ply.find(end) + end.size()), 3 * 8 + 2 * 4 + 3u);
  EXPECT_EQ(ply.substr(ply.size() - 3), std::string("\x0a\x14\x1e"));
  cloud.points[0].p.x() = std::nan("");
  EXPECT_THROW(FormatPly(cloud), std::invalid_argument);
}

}  // namespace
}  // namespace lt
