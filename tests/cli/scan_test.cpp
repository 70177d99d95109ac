// `lasertwin scan` end to end: render a tiny run (tests/data/scenes/scan_distorted.json:
// a 160x120 camera with Brown-Conrady distortion, 80 mm above the demo's slot
// test part, one laser sheet; frame 0 laser, frame 1 bright), scan it, and
// compare the triangulated points with the renderer's exact stripe centres.
// The PLY is read back with a small reader here. Bad input gives exit code 2
// and a message naming the file and place.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <nlohmann/json.hpp>

#include "plane_scene.h"
#include "ply_util.h"
#include "run_many.h"

namespace lt::test {
namespace {

namespace fs = std::filesystem;

using ::testing::HasSubstr;
using ::testing::StartsWith;

const fs::path kSource = LT_SOURCE_DIR;


std::vector<std::vector<std::string>> ReadCsv(const fs::path& p, const std::string& header) {
  std::stringstream in(ReadFile(p));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, header) << p;
  std::vector<std::vector<std::string>> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    size_t start = 0;
    for (size_t i = 0; i <= line.size(); ++i) {
      if (i == line.size() || line[i] == ',') {
        f.push_back(line.substr(start, i - start));
        start = i + 1;
      }
    }
    rows.push_back(f);
  }
  return rows;
}

Vec3 At(const std::vector<std::string>& f, size_t k) { return {std::stod(f[k]), std::stod(f[k + 1]), std::stod(f[k + 2])}; }

const char* kCentersHeader = "u,v,width,strength,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world";
const char* kTruthHeader = "u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world";

// A tiny reader for the PLY that scan writes: binary little-endian, double
// x y z, int frame, int plane.

class ScanCommand : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    rendered_ = new fs::path(NewTestFolder("scan_rendered"));
    CliResult r = RunCli("render " + Quoted(kSource / "tests/data/scenes/scan_distorted.json") + " --out " +
                            Quoted(*rendered_ / "run") + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete rendered_;
    rendered_ = nullptr;
  }
  // A private copy of the rendered run (each test writes its own outputs).
  static fs::path CopyRun(const std::string& name) {
    fs::path dir = NewTestFolder("scan_" + name) / "run";
    fs::copy(*rendered_ / "run", dir, fs::copy_options::recursive);
    return dir;
  }

  static fs::path* rendered_;
};
fs::path* ScanCommand::rendered_ = nullptr;

// Ground-truth centres by column; `clean` is false where the column's pixels
// straddle a depth step of the part (the truth jumps between it and a
// neighbour). There the stripe is split over two surfaces and any centre of
// the mixture lies between them: no method can give either surface.
struct Truth {
  std::map<int, std::vector<std::string>> by_column;
  bool Clean(int u) const {
    for (int a : {u - 1, u}) {
      auto i = by_column.find(a), j = by_column.find(a + 1);
      if (i == by_column.end() || j == by_column.end()) return false;
      if (std::abs(std::stod(i->second[1]) - std::stod(j->second[1])) > 0.5) return false;
      if (Distance(At(i->second, 3), At(j->second, 3)) > 0.5e-3) return false;
    }
    return true;
  }
};

Truth ReadTruth(const fs::path& run) {
  Truth t;
  for (auto& f : ReadCsv(run / "gt/000000_centers.csv", kTruthHeader)) t.by_column[int(std::lround(std::stod(f[0])))] = f;
  return t;
}

// Largest 3D distance (camera and world frames) between scanned points and the
// truth over clean columns; counts the clean columns compared.
double WorstError(const fs::path& run, const Truth& truth, int* compared) {
  double worst = 0;
  *compared = 0;
  for (const auto& f : ReadCsv(run / "centers/000000.csv", kCentersHeader)) {
    const int u = int(std::lround(std::stod(f[0])));
    if (!truth.Clean(u)) continue;
    EXPECT_EQ(f[4], "0");
    EXPECT_NE(f[5], "") << "clean column " << u << " has no 3D point";
    if (f[5].empty() || f[8].empty()) continue;
    const auto& g = truth.by_column.at(u);
    worst = std::max({worst, Distance(At(f, 5), At(g, 3)), Distance(At(f, 8), At(g, 6))});
    ++*compared;
  }
  return worst;
}

TEST_F(ScanCommand, PointsMatchTheGroundTruth) {
  const fs::path run = CopyRun("truth");
  CliResult r = RunCli("scan " + Quoted(run));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("scanned 1 laser frame (1 without laser light skipped): "));
  EXPECT_THAT(r.err, HasSubstr("(world frame, poses world_from_cam)"));
  EXPECT_TRUE(fs::exists(run / "centers/000000.csv"));
  EXPECT_FALSE(fs::exists(run / "centers/000001.csv"));  // the bright frame
  const Truth truth = ReadTruth(run);
  ASSERT_EQ(truth.by_column.size(), 160u);
  int compared = 0;
  const double worst = WorstError(run, truth, &compared);
  // About 40 of the 160 columns straddle one of the part's 1 mm steps.
  EXPECT_GE(compared, 100);
  // Tolerance 0.1 mm at the ~80 mm working distance. Along a column, one pixel
  // of stripe position is ~0.4 mm in 3D here (0.17 mm pixel footprint, 26.6
  // degree triangulation angle). Com on this 4-spp render with shot and dark
  // noise errs by up to ~0.1 px (~0.04 mm); 0.1 mm = 0.25 px leaves margin for
  // noise, while a wrong laser plane or pose moves points by millimetres.
  EXPECT_LT(worst, 0.1e-3);
}

// --background local (a per-peak background line instead of the black level)
// is accepted and measures the rendered stripe as well (same tolerance as above).
TEST_F(ScanCommand, LocalBackgroundMatchesTheGroundTruth) {
  const fs::path run = CopyRun("local_background");
  CliResult r = RunCli("scan " + Quoted(run) + " --background local");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  int compared = 0;
  const double worst = WorstError(run, ReadTruth(run), &compared);
  EXPECT_GE(compared, 100);
  EXPECT_LT(worst, 0.1e-3);
}

TEST_F(ScanCommand, PlyHoldsTheTriangulatedPoints) {
  const fs::path run = CopyRun("ply");
  CliResult r = RunCli("scan " + Quoted(run) + " --method multicom --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "");
  std::vector<Vec3> csv_world;
  for (const auto& f : ReadCsv(run / "centers/000000.csv", kCentersHeader)) {
    if (!f[8].empty()) csv_world.push_back(At(f, 8));
  }
  std::string header;
  std::vector<PlyVertex> ply = ReadPly(run / "cloud.ply", &header);
  EXPECT_THAT(header, HasSubstr("world frame"));
  // The run has ground truth and bright frames: labels and colour.
  EXPECT_THAT(header, HasSubstr("property int plane\nproperty int label\nproperty uchar red\nproperty uchar green\n"
                                "property uchar blue\nend_header\n"));
  ASSERT_EQ(ply.size(), csv_world.size());
  ASSERT_GT(ply.size(), 140u);
  for (size_t i = 0; i < ply.size(); ++i) {
    EXPECT_EQ(ply[i].frame, 0);
    EXPECT_EQ(ply[i].plane, 0);
    EXPECT_TRUE(ply[i].label == 0 || ply[i].label == 1) << ply[i].label;  // the test part or the bed
    // The CSV has 12 significant digits (1e-14 m at these coordinates).
    EXPECT_LT(Distance(ply[i].p, csv_world[i]), 1e-12) << i;
  }
}

// Calibration files with the rig's own camera and plane, as the calibrate
// command will write them (OpenCV YAML, numbers with 17 digits).
std::string CalibrationYaml(const fs::path& run, bool with_distortion) {
  nlohmann::json rig = nlohmann::json::parse(ReadFile(run / "rig.json"));
  const auto& cam = rig["camera"];
  const auto& plane = rig["lasers"][0]["sheet_planes_in_cam"][0];
  auto num = [](double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  const auto& d = cam["distortion"]["coefficients"];
  std::string text = "%YAML:1.0\n---\nimage_width: 160\nimage_height: 120\ncamera_matrix: !!opencv-matrix\n"
                     "   rows: 3\n   cols: 3\n   dt: d\n   data: [ " +
                     num(cam["fx"]) + ", 0., " + num(cam["cx"]) + ", 0., " + num(cam["fy"]) + ", " + num(cam["cy"]) +
                     ", 0., 0., 1. ]\n";
  if (with_distortion) {
    text += "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ " + num(d[0]) +
            ", " + num(d[1]) + ", " + num(d[2]) + ", " + num(d[3]) + ", " + num(d[4]) + " ]\n";
  }
  text += "laser_planes: !!opencv-matrix\n   rows: 1\n   cols: 4\n   dt: d\n   data: [ " + num(plane["n"][0]) + ", " +
          num(plane["n"][1]) + ", " + num(plane["n"][2]) + ", " + num(plane["d"]) + " ]\n";
  return text;
}

TEST_F(ScanCommand, CalibrationFileWithTheTrueGeometryGivesTheSameResult) {
  const fs::path run = CopyRun("calib_true");
  ASSERT_EQ(RunCli("scan " + Quoted(run) + " --quiet").exit_code, 0);
  const std::string reference = ReadFile(run / "centers/000000.csv");
  std::ofstream(run / "calib.yml") << CalibrationYaml(run, true);
  CliResult r = RunCli("scan " + Quoted(run) + " --calib " + Quoted(run / "calib.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("1 laser plane from " + (run / "calib.yml").string()));
  EXPECT_EQ(ReadFile(run / "centers/000000.csv"), reference);
}

TEST_F(ScanCommand, LensDistortionIsApplied) {
  // The same camera matrix and plane without the lens distortion: the stripe
  // runs near the centre row, so the barrel distortion (k1 = -0.2) mostly moves
  // points along it, by about k1 r^2 |x| = 0.2 x 0.03 x 14 mm = 0.08 mm at the
  // image's left and right ends. Points must move by more than 0.05 mm there.
  const fs::path run = CopyRun("calib_nodist");
  ASSERT_EQ(RunCli("scan " + Quoted(run) + " --quiet").exit_code, 0);
  const auto with = ReadCsv(run / "centers/000000.csv", kCentersHeader);
  std::ofstream(run / "calib.yml") << CalibrationYaml(run, false);
  CliResult r = RunCli("scan " + Quoted(run) + " --quiet --calib " + Quoted(run / "calib.yml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto without = ReadCsv(run / "centers/000000.csv", kCentersHeader);
  ASSERT_EQ(with.size(), without.size());
  double largest = 0;
  for (size_t i = 0; i < with.size(); ++i) {
    if (with[i][5].empty() || without[i][5].empty()) continue;
    largest = std::max(largest, Distance(At(with[i], 5), At(without[i], 5)));
  }
  EXPECT_GT(largest, 0.05e-3);
  EXPECT_LT(largest, 0.15e-3);
}

TEST_F(ScanCommand, BadInputExitsWithTwo) {
  const fs::path base = NewTestFolder("scan_bad");
  const fs::path rig = *rendered_ / "run/rig.json";
  auto make_run = [&](const std::string& name, const std::string& manifest) {
    fs::path dir = base / name;
    fs::create_directories(dir / "frames");
    fs::copy_file(rig, dir / "rig.json");
    if (!manifest.empty()) std::ofstream(dir / "manifest.jsonl") << manifest;
    return dir;
  };
  const std::string line0 = R"({"index":0,"shutter":{"laser_on":true},"files":{"image":"frames/000000.png"},"bit_depth":10})";
  const fs::path no_manifest = make_run("no_manifest", "");
  const fs::path corrupt = make_run("corrupt", line0 + "\n{\"index\": 1, \"files\": \n");
  const fs::path no_image = make_run("no_image", line0 + "\n");
  const fs::path good = CopyRun("bad_calib");
  std::ofstream(good / "garbage.yml") << "camera_matrix: [1, 2, 3]\n";
  std::ofstream(good / "three.csv") << "x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,0,0,0,0,0,1\n0,0,0,0,0,0,1\n";
  std::ofstream(good / "bad.csv") << "x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n0,0,0,0,0,1\n";
  std::ofstream(good / "ambiguous.csv") << "0,0,0,0,0,0,1\n0,0,0,0,0,0,1\n";
  std::ofstream(good / "tf.csv") << "field.child_frame_id,x,y,z,qx,qy,qz,qw\nscanner,0,0,0,0,0,0,1\npart,0,0,0,0,0,0,1\n";
  std::ofstream(good / "cameras.txt") << "1 PINHOLE 640 480 500 500 320 240\n2 PINHOLE 640 480 510 510 320 240\n";

  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {Quoted(base / "nowhere"), (base / "nowhere").string() + ": run folder not found"},
      {Quoted(no_manifest), no_manifest.string() + ": no manifest.jsonl and no image file"},
      {Quoted(corrupt), (corrupt / "manifest.jsonl").string() + ":2:"},
      {Quoted(no_image), (no_image / "frames/000000.png").string() + ": no such file (frame 0, " +
                             (no_image / "manifest.jsonl").string() + ":1)"},
      {Quoted(good) + " --method fastest", "--method: unknown extraction method 'fastest'"},
      {Quoted(good) + " --calib " + Quoted(good / "missing.yml"), (good / "missing.yml").string() + ": cannot open file"},
      {Quoted(good) + " --calib " + Quoted(good / "garbage.yml"),
       (good / "garbage.yml").string() + ":1: not an OpenCV FileStorage YAML file"},
      {Quoted(good) + " --frames 1", (good / "manifest.jsonl").string() + ": no laser frame to scan"},
      {Quoted(good) + " --min-ray-angle-deg 95", "option min_ray_angle_deg: must be in [0, 90) degrees, got 95"},
      {Quoted(good) + " --poses " + Quoted(good / "three.csv"),
       (good / "three.csv").string() + ": holds 3 poses but " + (good / "manifest.jsonl").string() + " has 2 frames"},
      {Quoted(good) + " --poses " + Quoted(good / "bad.csv"), (good / "bad.csv").string() + ":3: 6 fields"},
      {Quoted(good) + " --poses " + Quoted(good / "ambiguous.csv"),
       (good / "ambiguous.csv").string() + ":1: 7 numbers per row (x y z and a quaternion), no header"},
      {Quoted(good) + " --poses " + Quoted(good / "three.csv") + " --pose-units inch", "--pose-units: unknown units 'inch'"},
      {Quoted(good) + " --pose-units mm", "--pose-units: describes a pose file: give it with --poses"},
      {Quoted(good) + " --image-time-offset 0.001", "--image-time-offset: describes a pose file: give it with --poses"},
      {Quoted(good) + " --poses " + Quoted(good / "three.csv") + " --image-time-offset 1ms",
       "--image-time-offset: '1ms' is not a number of seconds"},
      {Quoted(good) + " --poses " + Quoted(good / "three.csv") + " --image-time-offset 0.001",
       (good / "three.csv").string() + ": --image-time-offset matches poses to the images' times, but the file has no times"},
      {Quoted(good) + " --pose-body scanner", "--pose-body: describes a pose file: give it with --poses"},
      {Quoted(good) + " --poses " + Quoted(good / "tf.csv"),
       (good / "tf.csv").string() + ":3: rows of several child frames (column 1 'field.child_frame_id'), mixed in one "
                                    "trajectory if read: give --pose-body: 'scanner', 'part'"},
      {Quoted(good) + " --poses " + Quoted(good / "tf.csv") + " --pose-body robot",
       (good / "tf.csv").string() + ":1: no rows of the child frame 'robot'"},
      {Quoted(good) + " --calib-camera 2", "--calib-camera: picks a camera of --calib's file: give --calib"},
      {Quoted(good) + " --calib " + Quoted(good / "cameras.txt"),
       (good / "cameras.txt").string() + ":2: a COLMAP cameras.txt of 2 cameras: give --calib-camera"},
      {Quoted(good) + " --calib " + Quoted(good / "cameras.txt") + " --calib-camera 3",
       (good / "cameras.txt").string() + ":1: no camera '3' in a COLMAP cameras.txt"},
      {Quoted(good) + " --shutter sometimes", "--shutter: unknown shutter pattern 'sometimes'"},
      {Quoted(good) + " --background ambient", "--background: expected a level (a number) or 'local', got 'ambient'"},
      {Quoted(good) + " --depth-range 60", "--depth-range: expected MIN_MM:MAX_MM (camera z), got '60'"},
      {Quoted(good) + " --depth-range 120:60", "--depth-range: the depth range must be 0 < MIN < MAX (finite), got 120:60 mm"},
  };
  std::vector<std::string> args;
  for (const auto& c : cases) args.push_back("scan " + c.args);
  std::vector<CliResult> results = RunMany(args);
  for (size_t i = 0; i < cases.size(); ++i) {
    EXPECT_EQ(results[i].exit_code, 2) << args[i] << "\n" << results[i].err;
    EXPECT_EQ(results[i].out, "") << args[i];
    EXPECT_THAT(results[i].err, StartsWith("lasertwin: error: " + cases[i].message)) << args[i];
  }
  // Nothing was written for the failed scans.
  EXPECT_FALSE(fs::exists(good / "cloud.ply"));
  EXPECT_FALSE(fs::exists(no_image / "cloud.ply"));
}

// A capture without a manifest: the images of frames/ in name order, the
// camera's pose from a pose file (the manifest's world_from_cam, written as a
// robot would, in millimetres with w first); the world points are the truth's.
TEST_F(ScanCommand, CaptureWithoutManifestTakesTheFolderAndAPoseFile) {
  const fs::path run = CopyRun("capture");
  const nlohmann::json line = nlohmann::json::parse(ReadFile(run / "manifest.jsonl").substr(0, ReadFile(run / "manifest.jsonl").find('\n')));
  const auto& t = line["world_from_cam"]["translation_m"];
  const auto& q = line["world_from_cam"]["rotation_quat_wxyz"];
  ASSERT_EQ(q.size(), 4u);
  char row[400];
  std::snprintf(row, sizeof row, "%.17g;%.17g;%.17g;%.17g;%.17g;%.17g;%.17g\n", 1000 * t[0].get<double>(),
                1000 * t[1].get<double>(), 1000 * t[2].get<double>(), q[0].get<double>(), q[1].get<double>(),
                q[2].get<double>(), q[3].get<double>());
  std::ofstream(run / "poses.csv") << "X_mm;Y_mm;Z_mm;q1;q2;q3;q4\n" << row;
  fs::rename(run / "manifest.jsonl", run / "manifest.jsonl.bak");
  fs::rename(run / "gt", run / "gt.bak");            // ground truth is not the folder's frames
  fs::remove(run / "frames/000001.png");            // the bright frame (no shutter state without a manifest)
  fs::rename(run / "frames/000000.png", run / "frames/Frame_1.PNG");
  CliResult r = RunCli("scan " + Quoted(run) + " --poses " + Quoted(run / "poses.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("frames: the 1 image files of " + (run / "frames").string() +
                               " in file name order (no manifest.jsonl)"));
  EXPECT_THAT(r.err, HasSubstr("(world frame, poses world_from_cam from " + (run / "poses.csv").string() + " (CSV columns x,y,z,q1,q2,q3,q4, mm))"));
  fs::rename(run / "gt.bak", run / "gt");
  const Truth truth = ReadTruth(run);
  int compared = 0;
  EXPECT_LT(WorstError(run, truth, &compared), 0.1e-3);
  EXPECT_GE(compared, 100);
}

// As for extract: a typed nan is not the default threshold (NaN inside), but an
// option error, and nothing is written.
TEST_F(ScanCommand, NonFiniteThresholdsAreRefused) {
  const fs::path run = CopyRun("nan_threshold");
  for (const std::string option : {"--threshold", "--high-threshold"}) {
    CliResult r = RunCli("scan " + Quoted(run) + " " + option + " nan");
    EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(option + (option == "--threshold" ? ": expected a finite number or 'auto', got 'nan'"
                                                                    : ": expected a finite number, got 'nan'")));
  }
  EXPECT_FALSE(fs::exists(run / "cloud.ply"));
}

// A diffractive element's three sheets (sheet_angles_deg -14, -1, 6) on a floor
// 100 mm below a 64x48 camera: the first sheet's stripe falls outside the image
// (as a part, or a weak outer order, can hide an outer sheet everywhere), so
// every column shows 2 stripes, which could be sheets 0 and 1 or 1 and 2.
// Before, scan refused the frame with or without --depth-range (0
// triangulated). Read as sheets 0 and 1 they would lie at 57 and 75 mm: a
// range of 80:120 mm numbers them, each point on its true sheet; 50:200 mm
// admits both readings and numbers nothing; without a range the warning says
// that a depth range would decide.
TEST(ScanDepthRange, ARangeNumbersTheSheetsWhenOneIsMissingOnEveryColumn) {
  const fs::path dir = TestFolder("scan_range_missing_sheet");
  fs::create_directories(dir);
  const nlohmann::json laser = {{"power_mw", 3}, {"wavelength_nm", 650}, {"divergence_deg", 1},
                                {"sheet_angles_deg", {-14, -1, 6}},
                                {"cam_from_projector",
                                 {{"translation_m", {0, 0.04, 0}}, {"rotation_rpy_deg", {std::atan(0.4) * 180 / M_PI, 0, 0}}}}};
  const nlohmann::json scene = PlaneScene(nlohmann::json::array({laser}));
  std::ofstream(dir / "scene.json") << scene.dump();
  const fs::path run = dir / "run";
  ASSERT_EQ(RunCli("render " + Quoted(dir / "scene.json") + " --out " + Quoted(run) + " --quiet").exit_code, 0);
  // The true centres of each column: (row, sheet).
  std::map<long, std::vector<std::pair<double, int>>> truth;
  for (const auto& f : ReadCsv(run / "gt/000000_centers.csv", kTruthHeader)) {
    truth[std::lround(std::stod(f[0]))].push_back({std::stod(f[1]), std::stoi(f[2])});
    EXPECT_NE(std::stoi(f[2]), 0);  // outside the image
  }

  CliResult r = RunCli("scan " + Quoted(run));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("; a working depth range (--depth-range, or the calibration file's depth_min_mm and "
                               "depth_max_mm) would decide which"));
  EXPECT_THAT(r.err + r.out, HasSubstr(" 0 triangulated"));
  r = RunCli("scan " + Quoted(run) + " --depth-range 50:200");
  EXPECT_THAT(r.err, HasSubstr("more than one numbering puts them within the depth range"));
  EXPECT_THAT(r.err + r.out, HasSubstr(" 0 triangulated"));

  r = RunCli("scan " + Quoted(run) + " --depth-range 80:120");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  int right = 0, wrong = 0, none = 0;
  for (const auto& f : ReadCsv(run / "centers/000000.csv", kCentersHeader)) {
    const int plane = std::stoi(f[4]);
    int sheet = -1;  // the true centre within 2 px on the column
    for (const auto& [v, k] : truth[std::lround(std::stod(f[0]))]) sheet = std::abs(v - std::stod(f[1])) < 2 ? k : sheet;
    ASSERT_GE(sheet, 0) << f[0] << "," << f[1];
    ++(plane < 0 ? none : plane == sheet ? right : wrong);
    if (plane >= 0) {  // z_world on the floor (another sheet: 25 mm or more off)
      EXPECT_NEAR(std::stod(f[10]), 0, 2e-3) << f[0] << "," << f[1];
    }
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(none, 0);
  EXPECT_GE(right, 2 * 60);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace lt::test
