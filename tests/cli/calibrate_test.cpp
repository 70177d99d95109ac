// Calibration end to end: `lasertwin calib-session` writes a small session on
// the demo rig (binned 4 x 4 to 320x256, six views, 2 spp, on a robot arm),
// `lasertwin render` renders it, `lasertwin calibrate camera|laser|hand-eye`
// recovers the camera, the laser plane and tool_from_cam, and `lasertwin scan
// --calib` triangulates the stripes on the board with the result. Then the
// stress cases: a partly visible board, too few views, the wrong board, no
// robot poses: a result from the remaining views or a clear refusal (exit 2),
// never a file with NaN.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unistd.h>

#include "core/image.h"
#include "core/image_io.h"
#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_geometry.h"
#include "pipeline/calib_laser_plane.h"
#include "pipeline/calibration_file.h"
#include "pipeline/run_folder_reader.h"
#include "calib_session_util.h"
#include "ply_util.h"
#include "run_many.h"

#ifdef LT_HAVE_OPENCV
#include <opencv2/core.hpp>
#endif

namespace lt::test {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr double kDeg = M_PI / 180.0;

// The default hand-eye pose of calib-session (docs/calibration.md): the camera
// 40 mm off the flange axis and 110 mm out, turned 90° about it and tilted 10°.
Pose TrueToolFromCam() {
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(0.04, -0.015, 0.11);
  return p;
}

// A copy of the session's run whose manifest keeps the first `lines` lines
// with `edit` applied to each.
fs::path EditedRun(const std::string& name, size_t lines, const std::function<void(nlohmann::json&)>& edit = {}) {
  const Session& s = RenderedSession();
  const fs::path run = NewTestFolder(name) / "run";
  fs::copy(s.run, run, fs::copy_options::recursive);
  std::stringstream in(ReadFile(s.run / "manifest.jsonl"));
  std::string out, line;
  for (size_t i = 0; i < lines && std::getline(in, line); ++i) {
    nlohmann::json j = nlohmann::json::parse(line);
    if (edit) edit(j);
    out += j.dump() + "\n";
  }
  std::ofstream(run / "manifest.jsonl") << out;
  return run;
}

TEST(CalibrateCli, RenderedSessionCalibratesEndToEnd) {
  const Session& s = RenderedSession();
  ASSERT_TRUE(s.ok);
  // The laser step writes OpenCV's XML form (by the extension), which the hand-eye step reads.
  const fs::path cam_yaml = s.dir / "camera.yaml", laser_yaml = s.dir / "laser.xml", all_yaml = s.dir / "all.yaml";
  const CliResult cam = RunCli("calibrate camera " + Quoted(s.run) + " --fix-k3 --out " + Quoted(cam_yaml));
  ASSERT_EQ(cam.exit_code, 0) << cam.err;
  EXPECT_THAT(cam.out, HasSubstr("camera from 6 of 6 views, 320x256"));
  EXPECT_THAT(cam.out, HasSubstr("fx"));
  EXPECT_THAT(cam.out, HasSubstr("  valid within the field the boards observed: corners up to "));
  const CliResult laser =
      RunCli("calibrate laser " + Quoted(s.run) + " --calib " + Quoted(cam_yaml) + " --out " + Quoted(laser_yaml));
  ASSERT_EQ(laser.exit_code, 0) << laser.err;
  EXPECT_THAT(laser.out, HasSubstr("against the true plane"));
  const CliResult he = RunCli("calibrate hand-eye " + Quoted(s.run) + " --calib " + Quoted(laser_yaml) + " --out " +
                              Quoted(all_yaml));
  ASSERT_EQ(he.exit_code, 0) << he.err;
  EXPECT_THAT(he.out, HasSubstr("against the true tool_from_cam"));
  {
    std::ifstream in(laser_yaml);
    std::string first, second;
    std::getline(in, first);
    std::getline(in, second);
    EXPECT_EQ(first, "<?xml version=\"1.0\"?>");  // was "%YAML:1.0" whatever the extension
    EXPECT_EQ(second, "<opencv_storage>");
    const CalibrationFile l = ReadCalibrationFile(laser_yaml);
    EXPECT_TRUE(l.camera.has_value());
    EXPECT_EQ(l.laser_planes.size(), 1u);
  }

  // Each step kept the parts before it.
  const CalibrationFile f = ReadCalibrationFile(all_yaml);
  ASSERT_TRUE(f.camera.has_value());
  ASSERT_EQ(f.laser_planes.size(), 1u);
  ASSERT_TRUE(f.tool_from_cam.has_value());

  // Tolerances for 320x256 images with 2 spp and the sensor's noise: the
  // corners are good to ~0.15 px; the reported σ of fx was 3.5 px and of
  // cx, cy 3-4 px (measured), the bounds are about 3σ.
  const RunRig rig = ReadRunRig(s.run);
  const CalibratedCamera& c = *f.camera;
  EXPECT_EQ(c.width, 320);
  EXPECT_EQ(c.height, 256);
  EXPECT_NEAR(c.fx, rig.camera.fx(), 10);
  EXPECT_NEAR(c.fy, rig.camera.fy(), 10);
  EXPECT_NEAR(c.cx, rig.camera.cx(), 10);
  EXPECT_NEAR(c.cy, rig.camera.cy(), 10);
  EXPECT_NEAR(rig.camera.fx(), 8.889e-3 / (4 * 4.8e-6), 1e-6);  // the demo camera, binned

  // The laser plane through the calibrated camera: the camera's errors
  // dominate. On this small session fx and cy come out about 1σ (3-4 px) off,
  // which turns the rays by up to 0.5° (measured 0.10° / 0.17 mm and 0.44° /
  // 0.20 mm on two noise realisations); the full-size session of
  // docs/experiments.md does 0.011° / 0.018 mm.
  const PlaneError pe = ComparePlanes(f.laser_planes[0], rig.planes_in_cam[0]);
  EXPECT_LT(pe.normal_angle_rad, 1.0 * kDeg);
  EXPECT_LT(pe.offset_m, 0.6e-3);
  // Through the true camera the plane fit alone is measured (0.04° / 0.03 mm here).
  const fs::path true_cam_yaml = s.dir / "laser_true_camera.yaml";
  const CliResult laser_true = RunCli("calibrate laser " + Quoted(s.run) + " --out " + Quoted(true_cam_yaml));
  ASSERT_EQ(laser_true.exit_code, 0) << laser_true.err;
  EXPECT_THAT(laser_true.err, HasSubstr("using the run's true camera"));
  const PlaneError pt = ComparePlanes(ReadCalibrationFile(true_cam_yaml).laser_planes.at(0), rig.planes_in_cam[0]);
  EXPECT_LT(pt.normal_angle_rad, 0.15 * kDeg);
  EXPECT_LT(pt.offset_m, 0.15e-3);

  // Hand-eye (measured 0.3° and 0.3 mm, reported σ 0.15° and 0.11 mm).
  const PoseError he_err = ComparePoses(*f.tool_from_cam, TrueToolFromCam());
  EXPECT_LT(he_err.rotation_rad, 1.0 * kDeg);
  EXPECT_LT(he_err.translation_m, 1.0e-3);

  // Scanning the session's own dim frames with the calibration: the stripe
  // points lie on the board, the world's z = 0 plane (measured: RMS 0.27 and
  // 0.73 mm, worst 0.65 and 1.04 mm on the two realisations above: the errors
  // of the plane and of the intrinsics, with the camera placed by its true poses).
  const fs::path scan_run = NewTestFolder("calibrate_scan") / "run";
  fs::copy(s.run, scan_run, fs::copy_options::recursive);
  const CliResult scan = RunCli("scan " + Quoted(scan_run) + " --calib " + Quoted(all_yaml) + " --quiet");
  ASSERT_EQ(scan.exit_code, 0) << scan.err;
  const std::vector<PlyVertex> cloud = ReadPly(scan_run / "cloud.ply");
  ASSERT_GT(cloud.size(), 100u);
  double worst = 0, sum2 = 0;
  for (const PlyVertex& v : cloud) {
    worst = std::max(worst, std::abs(v.p.z));
    sum2 += v.p.z * v.p.z;
  }
  const double rms = std::sqrt(sum2 / double(cloud.size()));
  EXPECT_LT(rms, 1.2e-3) << "worst " << worst;
  EXPECT_LT(worst, 2.5e-3) << "rms " << rms;

#ifdef LT_HAVE_OPENCV
  // OpenCV reads the file as it is.
  cv::FileStorage fs(all_yaml.string(), cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat k, d, planes, x;
  fs["camera_matrix"] >> k;
  fs["distortion_coefficients"] >> d;
  fs["laser_planes"] >> planes;
  fs["tool_from_cam"] >> x;
  EXPECT_EQ(int(fs["image_width"]), 320);
  ASSERT_EQ(k.rows, 3);
  EXPECT_DOUBLE_EQ(k.at<double>(0, 0), c.fx);
  EXPECT_EQ(d.total(), 5u);
  ASSERT_EQ(planes.cols, 4);
  EXPECT_DOUBLE_EQ(planes.at<double>(0, 3), f.laser_planes[0].d);
  ASSERT_EQ(x.rows, 4);
  EXPECT_DOUBLE_EQ(x.at<double>(0, 3), f.tool_from_cam->translation().x());
  cv::FileStorage xml(laser_yaml.string(), cv::FileStorage::READ);  // the XML form
  ASSERT_TRUE(xml.isOpened());
  xml["laser_planes"] >> planes;
  ASSERT_EQ(planes.cols, 4);
  EXPECT_DOUBLE_EQ(planes.at<double>(0, 3), f.laser_planes[0].d);
  EXPECT_EQ(std::string(xml["distortion_model"]), "brown_conrady");
#endif
}

// A board half hidden in one view: the view is skipped with the detector's
// reason and the other five calibrate.
// The laser step starts from a camera calibrated by another tool: the run's
// camera written as a ROS camera_info file (a stereo rectification, warned
// about) and as a Kalibr camchain gives the plane the same camera gives in
// OpenCV's form, bit for bit, and the output keeps that camera. (Before:
// both refused, "the first line must be %YAML:1.0".) The camchain is a stereo
// rig's, the run's camera its cam1, read with --calib-camera cam1.
TEST(CalibrateCli, LaserStepFromRosAndKalibrCameraFiles) {
  const Session& s = RenderedSession();
  ASSERT_TRUE(s.ok);
  const fs::path dir = NewTestFolder("calibrate_other_formats");
  const RunRig rig = ReadRunRig(s.run);
  // The run's intrinsics with a small distortion of its own, the same in every file.
  CalibrationFile opencv;
  opencv.camera = CalibratedCamera::From(rig.camera);
  opencv.camera->distortion = DistortionModel::kBrownConrady;
  opencv.camera->brown_conrady = {-0.01, 0.002, 0.0005, -0.0003, 0};
  const CalibratedCamera& c = *opencv.camera;
  const BrownConradyCoeffs b = c.brown_conrady;
  WriteCalibrationFile(dir / "camera.yml", opencv);
  {
    // Keys of another program's own (a VINS config holds dozens): one warning names them.
    std::ofstream extra(dir / "camera.yml", std::ios::app);
    for (int k = 0; k < 10; ++k) extra << "extra_" << k << ": 1\n";
  }
  auto n = [](double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  std::ofstream(dir / "ost.yaml") << "image_width: " << c.width << "\nimage_height: " << c.height
                                  << "\ncamera_name: scanner\ncamera_matrix:\n  rows: 3\n  cols: 3\n  data: [" << n(c.fx)
                                  << ", 0, " << n(c.cx) << ", 0, " << n(c.fy) << ", " << n(c.cy)
                                  << ", 0, 0, 1]\ndistortion_model: plumb_bob\ndistortion_coefficients:\n  rows: 1\n"
                                  << "  cols: 5\n  data: [" << n(b.k1) << ", " << n(b.k2) << ", " << n(b.p1) << ", "
                                  << n(b.p2) << ", " << n(b.k3) << "]\nrectification_matrix:\n  rows: 3\n  cols: 3\n"
                                  << "  data: [0.9998, -0.02, 0, 0.02, 0.9998, 0, 0, 0, 1]\n";
  std::ofstream(dir / "camchain.yaml") << "cam0:\n  camera_model: pinhole\n  intrinsics: [400, 401, 150, 120]\n"
                                       << "  resolution: [320, 240]\n"
                                       << "cam1:\n  camera_model: pinhole\n  intrinsics: [" << n(c.fx) << ", " << n(c.fy)
                                       << ", " << n(c.cx) << ", " << n(c.cy) << "]\n  distortion_model: radtan\n"
                                       << "  distortion_coeffs: [" << n(b.k1) << ", " << n(b.k2) << ", " << n(b.p1)
                                       << ", " << n(b.p2) << "]\n  resolution: [" << c.width << ", " << c.height << "]\n";
  std::vector<CalibrationFile> out;
  for (const char* in : {"camera.yml", "ost.yaml", "camchain.yaml"}) {
    const fs::path result = dir / (std::string("laser_from_") + in + ".yml");
    const std::string camera = std::string(in) == "camchain.yaml" ? " --calib-camera cam1" : "";
    const CliResult r = RunCli("calibrate laser " + Quoted(s.run) + " --calib " + Quoted(dir / in) + camera + " --out " +
                               Quoted(result) + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << in << "\n" << r.err;
    EXPECT_THAT(r.err, ::testing::Not(HasSubstr("using the run's true camera"))) << in;
    if (std::string(in) == "camera.yml") {
      EXPECT_THAT(r.err, HasSubstr((dir / in).string() + ": 10 keys (extra_0, extra_1, extra_2, extra_3, extra_4, "
                                                          "extra_5, extra_6, extra_7 and 2 more) are not kept in the output"));
      EXPECT_EQ(r.err.find("not kept"), r.err.rfind("not kept")) << r.err;  // one line
    }
    if (std::string(in) == "ost.yaml") {
      EXPECT_THAT(r.err, HasSubstr((dir / "ost.yaml").string() + ":13: rectification_matrix is not the identity"));
    }
    out.push_back(ReadCalibrationFile(result));
  }
  ASSERT_EQ(out.size(), 3u);
  for (const CalibrationFile& f : out) {
    ASSERT_TRUE(f.camera);
    EXPECT_EQ(f.camera->fx, c.fx);
    EXPECT_EQ(f.camera->cy, c.cy);
    EXPECT_EQ(f.camera->brown_conrady.p1, b.p1);
    ASSERT_EQ(f.laser_planes.size(), 1u);
    EXPECT_EQ(f.laser_planes[0].n, out[0].laser_planes[0].n);
    EXPECT_EQ(f.laser_planes[0].d, out[0].laser_planes[0].d);
  }
}

TEST(CalibrateCli, PartlyVisibleBoardIsSkipped) {
  ASSERT_TRUE(RenderedSession().ok);
  const fs::path run = EditedRun("calibrate_partial", 12);
  const fs::path frame0 = run / "frames/000000.png";
  Image<uint16_t> img = std::get<Image<uint16_t>>(ReadImage(frame0));
  for (int y = 0; y < img.height; ++y) {
    for (int x = img.width / 2; x < img.width; ++x) img.At(x, y, 0) = 0;
  }
  WriteImage(frame0, img);
  const CliResult r = RunCli("calibrate camera " + Quoted(run) + " --fix-k3 --out " + Quoted(run / "c.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("frame 0: "));
  EXPECT_THAT(r.out, HasSubstr("camera from 5 of 6 views"));
}

// `calibrate camera FOLDER` on a folder of photographs (no manifest.jsonl):
// every image file is a view; the board must be given. (Before: "manifest.jsonl:
// run manifest not found", whatever the folder held.)
TEST(CalibrateCli, AFolderOfPhotographs) {
  CameraParams p;
  p.width = 640, p.height = 480, p.fx = 805, p.fy = 803, p.cx = 323.4, p.cy = 236.8;
  p.distortion = DistortionModel::kBrownConrady;
  p.brown_conrady = {-0.18, 0.08, 0, 0, 0};
  const Camera cam(p);
  CheckerboardSpec b;
  b.rows = 7, b.cols = 10, b.square_m = 6e-3;
  const fs::path dir = fs::temp_directory_path() / ("lt_calibrate_photos_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "photos");
  fs::create_directories(dir / "empty");
  const Eigen::Vector3d centre(4.5 * b.square_m, 3 * b.square_m, 0);
  const double views[][4] = {{0, 0, 30, 0}, {0.02, -0.01, 35, 90}, {-0.02, 0.01, 30, 45}, {0.02, 0.02, 25, 135},
                             {-0.02, -0.01, 40, 200}, {0, 0.02, 20, 270}};
  int k = 0;
  for (const auto& v : views) {
    Pose pose = Pose::Identity();
    pose.linear() =
        Eigen::AngleAxisd(v[2] * kDeg, Eigen::Vector3d(std::cos(v[3] * kDeg), std::sin(v[3] * kDeg), 0)).toRotationMatrix();
    pose.translation() = Eigen::Vector3d(v[0], v[1], 0.21) - pose.linear() * centre;
    SyntheticBoardOptions o;
    o.supersampling = 8;
    const Image<float> f = RenderCheckerboard(cam, pose, b, o);
    Image<uint8_t> img(f.width, f.height);
    for (size_t i = 0; i < f.pixels.size(); ++i) img.pixels[i] = uint8_t(std::lround(20 + 210 * f.pixels[i]));
    WriteImage(dir / "photos" / ("view" + std::to_string(k++) + ".png"), img);
  }
  const fs::path out = dir / "camera.yaml";
  const std::vector<CliResult> r = RunMany({
      "calibrate camera " + Quoted(dir / "photos") + " --rows 7 --cols 10 --square-mm 6 --fix-k3 --out " + Quoted(out),
      "calibrate camera " + Quoted(dir / "photos") + " --out " + Quoted(dir / "x.yaml"),
      "calibrate camera " + Quoted(dir / "empty") + " --rows 7 --cols 10 --square-mm 6 --out " + Quoted(dir / "x.yaml"),
  });
  ASSERT_EQ(r[0].exit_code, 0) << r[0].err;
  EXPECT_THAT(r[0].out, HasSubstr("camera from 6 of 6 images, 640x480"));
  const CalibrationFile c = ReadCalibrationFile(out);
  ASSERT_TRUE(c.camera);
  EXPECT_NEAR(c.camera->fx, p.fx, 1.0);  // noise-free 8-bit images: measured within 0.1 px
  EXPECT_NEAR(c.camera->cx, p.cx, 1.0);
  EXPECT_NEAR(c.camera->brown_conrady.k1, -0.18, 0.005);
  EXPECT_EQ(r[1].exit_code, 2);
  EXPECT_THAT(r[1].err, HasSubstr("a folder of photographs (no manifest.jsonl): give the board"));
  EXPECT_EQ(r[2].exit_code, 2);
  EXPECT_THAT(r[2].err, HasSubstr("empty: no image files in the folder"));
  EXPECT_FALSE(fs::exists(dir / "x.yaml"));
}

// The session recorded as a real capture (no manifest, no rig): the laser
// plane and hand-eye pose from it, with --shutter, --poses, --bit-depth and the
// camera from --calib, equal those from the run. Before, `calibrate` read only
// a run with a manifest ("manifest.jsonl: run manifest not found").
TEST(CalibrateCli, ACaptureWithoutManifestCalibratesAsTheRun) {
  const Session& s = RenderedSession();
  ASSERT_TRUE(s.ok);
  fs::path poses, view_poses;
  const fs::path capture = CaptureOfSession("calibrate_capture", &poses);
  CaptureOfSession("calibrate_capture_views", &view_poses, 2);
  const fs::path dir = capture.parent_path();
  const std::string board = " --board " + Quoted(s.dir / "session/checkerboard.json");
  const std::string shutter = " --shutter alternate-bright-first --bit-depth 10";
  const CliResult cam = RunCli("calibrate camera " + Quoted(s.run) + " --fix-k3 --quiet --out " + Quoted(dir / "cam.yaml"));
  ASSERT_EQ(cam.exit_code, 0) << cam.err;
  const std::vector<CliResult> laser = RunMany({
      "calibrate laser " + Quoted(s.run) + " --calib " + Quoted(dir / "cam.yaml") + " --out " + Quoted(dir / "run.yaml"),
      // Poses are the hand-eye step's: the laser step warns and reads no file.
      "calibrate laser " + Quoted(capture) + shutter + board + " --planes 1 --calib " + Quoted(dir / "cam.yaml") +
          " --poses " + Quoted(dir / "no_such_poses.csv") + " --out " + Quoted(dir / "capture.yaml"),
      "calibrate camera " + Quoted(capture) + shutter + board + " --fix-k3 --out " + Quoted(dir / "cam_capture.yaml"),
  });
  for (const CliResult& r : laser) ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(laser[1].err, HasSubstr("frames: the 12 image files of"));
  EXPECT_THAT(laser[1].err, HasSubstr("warning: --poses: the laser step uses no robot poses"));
  // No rig: the stripe's axis from the frames (the rows' search gave another plane, 0.008 deg off).
  EXPECT_THAT(laser[1].err, HasSubstr("stripes searched along the columns"));
  EXPECT_THAT(laser[2].out, HasSubstr("camera from 6 of 6 views, 320x256"));
  const CalibrationFile run_laser = ReadCalibrationFile(dir / "run.yaml");
  const CalibrationFile capture_laser = ReadCalibrationFile(dir / "capture.yaml");
  ASSERT_EQ(capture_laser.laser_planes.size(), 1u);
  // The same frames, extraction and fit: the same numbers.
  EXPECT_EQ(capture_laser.laser_planes[0].n, run_laser.laser_planes[0].n);
  EXPECT_EQ(capture_laser.laser_planes[0].d, run_laser.laser_planes[0].d);
  EXPECT_EQ(ReadCalibrationFile(dir / "cam_capture.yaml").camera->fx, ReadCalibrationFile(dir / "cam.yaml").camera->fx);

  const std::vector<CliResult> he = RunMany({
      "calibrate hand-eye " + Quoted(s.run) + " --calib " + Quoted(dir / "run.yaml") + " --out " + Quoted(dir / "he_run.yaml"),
      "calibrate hand-eye " + Quoted(capture) + shutter + board + " --poses " + Quoted(poses) + " --calib " +
          Quoted(dir / "run.yaml") + " --out " + Quoted(dir / "he_capture.yaml"),
      // The robot's log of one pose per view (per bright frame).
      "calibrate hand-eye " + Quoted(capture) + shutter + board + " --poses " + Quoted(view_poses) + " --calib " +
          Quoted(dir / "run.yaml") + " --out " + Quoted(dir / "he_views.yaml"),
  });
  for (const CliResult& r : he) ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(he[1].err, HasSubstr("poses: world_from_tool from " + poses.string() + " (CSV columns x,y,z,qw,qx,qy,qz, mm)"));
  EXPECT_THAT(he[2].err, HasSubstr(", one per bright frame"));
  const Pose x = *ReadCalibrationFile(dir / "he_run.yaml").tool_from_cam;
  for (const char* name : {"he_capture.yaml", "he_views.yaml"}) {
    const CalibrationFile f = ReadCalibrationFile(dir / name);
    ASSERT_TRUE(f.tool_from_cam) << name;
    // The tool poses went through millimetres in 17 digits: equal to 1e-9.
    const PoseError e = ComparePoses(*f.tool_from_cam, x);
    EXPECT_LT(e.rotation_rad, 1e-9) << name;
    EXPECT_LT(e.translation_m, 1e-9) << name;
    EXPECT_EQ(f.laser_planes.size(), 1u) << name;  // --calib's parts kept
  }
}

// A capture's refusals: each clear, before or after the work, and no file written.
TEST(CalibrateCli, CaptureRefusalsAreClear) {
  ASSERT_TRUE(RenderedSession().ok);
  fs::path poses, five;
  const fs::path capture = CaptureOfSession("calibrate_capture_refusals", &poses);
  CaptureOfSession("calibrate_capture_five", &five, 1, 5);
  const fs::path dir = capture.parent_path();
  const fs::path out = dir / "out.yaml";
  const std::string board = " --board " + Quoted(RenderedSession().dir / "session/checkerboard.json");
  const std::string shutter = " --shutter alternate-bright-first";
  {
    const CliResult r = RunCli("calibrate camera " + Quoted(RenderedSession().run) + " --fix-k3 --quiet --out " +
                               Quoted(dir / "cam.yaml"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string calib = " --calib " + Quoted(dir / "cam.yaml");
  const std::vector<CliResult> r = RunMany({
      "calibrate laser " + Quoted(capture) + shutter + board + " --planes 1 --out " + Quoted(out),
      "calibrate laser " + Quoted(capture) + shutter + calib + " --planes 1 --out " + Quoted(out),
      "calibrate hand-eye " + Quoted(capture) + shutter + board + calib + " --poses " + Quoted(five) + " --out " + Quoted(out),
      "calibrate hand-eye " + Quoted(capture) + " --shutter alternate" + board + calib + " --poses " + Quoted(poses) +
          " --out " + Quoted(out),
      "calibrate hand-eye " + Quoted(capture) + shutter + board + calib + " --out " + Quoted(out),
      "calibrate laser " + Quoted(capture) + board + calib + " --planes 1 --out " + Quoted(out),
      "calibrate laser " + Quoted(capture) + shutter + board + calib + " --out " + Quoted(out),
      "calibrate camera " + Quoted(capture) + " --shutter alternate" + board + " --out " + Quoted(out),
      "calibrate laser " + Quoted(capture) + shutter + board + calib + " --planes 1 --bit-depth 17 --out " + Quoted(out),
      "calibrate laser " + Quoted(capture) + shutter + board + calib + " --planes 1 --pose-units mm --out " + Quoted(out),
  });
  for (size_t i = 0; i < r.size(); ++i) EXPECT_EQ(r[i].exit_code, 2) << i << ": " << r[i].out << r[i].err;
  EXPECT_THAT(r[0].err, HasSubstr("no rig.json or scene.json, so no camera: give the calibrated camera with --calib"));
  EXPECT_THAT(r[1].err, HasSubstr("no scene.json to find the session's checkerboard.json in: give the board with --board"));
  EXPECT_THAT(r[2].err, HasSubstr("robot_poses.csv: holds 5 poses but " + (capture / "frames").string() +
                                  " has 12 frames (one pose per frame"));
  EXPECT_THAT(r[2].err, HasSubstr("; or one per bright frame: 6"));
  for (size_t i : {3, 7}) {
    EXPECT_THAT(r[i].err, HasSubstr("no bright frame shows the board: are the frames the other way round (--shutter "
                                    "alternate-bright-first)?")) << i;
  }
  EXPECT_THAT(r[4].err, HasSubstr("a capture without manifest.jsonl has no robot poses: give the tool's poses"));
  EXPECT_THAT(r[5].err, HasSubstr("no manifest.jsonl: every frame is a laser frame unless the shutter pattern"));
  EXPECT_THAT(r[6].err, HasSubstr("holds no laser planes: give the number of laser sheets with --planes N"));
  EXPECT_THAT(r[8].err, HasSubstr("--bit-depth: must be 1..16, got 17"));
  EXPECT_THAT(r[9].err, HasSubstr("--pose-units: describes a pose file: give it with --poses"));
  EXPECT_FALSE(fs::exists(out));
}

TEST(CalibrateCli, RefusalsAreClearAndWriteNothing) {
  ASSERT_TRUE(RenderedSession().ok);
  const fs::path two = EditedRun("calibrate_two_views", 4);  // two bright/dim pairs
  const fs::path no_robot = EditedRun("calibrate_no_robot", 12, [](nlohmann::json& j) { j.erase("world_from_tool"); });
  const fs::path run = RenderedSession().run;
  const fs::path out = two.parent_path() / "out.yaml";
  const fs::path out_in_no_folder = two.parent_path() / "no_folder" / "c.yaml";
  std::ofstream(two.parent_path() / "cameras.txt") << "1 PINHOLE 640 480 500 500 320 240\n2 PINHOLE 640 480 510 510 320 240\n";
  const std::vector<CliResult> r = RunMany({
      "calibrate camera " + Quoted(two) + " --out " + Quoted(out),
      "calibrate camera " + Quoted(run) + " --rows 5 --cols 8 --square-mm 3 --out " + Quoted(out),
      "calibrate hand-eye " + Quoted(no_robot) + " --out " + Quoted(out),
      "calibrate laser " + Quoted(run) + " --calib " + Quoted(two / "missing.yaml") + " --out " + Quoted(out),
      "calibrate camera " + Quoted(run) + " --rows 5 --out " + Quoted(out),
      "calibrate focus " + Quoted(run) + " --out " + Quoted(out),
      "calib-session --out " + Quoted(two.parent_path() / "s") + " --rows 1 --cols 8",
      "calib-session --out " + Quoted(two.parent_path() / "s") + " --square-mm 12 --rig " +
          Quoted(kSource / "scenes/demo/scene.json"),
      // Before any work: an output folder that does not exist, a coefficient the model has not.
      "calibrate camera " + Quoted(run) + " --out " + Quoted(out_in_no_folder),
      "calibrate camera " + Quoted(run) + " --model fisheye --fix-k3 --out " + Quoted(out),
      // A form the writer does not have (it wrote YAML into any name before).
      "calibrate camera " + Quoted(run) + " --out " + Quoted(two.parent_path() / "c.json"),
      "calibrate laser " + Quoted(run) + " --out " + Quoted(two.parent_path() / "calib"),
      // --calib-camera without --calib; a camera the file does not hold.
      "calibrate laser " + Quoted(run) + " --calib-camera cam1 --out " + Quoted(out),
      "calibrate laser " + Quoted(run) + " --calib " + Quoted(two.parent_path() / "cameras.txt") + " --calib-camera 3 --out " +
          Quoted(out),
  });
  for (size_t i = 0; i < r.size(); ++i) EXPECT_EQ(r[i].exit_code, 2) << i << ": " << r[i].out << r[i].err;
  EXPECT_THAT(r[0].err, HasSubstr("camera calibration refused (2 of 2 views with the board): too few views"));
  EXPECT_THAT(r[1].err, HasSubstr("not the complete 5 x 8 board"));
  EXPECT_THAT(r[1].err, HasSubstr("camera calibration refused (0 of 6 views"));
  EXPECT_THAT(r[2].err, HasSubstr("no robot tool pose (manifest key world_from_tool)"));
  EXPECT_THAT(r[2].err, HasSubstr("hand-eye calibration refused"));
  EXPECT_THAT(r[3].err, HasSubstr("missing.yaml"));
  EXPECT_THAT(r[4].err, HasSubstr("give all three"));
  EXPECT_THAT(r[6].err, HasSubstr("the board needs at least 2 x 2 inner corners"));
  EXPECT_THAT(r[7].err, HasSubstr("use a smaller board"));
  EXPECT_THAT(r[8].err, HasSubstr("--out: the folder of"));
  EXPECT_THAT(r[8].err, HasSubstr("does not exist"));
  EXPECT_THAT(r[9].err, HasSubstr("option fix_k3: holds the Brown–Conrady model's k3; the model is fisheye"));
  EXPECT_THAT(r[10].err, HasSubstr("c.json: unknown extension '.json': a calibration file is written as OpenCV YAML "
                                   "(.yaml, .yml) or OpenCV XML (.xml)"));
  EXPECT_THAT(r[11].err, HasSubstr("calib: no extension"));
  EXPECT_THAT(r[12].err, HasSubstr("--calib-camera: picks a camera of --calib's file: give --calib"));
  EXPECT_THAT(r[13].err, HasSubstr((two.parent_path() / "cameras.txt").string() +
                                   ":1: no camera '3' in a COLMAP cameras.txt: its cameras are '1', '2'"));
  for (size_t i : {10, 11}) {  // refused before any work: no result, no warning of the laser step
    EXPECT_THAT(r[i].out + r[i].err, ::testing::Not(HasSubstr("from 6 of 6")));
    EXPECT_THAT(r[i].err, ::testing::Not(HasSubstr("warning")));
  }
  EXPECT_FALSE(fs::exists(two.parent_path() / "c.json"));
  EXPECT_FALSE(fs::exists(two.parent_path() / "calib"));
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace lt::test
