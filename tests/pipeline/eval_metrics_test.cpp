// EvaluateRun on synthetic run folders with a known answer: a pinhole camera
// looks at a tilted plane; the ground-truth centres, the depth/normal buffers
// and the "measured" centres are written directly (no extraction), with known
// offsets, dropped rows, extra centres, swapped plane numbers and points moved
// off the surface by a known distance along its normal.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>

#include "core/error.h"
#include "core/image_io.h"
#include "core/pose.h"
#include "pipeline/eval_metrics.h"
#include "pipeline/ground_truth.h"
#include "pipeline/scan_output.h"
#include "sensor/laser.h"
#include "sensor/plane.h"
#include "sensor/rig.h"

namespace lt {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const Camera& EvalCamera() {
  static const Camera camera = [] {
    CameraParams p;
    p.width = 80;
    p.height = 60;
    p.fx = p.fy = 100;
    p.cx = 39.5;
    p.cy = 29.5;
    p.pixel_pitch_m = 10e-6;
    return Camera(p);
  }();
  return camera;
}

// The surface: a plane 0.1 m away, tilted about both axes; its normal faces the camera.
const Plane kSurface = Plane::FromPointNormal({0, 0, 0.1}, Eigen::Vector3d(0.2, -0.1, -1).normalized());
// Pixels at u >= kEdge see nothing (Z = 0).
constexpr int kEdge = 72;

Eigen::Vector3d SurfacePoint(double u, double v) {
  const Eigen::Vector3d r = *EvalCamera().Unproject({u, v});
  return (-kSurface.d / kSurface.n.dot(r)) * r;
}

// The true stripe of plane k on row v (rows are scanned).
double TrueU(int k, int v) { return (k == 0 ? 40.3 : 15.6) + 0.1 * v; }

struct Measured {
  int plane = 0;
  double u = 0, v = 0;
  double off_surface_m = 0;  // moved along the surface normal (towards the camera)
  bool triangulate = true;
};

struct EvalRun {
  fs::path dir;
  int planes = 1;
  std::vector<Measured> measured;
  std::optional<Pose> world_from_cam;       // the manifest's (the true pose)
  std::optional<Pose> scan_world_from_cam;  // the pose the measured points were placed with

  // Every true centre measured with offset du and its own plane.
  static EvalRun Exact(const std::string& name, int planes, double du) {
    EvalRun r;
    r.dir = fs::temp_directory_path() / ("lt_eval_test_" + std::to_string(::getpid())) / name;
    r.planes = planes;
    for (int v = 0; v < EvalCamera().height(); ++v) {
      for (int k = 0; k < planes; ++k) r.measured.push_back({k, TrueU(k, v) + du, double(v)});
    }
    return r;
  }

  void Write(bool scanned = true, bool with_buffers = true) const {
    fs::remove_all(dir);
    fs::create_directories(dir / "gt");
    SensorRig rig;
    rig.camera = EvalCamera();
    // A laser with one sheet per plane of the run (the planes' geometry is not
    // used: the centres and points are written directly).
    LaserParams lp;
    lp.sheet_angles_rad = EvenSheetAngles(planes, 0.05);
    lp.sheet_power.assign(size_t(planes), 1.0);
    rig.lasers.emplace_back(lp);
    std::ofstream(dir / "rig.json") << SensorRigToJson(rig).dump(2);
    std::ofstream truth(dir / "gt/000000_centers.csv");
    truth << std::setprecision(12) << "u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world\n";
    for (int v = 0; v < EvalCamera().height(); ++v) {
      for (int k = 0; k < planes; ++k) {
        const Eigen::Vector3d p = SurfacePoint(TrueU(k, v), v);
        truth << TrueU(k, v) << "," << v << "," << k << "," << p.x() << "," << p.y() << "," << p.z() << ",,,\n";
      }
    }
    truth.close();
    // Buffers in an order other than the renderer's: channels are found by name.
    Image<float> gt(EvalCamera().width(), EvalCamera().height(), 5, 0.0f);
    for (int y = 0; y < gt.height; ++y) {
      for (int x = 0; x < kEdge; ++x) {
        const Eigen::Vector3d s = SurfacePoint(x, y);
        gt.At(x, y, 0) = float(kSurface.n.x());
        gt.At(x, y, 1) = float(kSurface.n.y());
        gt.At(x, y, 2) = float(kSurface.n.z());
        gt.At(x, y, 3) = 2;
        gt.At(x, y, 4) = float(s.z());
      }
    }
    if (with_buffers) WriteImage(dir / "gt/000000.exr", gt, true, {"N.X", "N.Y", "N.Z", "instance", "Z"});
    nlohmann::json line = {{"index", 0},
                           {"shutter", {{"laser_on", true}}},
                           {"files", {{"image", "frames/000000.png"}, {"centers", "gt/000000_centers.csv"}}},
                           {"gt_axis", "rows"}};
    if (with_buffers) line["files"]["gt"] = "gt/000000.exr";
    if (world_from_cam) line["world_from_cam"] = PoseToJson(*world_from_cam);
    nlohmann::json bright = {{"index", 1}, {"shutter", {{"laser_on", false}}}, {"files", {{"image", "frames/000001.png"}}}};
    std::ofstream(dir / "manifest.jsonl") << line.dump() << "\n" << bright.dump() << "\n";
    if (!scanned) return;
    fs::create_directories(dir / "centers");
    std::vector<ScanPoint> points;
    for (const Measured& m : measured) {
      ScanPoint p;
      p.pixel = {m.u, m.v, 2.0, 500.0, m.plane};
      if (m.triangulate) p.p_in_cam = SurfacePoint(m.u, m.v) + m.off_surface_m * kSurface.n;
      if (m.triangulate && scan_world_from_cam) p.p_in_world = *scan_world_from_cam * *p.p_in_cam;
      points.push_back(p);
    }
    WriteScanCsv(dir / "centers/000000.csv", points);
  }
};

// gt/NNNNNN_centers.csv as the renderer writes it (CRLF and blanks around
// fields tolerated); a field that is no finite number names file:line.
TEST(TruthCentersCsv, ReadsTheRendererHeaderAndNamesBadLines) {
  const fs::path dir = fs::temp_directory_path() / ("lt_truth_csv_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string head = "u,v,plane,x_cam,y_cam,z_cam,x_world,y_world,z_world\r\n";
  std::ofstream(dir / "good.csv") << head << "12.000000,3.25,1,0.001,-0.002,0.08,1,2,3\r\n\r\n 13, 4.5 ,0,0,0,0.1,0,0,0\n";
  const std::vector<TruthCenter> c = ReadTruthCentersCsv(dir / "good.csv");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].plane, 1);
  EXPECT_EQ(c[1].v, 4.5);
  EXPECT_EQ(c[1].line, 4);
  auto error = [&](const std::string& row) {
    std::ofstream(dir / "bad.csv") << head << row << "\n";
    try {
      ReadTruthCentersCsv(dir / "bad.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_THAT(error("12,nan,0,0,0,0.1,0,0,0"), HasSubstr("bad.csv:2: field 2 is not a finite number: 'nan'"));
  EXPECT_THAT(error("12,3,0,0,0,1e999,0,0,0"), HasSubstr("bad.csv:2: field 6 is not a finite number"));
  EXPECT_THAT(error("12,3,0.5,0,0,0.1,0,0,0"), HasSubstr("bad.csv:2: plane must be an integer >= 0, got '0.5'"));
  EXPECT_THAT(error("12,3,0,0,0,0.1"), HasSubstr("bad.csv:2: expected 9 fields, got 6"));
  fs::remove_all(dir);
}

TEST(Summarize, KnownValues) {
  ErrorStats s = Summarize({3, -4, 1, 0, 2});
  EXPECT_EQ(s.n, 5);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(30.0 / 5));
  EXPECT_DOUBLE_EQ(s.median, 2);
  EXPECT_DOUBLE_EQ(s.p95, 3.8);  // sorted |x| = 0 1 2 3 4; position 0.95 * 4 = 3.8
  EXPECT_DOUBLE_EQ(s.max, 4);
  ErrorStats e = Summarize({});
  EXPECT_EQ(e.n, 0);
  EXPECT_TRUE(e.ToJson()["rms"].is_null());
  EXPECT_THROW(Summarize({1, std::nan("")}), std::invalid_argument);
}

TEST(EvalOptions, Check) {
  EvalOptions o;
  EXPECT_NO_THROW(o.Check());
  o.max_match_px = 0;
  EXPECT_THAT([&] { o.Check(); }, ::testing::ThrowsMessage<InputError>(HasSubstr("max_match_px")));
  o = {};
  o.completeness_mm = std::nan("");
  EXPECT_THAT([&] { o.Check(); }, ::testing::ThrowsMessage<InputError>(HasSubstr("completeness_mm")));
  o = {};
  o.frames_begin = 3;
  o.frames_end = 3;
  EXPECT_THROW(o.Check(), InputError);
}

TEST(EvaluateRun, KnownOffsetAndDisplacement) {
  EvalRun run = EvalRun::Exact("offset", 1, 0.3);
  for (Measured& m : run.measured) m.off_surface_m = 50e-6;  // 0.05 mm along the normal
  run.Write();
  EvalOptions o;
  RunMetrics m = EvaluateRun(run.dir, o);
  ASSERT_EQ(m.frames.size(), 1u);  // the bright frame is not evaluated
  const EvalSummary& t = m.total;
  EXPECT_EQ(t.counts.gt_centers, 60);
  EXPECT_EQ(t.counts.matched, 60);
  // The CSVs hold 5-6 decimals: the offset is exact to 1e-5 px.
  EXPECT_NEAR(t.center_px.rms, 0.3, 1e-5);
  EXPECT_NEAR(t.center_px.max, 0.3, 1e-5);
  EXPECT_NEAR(t.center_bias_px, 0.3, 1e-5);
  EXPECT_DOUBLE_EQ(*t.detection_rate, 1.0);
  EXPECT_EQ(t.counts.false_positives, 0);
  EXPECT_DOUBLE_EQ(*t.plane_id_accuracy, 1.0);
  // Planar surface: the tangent-plane distance is exact; the buffers are float
  // (Z to ~1e-8 m) and the CSV points have 10 digits, so 1e-4 mm is ample.
  EXPECT_EQ(t.point_mm.n, 60);
  EXPECT_NEAR(t.point_mm.median, 0.05, 1e-4);
  EXPECT_NEAR(t.point_mm.max, 0.05, 1e-4);
  // 0.3 px is about 0.3 mm on the surface here: not within 0.1 mm of the true point...
  const double dist_mm = (SurfacePoint(TrueU(0, 0) + 0.3, 0) - SurfacePoint(TrueU(0, 0), 0)).norm() * 1e3;
  ASSERT_GT(dist_mm, 0.2);
  EXPECT_DOUBLE_EQ(*t.completeness, 0.0);
  // ...but within 1 mm.
  o.completeness_mm = 1.0;
  EXPECT_DOUBLE_EQ(*EvaluateRun(run.dir, o).total.completeness, 1.0);
}

TEST(EvaluateRun, DroppedRowsExtraCentresAndDistantMatches) {
  EvalRun run = EvalRun::Exact("dropped", 1, -0.2);
  std::vector<Measured> kept;
  for (const Measured& m : run.measured) {
    if (int(m.v) % 4 == 1) continue;  // 15 of 60 rows not found
    kept.push_back(m);
  }
  kept.push_back({0, TrueU(0, 2) + 10, 2});  // a reflection 10 px away on row 2
  kept.push_back({0, TrueU(0, 5) + 4, 5});   // row 5 is dropped: 4 px from the truth, beyond max_match_px
  run.measured = kept;
  run.Write();
  RunMetrics m = EvaluateRun(run.dir, {});
  const EvalSummary& t = m.total;
  EXPECT_EQ(t.counts.matched, 45);
  EXPECT_DOUBLE_EQ(*t.detection_rate, 45.0 / 60);
  EXPECT_EQ(t.counts.false_positives, 2);
  EXPECT_DOUBLE_EQ(*t.false_positive_rate, 2.0 / 47);
  EXPECT_NEAR(t.center_px.rms, 0.2, 1e-5);
  EXPECT_NEAR(t.center_bias_px, -0.2, 1e-5);
  // With a 5 px window the 4 px one matches.
  EvalOptions wide;
  wide.max_match_px = 5;
  EXPECT_EQ(EvaluateRun(run.dir, wide).total.counts.matched, 46);
}

TEST(EvaluateRun, PlaneIdentificationAndGreedyMatching) {
  EvalRun run = EvalRun::Exact("planes", 2, 0.1);
  int swapped = 0, unidentified = 0;
  for (Measured& m : run.measured) {
    const int v = int(m.v);
    if (v < 10) {
      m.plane = 1 - m.plane;  // both stripes of rows 0..9 swapped: 20 wrong pairs
      ++swapped;
    } else if (v < 15 && m.plane == 0) {
      m.plane = -1;  // 5 not identified (no 3D point)
      m.triangulate = false;
      ++unidentified;
    }
  }
  ASSERT_EQ(swapped, 20);
  // Two measured centres near one true centre on row 30: the closer one pairs.
  run.measured.push_back({0, TrueU(0, 30) + 0.05, 30});
  run.Write();
  RunMetrics m = EvaluateRun(run.dir, {});
  const EvalSummary& t = m.total;
  EXPECT_EQ(t.counts.gt_centers, 120);
  EXPECT_EQ(t.counts.matched, 120);
  EXPECT_EQ(t.counts.false_positives, 1);
  EXPECT_EQ(t.counts.plane_unidentified, 5);
  EXPECT_DOUBLE_EQ(*t.plane_id_accuracy, (120.0 - 20 - 5) / 120);
  // 119 pairs at 0.1 px, one at 0.05 px.
  EXPECT_NEAR(t.center_px.max, 0.1, 1e-5);
  EXPECT_NEAR(t.center_px.rms, std::sqrt((119 * 0.01 + 0.0025) / 120), 1e-5);
  // Per true plane: plane 0 has 10 swapped and 5 unidentified, plane 1 10 swapped.
  ASSERT_EQ(m.planes.size(), 2u);
  EXPECT_EQ(m.planes.at(0).counts.gt_centers, 60);
  EXPECT_DOUBLE_EQ(*m.planes.at(0).plane_id_accuracy, 45.0 / 60);
  EXPECT_DOUBLE_EQ(*m.planes.at(1).plane_id_accuracy, 50.0 / 60);
  EXPECT_EQ(m.planes.at(0).counts.false_positives, 1);  // the extra centre says plane 0
  EXPECT_EQ(t.counts.points_triangulated, 121 - 5);
}

TEST(EvaluateRun, PointsOffTheSurfaceAndWithoutBuffers) {
  EvalRun run = EvalRun::Exact("off", 1, 0);
  run.measured.push_back({0, 75.0, 3});  // over the background (u >= kEdge)
  run.Write();
  RunMetrics m = EvaluateRun(run.dir, {});
  EXPECT_EQ(m.total.counts.points_triangulated, 61);
  EXPECT_EQ(m.total.counts.points_off_surface, 1);
  EXPECT_EQ(m.total.point_mm.n, 60);
  EXPECT_LT(m.total.point_mm.max, 1e-4);
  EXPECT_DOUBLE_EQ(*m.total.completeness, 1.0);
  // Without ground-truth buffers there is no point error, and it is said so.
  run.Write(true, false);
  RunMetrics n = EvaluateRun(run.dir, {});
  EXPECT_EQ(n.total.point_mm.n, 0);
  EXPECT_FALSE(n.frames[0].has_surface);
  nlohmann::json j = n.ToJson();
  EXPECT_TRUE(j["point_error_mm"]["rms"].is_null());
  EXPECT_FALSE(j["frames"][0]["point_error_available"].get<bool>());
}

TEST(EvaluateRun, MetricsJsonIsFiniteAndComplete) {
  EvalRun run = EvalRun::Exact("json", 2, 0.25);
  run.Write();
  RunMetrics m = EvaluateRun(run.dir, {});
  const fs::path path = WriteMetricsJson(run.dir, m);
  std::ifstream in(path);
  nlohmann::json j = nlohmann::json::parse(in);  // would throw on NaN / Infinity
  EXPECT_NEAR(j["stripe_center_error_px"]["rms"].get<double>(), 0.25, 1e-5);
  EXPECT_EQ(j["frames_evaluated"].get<int>(), 1);
  ASSERT_EQ(j["frames"].size(), 1u);
  EXPECT_EQ(j["frames"][0]["planes"].size(), 2u);
  EXPECT_EQ(j["planes"][1]["plane"].get<int>(), 1);
  EXPECT_DOUBLE_EQ(j["detection_rate"].get<double>(), 1.0);
  EXPECT_EQ(j["axis"], "rows");
}

TEST(EvaluateRun, BadInput) {
  EvalRun run = EvalRun::Exact("bad", 1, 0);
  run.Write(false);
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("run `lasertwin scan")));
  EXPECT_THAT([&] { EvaluateRun(run.dir / "nowhere", {}); }, ::testing::Throws<InputError>());
  // Measured along columns (fractional rows) while the truth scans rows.
  run.measured = {{0, 40, 10.5}};
  run.Write();
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); }, ::testing::ThrowsMessage<InputError>(HasSubstr("--axis rows")));
  // A measured file is missing.
  run.Write();
  fs::remove(run.dir / "centers/000000.csv");
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("centers/000000.csv: no such file")));
  // A broken ground-truth line names file:line.
  run.Write();
  std::ofstream(run.dir / "gt/000000_centers.csv", std::ios::app) << "1,2,x,0,0,0,,,\n";
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("000000_centers.csv:62: field 3")));
  // Buffers without a Z channel.
  run.Write();
  WriteImage(run.dir / "gt/000000.exr", Image<float>(80, 60, 1), true, {"Y"});
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); }, ::testing::ThrowsMessage<InputError>(HasSubstr("no channel 'Z'")));
  // No frame in range.
  run.Write();
  EvalOptions o;
  o.frames_begin = 1;
  EXPECT_THAT([&] { EvaluateRun(run.dir, o); }, ::testing::ThrowsMessage<InputError>(HasSubstr("no laser frame")));
}

// Centres that cannot be this run's (outside its camera's image, on a plane its
// rig does not have: a file from another run) are refused, naming the file and
// the line or centre, instead of being scored.
TEST(EvaluateRun, CentresThatDoNotFitTheRigAreRefused) {
  EvalRun run = EvalRun::Exact("rigfit", 2, 0);
  run.Write();
  ASSERT_NO_THROW(EvaluateRun(run.dir, {}));
  // Ground truth: line 62 is the first after the 60 rows x 2 planes written (header on line 1).
  auto truth_line = [&](const std::string& l) {
    run.Write();
    std::ofstream(run.dir / "gt/000000_centers.csv", std::ios::app) << l << "\n";
  };
  truth_line("40.5,3,2,0,0,0.1,,,");  // plane 2 of a 2-plane rig
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("000000_centers.csv:122: plane 2 is not one of rig.json's laser planes (0..1)")));
  truth_line("40.5,99999,0,0,0,0.1,,,");  // row 99999 of a 60-row image
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("000000_centers.csv:122: the centre at (40.5, 99999) lies outside the 80x60 image")));
  truth_line("-0.75,3,0,0,0,0.1,,,");
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("000000_centers.csv:122: the centre at (-0.75, 3) lies outside")));
  // Measured: the 121st centre.
  run.measured.push_back({5, 40.5, 3});
  run.Write();
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("centers/000000.csv: centre 121: plane 5 is not one of rig.json's laser planes (0..1, or -1 for none)")));
  run.measured.back() = {-1, 80.25, 3};
  run.Write();
  EXPECT_THAT([&] { EvaluateRun(run.dir, {}); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("centers/000000.csv: centre 121: at (80.25, 3) lies outside the 80x60 image")));
  // The image's edges are its pixels' outer edges, and -1 is "no plane": accepted.
  run.measured.back() = {-1, 79.5, 3};
  run.Write();
  EXPECT_NO_THROW(EvaluateRun(run.dir, {}));
}

// On a curved surface a pixel's tangent plane puts a point of the surface
// |P - S|^2 / (2 R) away from it; the mean of the two normals does not. A sphere
// of radius 10 mm, 0.1 m in front of the camera (1 mm pixels, longer on the
// surface where it is steep), seen at up to 45 degrees: points exactly on it
// score below 0.5 um, and points 0.1 mm off it along its normal 0.1 mm within 2 um.
TEST(TrueSurface, OnACurvedSurfaceItsOwnPointsScoreZero) {
  const fs::path dir = fs::temp_directory_path() / ("lt_eval_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Eigen::Vector3d center(0.002, -0.001, 0.1);
  const double radius = 0.01;
  auto hit = [&](const Eigen::Vector3d& ray) -> std::optional<Eigen::Vector3d> {  // unit ray from the origin
    const double b = ray.dot(center), c = center.squaredNorm() - radius * radius, disc = b * b - c;
    if (disc < 0) return std::nullopt;
    return (b - std::sqrt(disc)) * ray;
  };
  Image<float> gt(80, 60, 5, 0.0f);
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 80; ++x) {
      gt.At(x, y, 4) = -1;
      const auto p = hit(EvalCamera().Unproject({double(x), double(y)})->normalized());
      if (!p) continue;
      const Eigen::Vector3d n = (*p - center).normalized();
      gt.At(x, y, 0) = float(p->z());
      for (int k = 0; k < 3; ++k) gt.At(x, y, 1 + k) = float(n[k]);
      gt.At(x, y, 4) = 0;
    }
  }
  WriteImage(dir / "sphere.exr", gt, true, {"Z", "N.X", "N.Y", "N.Z", "instance"});
  TrueSurface s(EvalCamera(), dir / "sphere.exr");
  double worst = 0, worst_off = 0;
  int scored = 0;
  for (double v = 20.3; v < 40; v += 0.71) {
    for (double u = 30.1; u < 52; u += 0.53) {
      const Eigen::Vector3d ray = EvalCamera().Unproject({u, v})->normalized();
      const auto p = hit(ray);
      if (!p) continue;
      const Eigen::Vector3d n = (*p - center).normalized();
      if (n.dot(-ray) < 0.7) continue;  // nearer the limb the pixels around are not one surface (normals > 30 degrees apart)
      const auto d = s.SignedDistance(*p);
      const auto d_off = s.SignedDistance(*p + 1e-4 * n);
      ASSERT_TRUE(d && d_off);
      worst = std::max(worst, std::abs(*d));
      worst_off = std::max(worst_off, std::abs(*d_off - 1e-4));
      ++scored;
    }
  }
  ASSERT_GT(scored, 300);
  // Measured: 0.05 um and 0.97 um; with the tangent planes alone 30 um and 32 um.
  EXPECT_LT(worst, 0.5e-6);
  // 2% of the offset: P's normal is the 4 pixels' blend (off by the second
  // order of the normals' turn per pixel, up to 10 degrees here), and a point
  // off the surface projects onto another surface point than its foot.
  EXPECT_LT(worst_off, 2e-6);
}

TEST(TrueSurface, AtAStepTheNearestSurfaceAroundCounts) {
  // Two fronto-parallel surfaces: z = 0.1 m left of column 40, 0.101 m from it on.
  const fs::path dir = fs::temp_directory_path() / ("lt_eval_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  Image<float> gt(80, 60, 4, 0.0f);
  for (int y = 0; y < 60; ++y) {
    for (int x = 0; x < 80; ++x) {
      gt.At(x, y, 0) = x < 40 ? 0.1f : 0.101f;
      gt.At(x, y, 3) = -1;
    }
  }
  WriteImage(dir / "step.exr", gt, true, {"Z", "N.X", "N.Y", "N.Z"});
  TrueSurface s(EvalCamera(), dir / "step.exr");
  // A point on the near surface projecting at u = 39.4, next to the step: the
  // nearest pixel (39) is on its surface, so the error is 0, not a blend with 1 mm.
  const Eigen::Vector3d r = *EvalCamera().Unproject({39.4, 20});
  EXPECT_NEAR(*s.SignedDistance(r * (0.1 / r.z())), 0.0, 1e-7);
  // Away from the step the blend is exact as well; the distance is signed (towards the camera: +).
  const Eigen::Vector3d q = *EvalCamera().Unproject({60.3, 20.7});
  EXPECT_NEAR(*s.SignedDistance(q * (0.1005 / q.z())), 0.0005, 1e-7);
  EXPECT_FALSE(s.SignedDistance({0, 0, -1}).has_value());
  // A point on the far surface projecting at u = 39.4, where pixel 39's centre
  // sees the near one: a stripe there lights the part of pixel 39 beyond the
  // step. Its distance to the nearest surface within the pixels around is 0
  // (the nearest pixel's plane alone said 1 mm).
  EXPECT_NEAR(*s.SignedDistance(r * (0.101 / r.z())), 0.0, 1e-7);
  // The same at u = 38.8, where the 4 pixels around the projection (38, 39) all
  // see the near surface but the nearest pixel (39) reaches the step.
  const Eigen::Vector3d l = *EvalCamera().Unproject({38.8, 20});
  EXPECT_NEAR(*s.SignedDistance(l * (0.101 / l.z())), 0.0, 1e-7);
  // Between the two, 0.4 mm behind the near surface and 0.6 mm before the far
  // one: the nearer of the two, signed.
  EXPECT_NEAR(*s.SignedDistance(r * (0.1004 / r.z())), -0.0004, 1e-7);
  // Away from the step only one surface is near: a point 1 mm beyond it is 1 mm off.
  const Eigen::Vector3d a = *EvalCamera().Unproject({20.4, 20});
  EXPECT_NEAR(*s.SignedDistance(a * (0.101 / a.z())), -0.001, 1e-7);

  // A face between the pixel centres that no pixel sees (a slot wall seen
  // edge-on): its exact stripe centre at u = 39.7, z = 0.1005, between the two
  // surfaces the pixels see. Measured exactly, it is 0.5 mm from both their
  // tangent planes, and 0 from the exact point.
  const Eigen::Vector3d w = *EvalCamera().Unproject({39.7, 20});
  const Eigen::Vector3d wall = w * (0.1005 / w.z());
  EXPECT_NEAR(std::abs(*s.SignedDistance(wall)), 0.0005, 1e-7);
  const std::vector<Eigen::Vector3d> exact = {wall, SurfacePoint(10, 20)};
  EXPECT_NEAR(*s.SignedDistance(wall, exact), 0.0, 1e-12);
  // 0.2 mm nearer the camera along the ray: 0.2 mm from the exact point (the
  // tangent planes are 0.3 and 0.7 mm away), positive.
  const Eigen::Vector3d nearer = w * (0.1003 / w.z());
  EXPECT_NEAR(*s.SignedDistance(nearer, exact), (wall - nearer).norm(), 1e-12);
  EXPECT_GT(*s.SignedDistance(nearer, exact), 0.0);
  // On one smooth surface the exact points change nothing (the blend stands).
  EXPECT_NEAR(*s.SignedDistance(q * (0.1005 / q.z()), {&wall, 1}), 0.0005, 1e-7);
}

TEST(EvaluateRun, AFaceNoPixelSeesIsScoredByItsExactCentres) {
  // The stripe's surface lies between the pixels' surfaces: left of u = 40.5
  // the buffers see a plane 1 mm nearer the camera, right of it 1 mm farther,
  // as where a slot wall narrower than a pixel joins a top and a floor. Rows 0
  // to 10 hold the stripe within a pixel of the break (u = 40.3 to 41.3),
  // measured exactly: each point is 1 mm from both tangent planes and 0 from
  // its exact centre.
  EvalRun run = EvalRun::Exact("subpixel_face", 1, 0.0);
  std::vector<Measured> kept;
  for (const Measured& m : run.measured)
    if (m.v <= 10) kept.push_back(m);
  run.measured = kept;
  run.Write();
  auto on_plane = [](const Plane& plane, double u, double v) {
    const Eigen::Vector3d r = *EvalCamera().Unproject({u, v});
    return Eigen::Vector3d((-plane.d / plane.n.dot(r)) * r);
  };
  const Plane nearer = Plane::FromPointNormal(Eigen::Vector3d(0, 0, 0.1) + 1e-3 * kSurface.n, kSurface.n);
  const Plane farther = Plane::FromPointNormal(Eigen::Vector3d(0, 0, 0.1) - 1e-3 * kSurface.n, kSurface.n);
  Image<float> gt(EvalCamera().width(), EvalCamera().height(), 5, 0.0f);
  for (int y = 0; y < gt.height; ++y)
    for (int x = 0; x < kEdge; ++x) {
      gt.At(x, y, 0) = float(kSurface.n.x());
      gt.At(x, y, 1) = float(kSurface.n.y());
      gt.At(x, y, 2) = float(kSurface.n.z());
      gt.At(x, y, 3) = 2;
      gt.At(x, y, 4) = float(on_plane(x <= 40 ? nearer : farther, x, y).z());
    }
  WriteImage(run.dir / "gt/000000.exr", gt, true, {"N.X", "N.Y", "N.Z", "instance", "Z"});
  const EvalSummary t = EvaluateRun(run.dir, {}).total;
  EXPECT_EQ(t.point_mm.n, 11);
  EXPECT_LT(t.point_mm.max, 1e-4);  // the tangent planes alone: 1 mm
}

TEST(EvaluateRun, ASurfaceDistanceSourceScoresEveryPointOfItsFrames) {
  // Points 0.05 mm off the plane, and one over the background (u >= kEdge:
  // no pixel sees a surface there), 2 mm off the plane's continuation.
  EvalRun run = EvalRun::Exact("scene_distance", 1, 0);
  for (Measured& m : run.measured) m.off_surface_m = 50e-6;
  run.measured.push_back({0, 75.0, 3, 2e-3});
  run.Write(true, false);  // no buffers: the source alone scores the points
  std::vector<int> asked;
  const SurfaceDistanceSource plane_distance = [&asked](const RunFrame& f) -> PointToSurface {
    asked.push_back(f.index);
    return [](const Eigen::Vector3d& p) { return std::optional<double>(std::abs(kSurface.SignedDistance(p))); };
  };
  RunMetrics m = EvaluateRun(run.dir, {}, plane_distance);
  EXPECT_EQ(asked, std::vector<int>{0});  // the laser frame only
  EXPECT_EQ(m.PointErrorMethod(), "scene");
  EXPECT_TRUE(m.frames[0].has_surface && m.frames[0].surface_from_scene);
  EXPECT_EQ(m.total.counts.points_off_surface, 0);
  EXPECT_EQ(m.total.point_mm.n, 61);
  // The CSV holds 10 digits of metres (1e-11 m): the distances are exact to 1e-7 mm.
  EXPECT_NEAR(m.total.point_mm.median, 0.05, 1e-7);
  EXPECT_NEAR(m.total.point_mm.max, 2.0, 1e-7);
  EXPECT_EQ(m.ToJson()["point_error_method"], "scene");
  EXPECT_EQ(m.ToJson()["frames"][0]["point_error_method"], "scene");

  // No surface at all: off the surface. A source that gives no function for a
  // frame leaves it to the buffers (here: none, so no point error).
  m = EvaluateRun(run.dir, {}, [](const RunFrame&) -> PointToSurface {
    return [](const Eigen::Vector3d&) { return std::optional<double>(); };
  });
  EXPECT_EQ(m.total.counts.points_off_surface, 61);
  EXPECT_EQ(m.total.point_mm.n, 0);
  m = EvaluateRun(run.dir, {}, [](const RunFrame&) { return PointToSurface(); });
  EXPECT_EQ(m.PointErrorMethod(), "none");
  EXPECT_FALSE(m.frames[0].has_surface);
  run.Write(true, true);
  m = EvaluateRun(run.dir, {}, [](const RunFrame&) { return PointToSurface(); });
  EXPECT_EQ(m.PointErrorMethod(), "gt_buffers");
  EXPECT_EQ(m.total.counts.points_off_surface, 1);  // the background point
  EXPECT_NEAR(m.total.point_mm.max, 0.05, 1e-4);
}

// A run whose measured points lie 0.05 mm off kSurface, its camera at a
// general pose w (the manifest's world_from_cam), and the distance to kSurface.
struct StitchedRun {
  EvalRun run;
  Pose w = Pose::Identity();
  explicit StitchedRun(const std::string& name) : run(EvalRun::Exact(name, 1, 0)) {
    for (Measured& m : run.measured) m.off_surface_m = 50e-6;
    w.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    w.translation() = Eigen::Vector3d(0.2, -0.1, 0.3);
    run.world_from_cam = w;
  }
  static PointToSurface PlaneDistance(const RunFrame&) {
    return [](const Eigen::Vector3d& p) { return std::optional<double>(std::abs(kSurface.SignedDistance(p))); };
  }
  // The run scanned with its world points placed by a pose `offset_m` (in the
  // surface's frame, turned into the world by w) off the manifest's, and
  // evaluated against kSurface.
  RunMetrics EvaluateOffBy(const Eigen::Vector3d& offset_m) {
    Pose off = Pose::Identity();
    off.translation() = w.linear() * offset_m;
    run.scan_world_from_cam = off * w;
    run.Write(true, false);
    return EvaluateRun(run.dir, {}, &PlaneDistance);
  }
};

// The world points where scan placed them (the centres CSV's world columns) are
// scored too: placed with a pose 0.3 mm off the manifest's along the surface's
// normal (a hand-eye calibration's error, say), they lie 0.35 mm from the surface
// while the points in the camera frame lie 0.05 mm from it. Before, only the camera
// frame's points were scored (through the manifest's pose): a cloud stitched 0.5 mm
// off by a wrong tool_from_cam scored as a right one.
TEST(EvaluateRun, StitchedWorldPointsAreScoredWithThePoseTheScanUsed) {
  StitchedRun stitched("stitched");
  EvalRun& run = stitched.run;
  const Pose w = stitched.w;
  const auto plane_distance = &StitchedRun::PlaneDistance;
  // Placed with the manifest's pose: the same errors.
  RunMetrics m = stitched.EvaluateOffBy(Eigen::Vector3d::Zero());
  EXPECT_EQ(m.total.stitched_point_mm.n, 60);
  EXPECT_NEAR(m.total.stitched_point_mm.max, 0.05, 1e-6);
  // Placed 0.3 mm off along the surface's normal (in the world).
  m = stitched.EvaluateOffBy(0.3e-3 * kSurface.n);
  EXPECT_NEAR(m.total.point_mm.median, 0.05, 1e-6);
  EXPECT_EQ(m.total.stitched_point_mm.n, 60);
  EXPECT_NEAR(m.total.stitched_point_mm.median, 0.35, 1e-6);
  EXPECT_NEAR(m.ToJson()["stitched_point_error_mm"]["median"].get<double>(), 0.35, 1e-6);
  EXPECT_NEAR(m.ToJson()["frames"][0]["stitched_point_error_mm"]["max"].get<double>(), 0.35, 1e-6);
  // On the ground-truth buffers too.
  run.Write(true, true);
  m = EvaluateRun(run.dir, {});
  EXPECT_NEAR(m.total.point_mm.median, 0.05, 1e-4);
  EXPECT_NEAR(m.total.stitched_point_mm.median, 0.35, 1e-4);
  // No world points (a scan without poses), or no manifest pose: nothing to score.
  run.scan_world_from_cam.reset();
  run.Write(true, false);
  m = EvaluateRun(run.dir, {}, plane_distance);
  EXPECT_EQ(m.total.stitched_point_mm.n, 0);
  EXPECT_FALSE(m.ToJson().contains("stitched_point_error_mm"));
  run.scan_world_from_cam = w;
  run.world_from_cam.reset();
  run.Write(true, false);
  EXPECT_EQ(EvaluateRun(run.dir, {}, plane_distance).total.stitched_point_mm.n, 0);
}

// A pose error along a flat surface leaves every stitched point on it, so the
// distance to the surface cannot see it; the stitch pose offset (each world
// point against where the manifest's pose puts the same camera-frame point) can.
TEST(EvaluateRun, StitchPoseOffsetSeesAPoseErrorAlongTheSurface) {
  StitchedRun stitched("pose_offset");
  EvalRun& run = stitched.run;
  const auto plane_distance = &StitchedRun::PlaneDistance;
  RunMetrics m = stitched.EvaluateOffBy(Eigen::Vector3d::Zero());
  EXPECT_EQ(m.total.pose_offset_mm.n, 60);
  EXPECT_LT(m.total.pose_offset_mm.max, 1e-6);
  // 0.4 mm off within the surface's plane.
  m = stitched.EvaluateOffBy(0.4e-3 * kSurface.n.unitOrthogonal());
  EXPECT_NEAR(m.total.stitched_point_mm.median, 0.05, 1e-6);  // blind to it
  EXPECT_EQ(m.total.pose_offset_mm.n, 60);
  EXPECT_NEAR(m.total.pose_offset_mm.median, 0.4, 1e-6);
  EXPECT_NEAR(m.total.pose_offset_mm.max, 0.4, 1e-6);
  EXPECT_NEAR(m.ToJson()["stitch_pose_offset_mm"]["median"].get<double>(), 0.4, 1e-6);
  // Without world points nothing is scored.
  run.scan_world_from_cam.reset();
  run.Write(true, false);
  m = EvaluateRun(run.dir, {}, plane_distance);
  EXPECT_EQ(m.total.pose_offset_mm.n, 0);
  EXPECT_FALSE(m.ToJson().contains("stitch_pose_offset_mm"));
}

}  // namespace
}  // namespace lt
