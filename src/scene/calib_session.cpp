#include "scene/calib_session.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_reader.h"
#include "core/random.h"
#include "scene/gltf_writer.h"
#include "scene/sensor_binning.h"
#include "sensor/rig.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr uint64_t kSessionPurpose = 0x43414c4942534553ull;  // "CALIBSES"
constexpr int kMaxAttempts = 500;
// Image margins a view must keep (pixels): the detector needs about
// 2σ + 2 px around each corner (σ = 1.5 px) and the white margin in view.
constexpr double kCornerMarginPx = 12;
constexpr double kBoardMarginPx = 2;
constexpr double kMinSquarePx = 12;
// Each laser sheet must cross the squares over at least this fraction of the
// squares' shorter side, at least this angle to the board.
constexpr double kMinStripeFraction = 0.5;
constexpr double kMinSheetAngleDeg = 15;

// The squares' area and the whole board (with margin) in the board frame.
struct BoardExtent {
  double x0, y0, x1, y1;
};

BoardExtent Squares(const CalibSessionOptions& o) {
  return {-o.square_m, -o.square_m, o.cols * o.square_m, o.rows * o.square_m};
}

BoardExtent Whole(const CalibSessionOptions& o) {
  const double m = o.margin_squares * o.square_m;
  const BoardExtent s = Squares(o);
  return {s.x0 - m, s.y0 - m, s.x1 + m, s.y1 + m};
}

Eigen::Vector3d BoardCentre(const CalibSessionOptions& o) {
  return {0.5 * (o.cols - 1) * o.square_m, 0.5 * (o.rows - 1) * o.square_m, 0};
}

void AddQuad(double x0, double y0, double x1, double y1, std::vector<float>* pos, std::vector<float>* nrm,
             std::vector<uint32_t>* idx) {
  const uint32_t base = uint32_t(pos->size() / 3);
  for (auto [x, y] : {std::pair{x0, y0}, {x0, y1}, {x1, y1}, {x1, y0}}) {
    pos->insert(pos->end(), {float(x), float(y), 0.f});
    nrm->insert(nrm->end(), {0.f, 0.f, -1.f});  // the printed side faces −z
  }
  // Counter-clockwise seen from −z.
  idx->insert(idx->end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

void WriteBoardGltf(const CalibSessionOptions& o, const fs::path& path) {
  GltfBuilder b;
  const int black = b.AddMaterial("black", {0.04, 0.04, 0.04, 1}, 0.0, 0.9);
  const int white = b.AddMaterial("white", {0.8, 0.8, 0.8, 1}, 0.0, 0.9);
  std::vector<float> pb, nb, pw, nw;
  std::vector<uint32_t> ib, iw;
  const double s = o.square_m;
  for (int i = -1; i < o.rows; ++i) {
    for (int j = -1; j < o.cols; ++j) {
      const bool is_black = ((i + j) % 2 + 2) % 2 == 0;
      AddQuad(j * s, i * s, (j + 1) * s, (i + 1) * s, is_black ? &pb : &pw, is_black ? &nb : &nw,
              is_black ? &ib : &iw);
    }
  }
  const BoardExtent q = Squares(o), w = Whole(o);
  if (o.margin_squares > 0) {
    AddQuad(w.x0, w.y0, w.x1, q.y0, &pw, &nw, &iw);
    AddQuad(w.x0, q.y1, w.x1, w.y1, &pw, &nw, &iw);
    AddQuad(w.x0, q.y0, q.x0, q.y1, &pw, &nw, &iw);
    AddQuad(q.x1, q.y0, w.x1, q.y1, &pw, &nw, &iw);
  }
  b.AddNode("black_squares", b.AddTriangleMesh("black_squares", pb, nb, {}, ib, black));
  b.AddNode("white_squares", b.AddTriangleMesh("white_squares", pw, nw, {}, iw, white));
  b.WriteGltf(path, false);
}

std::string Num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// The rig's sensor section, binned (camera and image sensor), without a
// pattern projector, with the session's shutter cycle. `pixel` is the rig's
// image sensor as parsed (its defaults for keys the rig leaves out).
nlohmann::json SessionSensor(const nlohmann::json& rig_sensor, const ImageSensorParams& pixel,
                             const CalibSessionOptions& o) {
  nlohmann::json sensor = rig_sensor;
  sensor.erase("pattern_projector");
  BinSensorSection(sensor, pixel, o.binning);
  double bright_us = 2000, dim_us = 50, period_ms = 10;
  if (sensor.contains("shutter") && sensor["shutter"].is_object()) {
    const nlohmann::json& sh = sensor["shutter"];
    if (sh.contains("frame_period_ms") && sh["frame_period_ms"].is_number()) {
      period_ms = sh["frame_period_ms"].get<double>();
    }
    if (sh.contains("alternating") && sh["alternating"].is_object()) {
      const nlohmann::json& alt = sh["alternating"];
      if (alt.contains("bright_exposure_us") && alt["bright_exposure_us"].is_number()) {
        bright_us = alt["bright_exposure_us"].get<double>();
      }
      if (alt.contains("dim_exposure_us") && alt["dim_exposure_us"].is_number()) {
        dim_us = alt["dim_exposure_us"].get<double>();
      }
    }
  }
  sensor["shutter"] = {{"frame_period_ms", period_ms},
                       {"cycle",
                        {{{"label", "bright"}, {"exposure_us", bright_us}, {"led", true}},
                         {{"label", "dim"}, {"exposure_us", dim_us}, {"laser", true}}}}};
  return sensor;
}

// Whether the board is fully and usefully in view at cam_from_board.
bool ViewFits(const SensorRig& rig, const CalibSessionOptions& o, const Pose& cam_from_board) {
  const Camera& cam = rig.camera;
  auto inside = [&](const Eigen::Vector2d& px, double margin) {
    return px.x() >= margin && px.y() >= margin && px.x() <= cam.width() - 1 - margin &&
           px.y() <= cam.height() - 1 - margin;
  };
  const BoardExtent w = Whole(o);
  const int n = 8;  // samples along each edge of the board (distortion bends edges)
  for (int k = 0; k <= n; ++k) {
    const double a = double(k) / n;
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(w.x0 + a * (w.x1 - w.x0), w.y0, 0),
                                    Eigen::Vector3d(w.x0 + a * (w.x1 - w.x0), w.y1, 0),
                                    Eigen::Vector3d(w.x0, w.y0 + a * (w.y1 - w.y0), 0),
                                    Eigen::Vector3d(w.x1, w.y0 + a * (w.y1 - w.y0), 0)}) {
      const auto px = cam.Project(cam_from_board * p);
      if (!px || !inside(*px, kBoardMarginPx)) return false;
    }
  }
  const double s = o.square_m;
  for (int i = 0; i < o.rows; ++i) {
    for (int j = 0; j < o.cols; ++j) {
      const auto px = cam.Project(cam_from_board * Eigen::Vector3d(j * s, i * s, 0));
      if (!px || !inside(*px, kCornerMarginPx)) return false;
      for (const Eigen::Vector3d& q : {Eigen::Vector3d((j + 1) * s, i * s, 0), Eigen::Vector3d(j * s, (i + 1) * s, 0)}) {
        const auto qx = cam.Project(cam_from_board * q);
        if (!qx || (*qx - *px).norm() < kMinSquarePx) return false;
      }
    }
  }
  // Every laser sheet crosses the squares well away from grazing.
  const Plane board = Plane{Eigen::Vector3d::UnitZ(), 0.0}.Transformed(cam_from_board);
  const BoardExtent q = Squares(o);
  const double shorter = std::min(q.x1 - q.x0, q.y1 - q.y0);
  for (const LaserProjector& laser : rig.lasers) {
    for (int k = 0; k < laser.sheet_count(); ++k) {
      const Plane sheet = laser.SheetPlane(k);
      const Eigen::Vector3d dir = sheet.n.cross(board.n);
      if (std::asin(std::min(1.0, dir.norm())) < kMinSheetAngleDeg * kDeg) return false;
      // The line in the board frame: points p with board z = 0 on the sheet.
      Eigen::Matrix3d a;
      const Eigen::Vector3d u = dir.normalized();
      a << sheet.n.transpose(), board.n.transpose(), u.transpose();
      const Eigen::Vector3d x0 = a.inverse() * Eigen::Vector3d(-sheet.d, -board.d, 0);
      const Pose board_from_cam = cam_from_board.inverse();
      const double step = 0.02 * shorter;
      int on = 0;
      for (double t = -2 * (q.x1 - q.x0 + q.y1 - q.y0); t <= 2 * (q.x1 - q.x0 + q.y1 - q.y0); t += step) {
        const Eigen::Vector3d p_cam = x0 + t * u;
        const Eigen::Vector3d b = board_from_cam * p_cam;
        if (b.x() < q.x0 || b.x() > q.x1 || b.y() < q.y0 || b.y() > q.y1) continue;
        const auto px = cam.Project(p_cam);
        if (px && inside(*px, 0)) ++on;
      }
      if (on * step < kMinStripeFraction * shorter) return false;
    }
  }
  return true;
}

// The radical inverse of i in `base`: the Halton sequence's coordinate.
double RadicalInverse(int i, int base) {
  double inv = 1.0 / base, f = inv, r = 0;
  for (; i > 0; i /= base, f *= inv) r += f * (i % base);
  return r;
}

// The direction (camera frame, z = 1) the board's centre is placed along.
// View 0 looks at the image centre; the others aim at Halton points spread
// over the image, so that a session's corners reach the image's edges, where
// a wide lens's distortion is strongest and boards near the centre leave it
// unconstrained. An aim whose board does not fit moves toward the centre over
// the attempts (the centre from half of them on).
std::optional<Eigen::Vector3d> AimDirection(const Camera& cam, int view, int attempt) {
  const Eigen::Vector2d centre(0.5 * (cam.width() - 1), 0.5 * (cam.height() - 1));
  const double reach = view == 0 ? 0.0 : std::max(0.0, 1.0 - attempt / (0.5 * kMaxAttempts));
  const Eigen::Vector2d aim =
      centre + reach * Eigen::Vector2d((RadicalInverse(view, 2) - 0.5) * cam.width(),
                                       (RadicalInverse(view, 3) - 0.5) * cam.height());
  const auto ray = cam.Unproject(aim);
  if (!ray || !(ray->z() > 0)) return std::nullopt;
  return *ray / ray->z();
}

}  // namespace

Pose CalibSessionOptions::DefaultToolFromCam() {
  // A camera mounted 40 mm off the flange axis and 110 mm out, turned a quarter
  // turn about the flange axis and tilted 10°.
  Pose p = Pose::Identity();
  p.linear() = (Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(0.04, -0.015, 0.11);
  return p;
}

void CalibSessionOptions::Check() const {
  if (rows < 2 || cols < 2) throw InputError("option rows/cols", "the board needs at least 2 x 2 inner corners");
  if (!(square_m > 0) || !std::isfinite(square_m)) throw InputError("option square", "must be > 0");
  if (margin_squares < 1) throw InputError("option margin", "the detector needs a white margin of >= 1 square");
  if (views < 1 || views > 1000) throw InputError("option views", "must be in [1, 1000]");
  if (binning < 1 || binning > 8) throw InputError("option binning", "must be in [1, 8]");
  if (!(min_tilt_deg >= 0) || !(max_tilt_deg >= min_tilt_deg) || !(max_tilt_deg < 80)) {
    throw InputError("option tilt", "need 0 <= min <= max < 80 degrees");
  }
  if (!(min_distance_m > 0) || !(max_distance_m >= min_distance_m) || !std::isfinite(max_distance_m)) {
    throw InputError("option distance", "need 0 < min <= max");
  }
  if (spp < 1 || spp > 65536) throw InputError("option spp", "must be in [1, 65536]");
  if (rig_scene.empty()) throw InputError("option rig", "a rig scene file is required");
}

CalibSession WriteCalibSession(const CalibSessionOptions& o, const fs::path& out_dir) {
  o.Check();
  const json::Document rig_doc = json::Document::Load(o.rig_scene);
  const json::Object rig_root = rig_doc.Root().AsObject();
  const nlohmann::json& rig_raw = rig_doc.Root().raw();
  if (!rig_raw.contains("sensor")) throw InputError(o.rig_scene.string(), "has no \"sensor\" section");
  // Check the rig as given (errors name the rig file), then the session's version of it.
  const SensorRig rig_as_given = ParseSensorRig(rig_root.GetObject("sensor"));
  const nlohmann::json sensor_json = SessionSensor(rig_raw["sensor"], rig_as_given.image_sensor.params(), o);
  const std::string session_name = o.rig_scene.string() + " (sensor, as binned for the session)";
  const json::Document sensor_doc =
      json::Document::Parse(sensor_json.dump(), session_name, o.rig_scene.parent_path());
  const SensorRig rig = ParseSensorRig(sensor_doc.Root().AsObject());
  if (!rig.led) throw InputError(o.rig_scene.string() + ": /sensor", "the rig has no LED: bright frames need one");
  if (rig.lasers.empty()) throw InputError(o.rig_scene.string() + ": /sensor", "the rig has no laser");

  CalibSession session;
  session.frames = 2 * o.views;
  // World: the board printed side up (board z into the board = world −z), centred on the origin.
  session.world_from_board = Pose::Identity();
  session.world_from_board.linear() = Eigen::Vector3d(1, -1, -1).asDiagonal();
  session.world_from_board.translation() = -(session.world_from_board.linear() * BoardCentre(o));

  for (int v = 0; v < o.views; ++v) {
    bool found = false;
    for (int attempt = 0; attempt < kMaxAttempts && !found; ++attempt) {
      Rng rng = Rng::For(o.seed, uint64_t(v), uint64_t(attempt), 0, kSessionPurpose);
      const double tilt = (o.min_tilt_deg + (o.max_tilt_deg - o.min_tilt_deg) * rng.NextDouble()) * kDeg;
      const double axis = 2 * M_PI * rng.NextDouble();
      const double spin = 2 * M_PI * rng.NextDouble() - M_PI;
      const double dist = o.min_distance_m + (o.max_distance_m - o.min_distance_m) * rng.NextDouble();
      const auto aim = AimDirection(rig.camera, v, attempt);
      if (!aim) continue;
      Pose cam_from_board = Pose::Identity();
      cam_from_board.linear() = (Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0)) *
                                 Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()))
                                    .toRotationMatrix();
      cam_from_board.translation() = dist * *aim - cam_from_board.linear() * BoardCentre(o);
      if (!ViewFits(rig, o, cam_from_board)) continue;
      CalibSessionView view;
      view.cam_from_board = cam_from_board;
      view.world_from_cam = session.world_from_board * cam_from_board.inverse();
      view.tilt_deg = tilt / kDeg;
      view.distance_m = dist;
      session.views.push_back(view);
      found = true;
    }
    if (!found) {
      throw InputError("calibration session",
                       "view " + std::to_string(v) + ": no pose in " + std::to_string(kMaxAttempts) +
                           " tries keeps the whole board in the image, its squares >= " + Num(kMinSquarePx) +
                           " px and every laser stripe on the board; use a smaller board (--rows, --cols, "
                           "--square-mm) or other tilts and distances");
    }
  }

  // The pose list: each view's pose from the start of its bright frame to the end of its dim frame.
  std::ostringstream csv;
  csv << "t_s,x_m,y_m,z_m,qw,qx,qy,qz\n";
  double last_t = -1e300;
  for (int v = 0; v < o.views; ++v) {
    const ShutterFrame bright = rig.shutter.Frame(2 * v), dim = rig.shutter.Frame(2 * v + 1);
    const Pose world_from = o.arm ? Pose(session.views[size_t(v)].world_from_cam * o.tool_from_cam.inverse())
                                  : session.views[size_t(v)].world_from_cam;
    const Eigen::Quaterniond q(world_from.linear());
    const Eigen::Vector3d t = world_from.translation();
    for (double ts : {bright.t_start_s, dim.t_end_s}) {
      if (!(ts > last_t)) {
        throw InputError("calibration session", "the shutter's frames overlap (the bright and dim exposures must "
                                                "each fit in a frame period)");
      }
      last_t = ts;
      csv << Num(ts) << "," << Num(t.x()) << "," << Num(t.y()) << "," << Num(t.z()) << "," << Num(q.w()) << ","
          << Num(q.x()) << "," << Num(q.y()) << "," << Num(q.z()) << "\n";
    }
  }

  fs::create_directories(out_dir);
  WriteBoardGltf(o, out_dir / "checkerboard.gltf");
  const nlohmann::json board = {{"rows", o.rows},
                                {"cols", o.cols},
                                {"square_mm", o.square_m * 1e3},
                                {"margin_squares", o.margin_squares}};
  WriteFileAtomically(out_dir / "checkerboard.json", board.dump(2) + "\n");
  WriteFileAtomically(out_dir / "poses.csv", csv.str());

  nlohmann::json motion = {{"type", "pose_list"}, {"file", "poses.csv"}, {"format", "csv"}, {"time_origin", "file"}};
  if (o.arm) motion["tool_from_cam"] = PoseToJson(o.tool_from_cam);
  nlohmann::json scene = {
      {"description", "Calibration session: a " + std::to_string(o.rows) + " x " + std::to_string(o.cols) +
                          " inner-corner checkerboard of " + Num(o.square_m * 1e3) + " mm squares seen in " +
                          std::to_string(o.views) + " poses, each as a bright frame (LED) then a dim frame "
                          "(laser). Generated by lasertwin calib-session from " + o.rig_scene.string() + "."},
      {"seed", o.seed},
      {"objects", {{{"name", "checkerboard"},
                    {"gltf", "checkerboard.gltf"},
                    {"world_from_object", PoseToJson(session.world_from_board)}}}},
      {"sensor", sensor_json},
      {"motion", motion},
      {"render", {{"spp", o.spp}, {"max_bounces", 1}, {"frames", session.frames}}},
      {"output", {{"png_bit_depth", 16}, {"write_radiance", false}, {"write_ground_truth", true}}}};
  if (rig_raw.contains("environment") && rig_raw["environment"].is_object() &&
      rig_raw["environment"].contains("radiance")) {
    scene["environment"] = {{"radiance", rig_raw["environment"]["radiance"]}};
  }
  WriteFileAtomically(out_dir / "scene.json", scene.dump(2) + "\n");
  return session;
}

}  // namespace lt
