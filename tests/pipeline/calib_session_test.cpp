// Session helpers of pipeline/calib_session.h that need no rendered run: the
// multi-line grouping of stripe pieces on the flat board, and the board file.
// (The whole chain on a rendered session is tests/cli/calibrate_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <unistd.h>

#include "core/error.h"
#include "core/image_io.h"
#include <nlohmann/json.hpp>
#include "pipeline/calib_board_turns.h"
#include "pipeline/calib_session.h"
#include "calib_test_util.h"

namespace lt {
namespace {

// Three stripes across a 640-column image (searched along columns: u is the
// column, v the subpixel row), nearly parallel with perspective, each broken
// every 30 columns as on black squares, plus one short stray piece.
std::vector<StripePoint> ThreeBrokenStripes(int* stray_first) {
  std::vector<StripePoint> pts;
  const double a[3] = {100, 170, 240}, b[3] = {0.30, 0.32, 0.34};
  for (int u = 40; u < 600; ++u) {
    if ((u / 30) % 2 == 1) continue;  // the stripe is too dim on black squares
    for (int k = 0; k < 3; ++k) {
      StripePoint p;
      p.u = u;
      p.v = a[k] + b[k] * u + 0.2 * std::sin(0.7 * u + k);  // 0.2 px of wobble
      p.plane = 7;
      pts.push_back(p);
    }
  }
  *stray_first = int(pts.size());
  for (int u = 300; u < 308; ++u) pts.push_back(StripePoint{double(u), 420.0 + 0.1 * u, 2, 1, 7});
  return pts;
}

TEST(CalibSessionGrouping, JoinsTheBrokenPiecesOfEachStripeInImageOrder) {
  int stray_first = 0;
  const std::vector<StripePoint> pts = ThreeBrokenStripes(&stray_first);
  PlaneIdOptions o;
  o.axis = SearchAxis::kCols;
  const PlaneIdentification id = IdentifyPlanes(pts, PixelRect{0, 0, 640, 512}, 3, o);
  ASSERT_GT(id.segments.size(), 20u);  // the stripes come in pieces
  std::vector<StripePoint> grouped = id.points;
  std::string error;
  ASSERT_TRUE(GroupStripesOnFlatTarget(&grouped, id.segments, 3, SearchAxis::kCols, 3.0, &error)) << error;
  for (int i = 0; i < stray_first; ++i) EXPECT_EQ(grouped[size_t(i)].plane, i % 3) << i;  // top to bottom
  for (size_t i = size_t(stray_first); i < grouped.size(); ++i) EXPECT_EQ(grouped[i].plane, -1) << i;
}

TEST(CalibSessionGrouping, RefusesAnotherNumberOfLines) {
  int stray_first = 0;
  std::vector<StripePoint> pts = ThreeBrokenStripes(&stray_first);
  pts.resize(size_t(stray_first));
  std::vector<StripePoint> two;
  for (size_t i = 0; i < pts.size(); ++i) {
    if (i % 3 != 1) two.push_back(pts[i]);  // the middle sheet missed the board
  }
  PlaneIdOptions o;
  o.axis = SearchAxis::kCols;
  const PlaneIdentification id = IdentifyPlanes(two, PixelRect{0, 0, 640, 512}, 3, o);
  std::vector<StripePoint> grouped = id.points;
  std::string error;
  EXPECT_FALSE(GroupStripesOnFlatTarget(&grouped, id.segments, 3, SearchAxis::kCols, 3.0, &error));
  EXPECT_EQ(error, "found 2 stripe line(s) on the board, expected 3");
}

TEST(CalibSessionBoard, BoardFileIsReadStrictly) {
  const auto dir = std::filesystem::temp_directory_path() / ("lt_calib_board_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& text) {
    std::ofstream(dir / "checkerboard.json") << text;
    return dir / "checkerboard.json";
  };
  const CheckerboardSpec b = ReadCheckerboardFile(write(R"({"rows": 6, "cols": 9, "square_mm": 2.5})"));
  EXPECT_EQ(b.rows, 6);
  EXPECT_EQ(b.cols, 9);
  EXPECT_DOUBLE_EQ(b.square_m, 2.5e-3);
  EXPECT_EQ(b.margin_squares, 1);
  // A symmetric board (rows + cols even) is read: the camera and laser steps take it.
  EXPECT_TRUE(ReadCheckerboardFile(write(R"({"rows": 6, "cols": 8, "square_mm": 3})")).Symmetric());
  for (const char* bad : {R"({"rows": 6, "cols": 9, "square_mm": 0})",
                          R"({"rows": 6, "cols": 9, "square_mm": 3, "colour": 1})", R"({"rows": 6, "cols": 9})"}) {
    try {
      ReadCheckerboardFile(write(bad));
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("checkerboard.json"), std::string::npos) << e.what();
    }
  }
  // A run folder without a scene names what is missing.
  try {
    FindSessionBoardFile(dir);
    ADD_FAILURE() << "found a board without a scene";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

// A recorded session without a renderer: bright frames of a synthetic board
// (RenderCheckerboard, 1% noise, 10-bit DN in 16-bit PNG), dark laser frames,
// and the robot tool pose of each view in the manifest. The camera and the
// hand-eye pose come back; the laser step finds no stripe and refuses.
namespace session_run {

constexpr double kDeg = M_PI / 180.0;

Pose ToolFromCam() {
  Pose x = Pose::Identity();
  x.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  x.translation() = Eigen::Vector3d(0.05, -0.02, 0.08);
  return x;
}

std::filesystem::path WriteRun(const CheckerboardSpec& board_spec = Board(), const std::string& name = "lt_calib_run_") {
  const auto dir = std::filesystem::temp_directory_path() / (name + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "frames");
  std::ofstream(dir / "scene.json") << R"({"sensor": {"camera": {"resolution": [640, 480], "pixel_pitch_um": 4.8,
    "fx": 805, "fy": 803, "cx": 323.4, "cy": 236.8, "f_number": 4,
    "distortion": {"model": "brown_conrady", "k1": -0.18, "k2": 0.09}}}})";
  const Camera cam(Camera640Params({-0.18, 0.09, 0, 0, 0}));
  const std::vector<Pose> poses = {BoardPose(0, 0, 0.20, 30 * kDeg, 0, 0),
                                   BoardPose(0.03, -0.02, 0.21, 35 * kDeg, 90 * kDeg, 15 * kDeg),
                                   BoardPose(-0.03, 0.02, 0.22, 30 * kDeg, 45 * kDeg, -20 * kDeg),
                                   BoardPose(0.03, 0.025, 0.19, 25 * kDeg, 135 * kDeg, 180 * kDeg),
                                   BoardPose(-0.035, -0.02, 0.23, 40 * kDeg, 200 * kDeg, 5 * kDeg),
                                   BoardPose(0.0, 0.03, 0.20, 20 * kDeg, 270 * kDeg, 90 * kDeg)};
  Pose world_from_board = Pose::Identity();
  world_from_board.translation() = Eigen::Vector3d(0.4, 0.1, 0);
  std::ofstream manifest(dir / "manifest.jsonl");
  const Image<uint16_t> dark(640, 480, 1);
  for (size_t v = 0; v < poses.size(); ++v) {
    SyntheticBoardOptions o;
    o.noise_sigma = 0.01 * (o.white - o.black);
    o.seed = 40 + v;
    const Image<float> board = RenderCheckerboard(cam, poses[v], board_spec, o);
    Image<uint16_t> img(640, 480, 1);
    for (size_t i = 0; i < img.pixels.size(); ++i) {
      img.pixels[i] = uint16_t(std::clamp(std::lround(1000.0 * board.pixels[i]), 0L, 1023L));
    }
    const std::string bright = "frames/" + std::to_string(2 * v) + ".png", dim = "frames/" + std::to_string(2 * v + 1) + ".png";
    WriteImage(dir / bright, img);
    WriteImage(dir / dim, dark);
    const Pose world_from_tool = world_from_board * poses[v].inverse() * ToolFromCam().inverse();
    const nlohmann::json tool = PoseToJson(world_from_tool);
    manifest << nlohmann::json{{"index", 2 * v}, {"files", {{"image", bright}}}, {"shutter", {{"laser_on", false}}},
                               {"bit_depth", 10}, {"world_from_tool", tool}}
                    .dump()
             << "\n"
             << nlohmann::json{{"index", 2 * v + 1}, {"files", {{"image", dim}}}, {"shutter", {{"laser_on", true}}},
                               {"bit_depth", 10}}
                    .dump()
             << "\n";
  }
  return dir;
}

}  // namespace session_run

// The recorded session with a symmetric 7 x 9 board, which the hand-eye step
// refused before (rows + cols must be odd): its views turn the board by up to
// 180 degrees, so the detector's frame differs between views; each view's is
// chosen from the robot's motion and tool_from_cam comes back as with the
// 7 x 10 board.
TEST(CalibSessionRun, HandEyeWithASymmetricBoard) {
  CheckerboardSpec board = Board();
  board.cols = 9;
  const auto run = session_run::WriteRun(board, "lt_calib_run_symmetric_");
  const Camera cam(Camera640Params({-0.18, 0.09, 0, 0, 0}));  // the run's camera
  const SessionHandEyeResult he = CalibrateSessionHandEye(ReadSessionRun(run), board, cam);
  ASSERT_TRUE(he.hand_eye.ok) << he.hand_eye.reason;
  EXPECT_EQ(he.used.size(), 6u);
  const PoseError e = ComparePoses(he.hand_eye.tool_from_cam, session_run::ToolFromCam());
  EXPECT_LT(e.rotation_rad, 0.05 * session_run::kDeg);
  EXPECT_LT(e.translation_m, 0.2e-3);
  std::filesystem::remove_all(run);
}

// AlignBoardFrames on exact poses: views whose frame is turned by a half or
// quarter turn (a square 8 x 8 board) get the first view's frame back.
TEST(CalibSessionRun, BoardFramesAreAlignedByTheRobotsMotion) {
  CheckerboardSpec board = Board();
  board.rows = board.cols = 8;
  const std::vector<Pose> turns = BoardTurns(board);
  ASSERT_EQ(turns.size(), 4u);
  Pose world_from_board = Pose::Identity();
  world_from_board.translation() = Eigen::Vector3d(0.4, 0.1, 0);
  const Pose x = session_run::ToolFromCam();
  std::vector<HandEyeObservation> obs;
  std::vector<Pose> truth;
  const size_t turn_of_view[] = {0, 2, 1, 3, 0, 1};
  for (int v = 0; v < 6; ++v) {
    Pose world_from_tool = Pose::Identity();
    world_from_tool.linear() =
        Eigen::AngleAxisd(0.3 + 0.25 * v, Eigen::Vector3d(std::cos(v), std::sin(v), 2).normalized()).toRotationMatrix();
    world_from_tool.translation() = Eigen::Vector3d(0.4 + 0.01 * v, 0.1 - 0.02 * v, 0.25);
    const Pose cam_from_board = (world_from_tool * x).inverse() * world_from_board;
    truth.push_back(cam_from_board);
    // The detector's frame, turned: p_true = G p_detected.
    const Pose& g = turns[turn_of_view[v]];
    HandEyeObservation o;
    o.base_from_tool = world_from_tool;
    o.cam_from_target = cam_from_board * g;
    for (const Eigen::Vector3d& p : board.CornerPoints()) o.target_points.push_back(p);
    obs.push_back(o);
  }
  const std::vector<std::string> why = AlignBoardFrames(board, &obs);
  for (int v = 0; v < 6; ++v) {
    EXPECT_EQ(why[size_t(v)], "") << v;
    EXPECT_LT((obs[size_t(v)].cam_from_target.matrix() - truth[size_t(v)].matrix()).norm(), 1e-9) << "view " << v;
  }
  // A turned frame maps the corner list onto itself.
  EXPECT_LT((turns[1] * board.CornerPoints().front() - board.CornerPoints().back()).norm(), 1e-12);
}

TEST(CalibSessionRun, CameraAndHandEyeFromARecordedSession) {
  const auto run = session_run::WriteRun();
  const CheckerboardSpec board = Board();
  const SessionCameraResult cam = CalibrateSessionCamera(ReadSessionRun(run), board);
  ASSERT_EQ(cam.views.size(), 6u);
  EXPECT_EQ(cam.views[0].dim_frame, 1);
  ASSERT_TRUE(cam.calibration.ok) << cam.calibration.reason;
  EXPECT_EQ(cam.used.size(), 6u);
  // Rendered boards with 1% noise: corners to a few hundredths of a pixel
  // (docs/calibration.md), so fx to well within 0.5%.
  EXPECT_NEAR(cam.calibration.camera.fx, 805, 4);
  EXPECT_NEAR(cam.calibration.camera.cy, 236.8, 2);
  const Camera calibrated(cam.calibration.camera);

  const SessionHandEyeResult he = CalibrateSessionHandEye(ReadSessionRun(run), board, calibrated);
  ASSERT_TRUE(he.hand_eye.ok) << he.hand_eye.reason;
  const PoseError e = ComparePoses(he.hand_eye.tool_from_cam, session_run::ToolFromCam());
  EXPECT_LT(e.rotation_rad, 0.05 * session_run::kDeg);
  EXPECT_LT(e.translation_m, 0.2e-3);

  // No laser in the rig: the number of planes must be given; then the dark
  // laser frames give no stripe and the fit is refused, with reasons.
  EXPECT_THROW(CalibrateSessionLaser(ReadSessionRun(run), board, calibrated), InputError);
  SessionLaserOptions o;
  o.planes = 1;
  const SessionLaserResult laser = CalibrateSessionLaser(ReadSessionRun(run), board, calibrated, o);
  ASSERT_EQ(laser.laser_views.size(), 6u);
  for (const SessionLaserView& v : laser.laser_views) {
    EXPECT_FALSE(v.used);
    EXPECT_NE(v.note.find("no stripe on the board"), std::string::npos) << v.note;
  }
  for (const LaserPlaneFit& f : laser.fits) EXPECT_FALSE(f.ok);

  // A bright or dim frame of another size than the rig's camera is an error
  // naming it (the corners or the stripe would be read in the wrong pixels).
  for (const char* frame : {"frames/4.png", "frames/5.png"}) {
    const Image<uint16_t> original = std::get<Image<uint16_t>>(ReadImage(run / frame));
    WriteImage(run / frame, Image<uint16_t>(320, 240, 1));
    try {
      if (std::string(frame) == "frames/4.png") {
        CalibrateSessionCamera(ReadSessionRun(run), board);
      } else {
        CalibrateSessionLaser(ReadSessionRun(run), board, calibrated, o);
      }
      ADD_FAILURE() << frame << " of another size was taken";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(frame), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("the image is 320x240 but the camera"), std::string::npos) << e.what();
    }
    WriteImage(run / frame, original);
  }
  std::filesystem::remove_all(run);
}

// The recorded session as a real capture: its frames alone (no manifest, no
// scene.json) and a pose file of the tool poses, one per view, in m. Read with
// the alternating shutter, the bit depth and a given camera, as scan reads a
// capture, it gives the same hand-eye pose as the run.
TEST(CalibSessionRun, ACaptureWithoutManifestIsTheRun) {
  const auto run = session_run::WriteRun(Board(), "lt_calib_capture_");
  const Camera cam(Camera640Params({-0.18, 0.09, 0, 0, 0}));
  const SessionHandEyeResult from_run = CalibrateSessionHandEye(ReadSessionRun(run), Board(), cam);
  ASSERT_TRUE(from_run.hand_eye.ok) << from_run.hand_eye.reason;
  std::ofstream poses(run / "tool.csv");
  poses << "x,y,z,qx,qy,qz,qw\n" << std::setprecision(17);
  std::vector<Pose> tools;
  for (const RunFrame& f : ReadRunManifest(run)) {
    if (!f.world_from_tool) continue;
    tools.push_back(*f.world_from_tool);
    const Eigen::Quaterniond q(f.world_from_tool->linear());
    const Eigen::Vector3d t = f.world_from_tool->translation();
    poses << t.x() << "," << t.y() << "," << t.z() << "," << q.x() << "," << q.y() << "," << q.z() << "," << q.w() << "\n";
  }
  poses.close();
  std::filesystem::remove(run / "manifest.jsonl");
  std::filesystem::remove(run / "scene.json");

  SessionCaptureOptions o;
  o.shutter = ShutterPattern::kAlternateBrightFirst;
  o.poses = run / "tool.csv";
  o.bit_depth = 10;
  {
    const SessionRun c = ReadSessionRun(run, o);  // no camera: only the images' size
    EXPECT_TRUE(c.from_listing);
    EXPECT_FALSE(c.has_camera);
    EXPECT_EQ(c.width, 640);
    ASSERT_EQ(c.frames.size(), 12u);
    EXPECT_FALSE(c.frames[4].IsLaserFrame());
    EXPECT_TRUE(c.frames[5].IsLaserFrame());
    EXPECT_EQ(c.frames[5].bit_depth, 10);
    ASSERT_TRUE(c.frames[4].world_from_tool);  // the third view's pose
    EXPECT_LT((c.frames[4].world_from_tool->matrix() - tools[2].matrix()).norm(), 1e-12);
    EXPECT_NE(c.pose_source.find(", one per bright frame"), std::string::npos) << c.pose_source;
  }
  o.camera = cam;
  o.camera_source = "cam.yaml";
  const SessionRun c = ReadSessionRun(run, o);
  EXPECT_TRUE(c.has_camera);
  EXPECT_FALSE(c.rig_in_run);
  // --bayer: the sensor's mosaic, as scan's (without it and a rig, mono).
  EXPECT_EQ(c.rig.color_filter, ColorFilter::kMono);
  {
    SessionCaptureOptions bayer = o;
    bayer.color_filter = ColorFilter::kRGGB;
    EXPECT_EQ(ReadSessionRun(run, bayer).rig.color_filter, ColorFilter::kRGGB);
  }
  const SessionHandEyeResult from_capture = CalibrateSessionHandEye(c, Board(), cam);
  ASSERT_TRUE(from_capture.hand_eye.ok) << from_capture.hand_eye.reason;
  EXPECT_EQ(from_capture.used, from_run.used);
  const PoseError e = ComparePoses(from_capture.hand_eye.tool_from_cam, from_run.hand_eye.tool_from_cam);
  EXPECT_LT(e.rotation_rad, 1e-9);
  EXPECT_LT(e.translation_m, 1e-9);

  // A camera of another size than the images is named with the first image.
  CameraParams small = cam.params();
  small.width = 320, small.height = 240;
  o.camera = Camera(small);
  try {
    ReadSessionRun(run, o);
    ADD_FAILURE() << "a 320x240 camera was taken for 640x480 images";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("0.png: the image is 640x480 but the camera (cam.yaml) is 320x240"),
              std::string::npos) << err.what();
  }
  std::filesystem::remove_all(run);
}

}  // namespace
}  // namespace lt
