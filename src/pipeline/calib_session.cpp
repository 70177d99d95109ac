#include "pipeline/calib_session.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <type_traits>

#include "core/error.h"
#include "core/image_io.h"
#include "core/json_reader.h"
#include "pipeline/calib_board_turns.h"
#include "pipeline/calib_camera_images.h"
#include "pipeline/frame_extraction.h"
#include "pipeline/image_file_facts.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/stripe_extractor.h"
#include "pipeline/triangulation.h"

namespace lt {

namespace fs = std::filesystem;

namespace {

constexpr const char* kBoardObject = "checkerboard";

// The run's scene.json object named "checkerboard", if any.
std::optional<json::Object> BoardObject(const json::Document& scene) {
  const json::Object root = scene.Root().AsObject();
  auto objects = root.Find("objects");
  if (!objects) return std::nullopt;
  for (const json::Value& v : objects->Array()) {
    json::Object o = v.AsObject();
    if (o.String("name") == kBoardObject) return o;
  }
  return std::nullopt;
}

fs::path ScenePath(const fs::path& run_dir) {
  const fs::path p = run_dir / "scene.json";
  if (!fs::exists(p)) throw InputError(p.string(), "no such file (the run's scene)");
  return p;
}

// A frame's image, of the run camera's size, as scan reads it: an alpha
// channel left out, and (with declared_bits) the bits its file declares
// stored unscaled (DeclaredUnscaledBits; 0 when none).
AnyImage ReadFrameImage(const SessionRun& run, const RunFrame& frame, int* declared_bits = nullptr) {
  AnyImage image;
  try {
    ImageFileFacts facts;
    image = ReadImage(frame.image, AlphaChannel::kDrop, &facts);
    if (declared_bits) *declared_bits = DeclaredUnscaledBits(facts);
  } catch (const InputError& e) {
    throw InputError(e.where(), e.message() + " (frame " + std::to_string(frame.index) + ", " + frame.where + ")");
  }
  CheckFrameImageSize(image, frame, run.rig.camera, run.rig.source.string());
  return image;
}

}  // namespace

bool GroupStripesOnFlatTarget(std::vector<StripePoint>* points, const std::vector<StripeSegment>& segments, int n,
                              SearchAxis axis, double tol_px, std::string* error) {
  auto along = [&](int i) { return axis == SearchAxis::kCols ? (*points)[size_t(i)].u : (*points)[size_t(i)].v; };
  auto across = [&](int i) { return axis == SearchAxis::kCols ? (*points)[size_t(i)].v : (*points)[size_t(i)].u; };
  std::vector<const StripeSegment*> pieces;
  for (const StripeSegment& seg : segments) {
    if (!seg.ignored) pieces.push_back(&seg);
  }
  // Pooled slope: within-piece covariance over within-piece variance.
  double sxy = 0, sxx = 0;
  for (const StripeSegment* seg : pieces) {
    double mx = 0, my = 0;
    for (int i : seg->points) mx += along(i), my += across(i);
    mx /= double(seg->points.size()), my /= double(seg->points.size());
    for (int i : seg->points) sxy += (along(i) - mx) * (across(i) - my), sxx += (along(i) - mx) * (along(i) - mx);
  }
  const double slope = sxx > 0 ? sxy / sxx : 0.0;
  std::vector<std::pair<double, const StripeSegment*>> by_intercept;
  for (const StripeSegment* seg : pieces) {
    double c = 0;
    for (int i : seg->points) c += across(i) - slope * along(i);
    by_intercept.emplace_back(c / double(seg->points.size()), seg);
  }
  std::sort(by_intercept.begin(), by_intercept.end(),
            [](const auto& x, const auto& y) { return x.first < y.first; });
  struct Line {
    std::vector<int> points;
    double a = 0, b = 0;  // across = a + b·along
  };
  std::vector<Line> lines;
  for (size_t k = 0; k < by_intercept.size(); ++k) {
    if (k == 0 || by_intercept[k].first - by_intercept[k - 1].first > 4 * tol_px) lines.emplace_back();
    const auto& pts = by_intercept[k].second->points;
    lines.back().points.insert(lines.back().points.end(), pts.begin(), pts.end());
  }
  for (Line& l : lines) {
    double s1 = 0, sx = 0, sy = 0, sxx2 = 0, sxy2 = 0;
    for (int i : l.points) s1 += 1, sx += along(i), sy += across(i), sxx2 += along(i) * along(i), sxy2 += along(i) * across(i);
    const double det = s1 * sxx2 - sx * sx;
    l.b = det > 1e-9 * s1 * s1 ? (s1 * sxy2 - sx * sy) / det : slope;
    l.a = (sy - l.b * sx) / s1;
    l.points.clear();
  }
  for (const StripeSegment* seg : pieces) {
    int best = -1;
    double best_d = tol_px;
    for (size_t k = 0; k < lines.size(); ++k) {
      double d = 0;
      for (int i : seg->points) d += std::abs(across(i) - (lines[k].a + lines[k].b * along(i)));
      d /= double(seg->points.size());
      if (d < best_d) best_d = d, best = int(k);
    }
    if (best >= 0) lines[size_t(best)].points.insert(lines[size_t(best)].points.end(), seg->points.begin(), seg->points.end());
  }
  // Lines with less than a fifth of the longest line's points are stray light.
  size_t longest = 0;
  for (const Line& l : lines) longest = std::max(longest, l.points.size());
  lines.erase(std::remove_if(lines.begin(), lines.end(),
                             [longest](const Line& l) { return l.points.empty() || 5 * l.points.size() < longest; }),
              lines.end());
  if (int(lines.size()) != n) {
    *error = "found " + std::to_string(lines.size()) + " stripe line(s) on the board, expected " + std::to_string(n);
    return false;
  }
  double mid = 0;
  int count = 0;
  for (const Line& l : lines) {
    for (int i : l.points) mid += along(i), ++count;
  }
  mid /= std::max(1, count);
  std::sort(lines.begin(), lines.end(), [mid](const Line& x, const Line& y) { return x.a + x.b * mid < y.a + y.b * mid; });
  for (auto& p : *points) p.plane = -1;
  for (size_t k = 0; k < lines.size(); ++k) {
    for (int i : lines[k].points) (*points)[size_t(i)].plane = int(k);
  }
  return true;
}

CheckerboardSpec ReadCheckerboardFile(const fs::path& path) {
  const json::Document doc = json::Document::Load(path);
  json::Object o = doc.Root().AsObject();
  CheckerboardSpec b;
  b.rows = int(o.Integer("rows", json::Range::AtLeast(2)));
  b.cols = int(o.Integer("cols", json::Range::AtLeast(2)));
  b.square_m = o.Number("square_mm", json::Range::Positive()) * 1e-3;
  b.margin_squares = int(o.Integer("margin_squares", 1, json::Range::AtLeast(0)));
  o.Finish();
  try {
    b.Check();
  } catch (const InputError& e) {
    throw InputError(path.string(), e.message());
  }
  return b;
}

fs::path FindSessionBoardFile(const fs::path& run_dir) {
  const fs::path scene_path = ScenePath(run_dir);
  const json::Document scene = json::Document::Load(scene_path);
  auto board = BoardObject(scene);
  if (!board) {
    throw InputError(scene_path.string() + ": /objects",
                     "no object named \"checkerboard\": give the board (--board FILE, or --rows, --cols, --square-mm)");
  }
  const fs::path file = board->Get("gltf").Path().parent_path() / "checkerboard.json";
  if (!fs::exists(file)) {
    throw InputError(file.string(), "no such file (the board layout beside the checkerboard's glTF): give the "
                                    "board with --board FILE or --rows, --cols, --square-mm");
  }
  return file;
}

SessionTruth ReadSessionTruth(const fs::path& run_dir) {
  SessionTruth t;
  const json::Document scene = json::Document::Load(ScenePath(run_dir));
  if (auto board = BoardObject(scene)) {
    if (auto pose = board->Find("world_from_object")) t.world_from_board = ReadPose(*pose);
  }
  const json::Object root = scene.Root().AsObject();
  if (auto motion = root.FindObject("motion")) {
    if (auto pose = motion->Find("tool_from_cam")) t.tool_from_cam = ReadPose(*pose);
  }
  return t;
}

std::string ShutterHint(const SessionRun& run, const std::vector<SessionView>& views) {
  if (std::any_of(views.begin(), views.end(), [](const SessionView& v) { return v.detection.ok; })) return "";
  if (run.shutter == ShutterPattern::kRecorded) return "";
  return std::string("no bright frame shows the board: are the frames the other way round (--shutter ") +
         (run.shutter == ShutterPattern::kAlternateLaserFirst ? "alternate-bright-first" : "alternate") + ")?";
}

std::vector<SessionView> ReadSessionViews(const SessionRun& run, const CheckerboardSpec& board,
                                          const CornerDetectionOptions& corners) {
  board.Check();
  corners.Check();
  const std::vector<RunFrame>& frames = run.frames;
  std::vector<SessionView> views;
  for (size_t i = 0; i < frames.size(); ++i) {
    const RunFrame& f = frames[i];
    if (f.IsLaserFrame()) continue;
    SessionView v;
    v.bright_frame = f.index;
    if (i + 1 < frames.size() && frames[i + 1].IsLaserFrame()) v.dim_frame = frames[i + 1].index;
    v.world_from_tool = f.world_from_tool;
    v.world_from_cam = f.world_from_cam;
    // A colour sensor's raw mosaic is demosaiced to grey first.
    v.detection = DetectCheckerboard(CornerDetectionImage(ReadFrameImage(run, f), run.rig.color_filter), board, corners);
    views.push_back(std::move(v));
  }
  if (views.empty()) {
    throw InputError(run.source.string(),
                     run.from_listing ? "no manifest.jsonl: every frame is a laser frame unless the shutter pattern "
                                        "(--shutter alternate-bright-first or alternate) says which frames are "
                                        "bright (the board) and which dim (the laser)"
                                      : "the run has no bright frames (frames without laser light) to find the board in");
  }
  return views;
}

SessionCameraResult CalibrateSessionCamera(const SessionRun& run, const CheckerboardSpec& board,
                                           const CameraCalibrationOptions& options,
                                           const CornerDetectionOptions& corners) {
  options.Check();
  SessionCameraResult r;
  r.views = ReadSessionViews(run, board, corners);
  std::vector<CalibrationView> views;
  for (size_t v = 0; v < r.views.size(); ++v) {
    if (!r.views[v].detection.ok) continue;
    views.push_back(ViewOfDetection(board, r.views[v].detection));
    r.used.push_back(int(v));
  }
  r.calibration = CalibrateCamera(views, run.width, run.height, options);
  return r;
}

void SessionLaserOptions::Check() const {
  ExtractionOptions e = extraction;
  if (std::isnan(e.threshold)) e.threshold = 1;
  if (std::isnan(e.background)) e.background = 0;
  e.Check();
  if (planes < 0) throw InputError("option planes", "must be >= 0");
  plane_id.Check();
  fit.Check();
  if (!(line_tolerance_px > 0) || !std::isfinite(line_tolerance_px)) {
    throw InputError("option line_tolerance_px", "must be > 0");
  }
  if (!(edge_inset_squares >= 0) || !std::isfinite(edge_inset_squares)) {
    throw InputError("option edge_inset_squares", "must be >= 0");
  }
  corners.Check();
}

SessionLaserResult CalibrateSessionLaser(const SessionRun& run, const CheckerboardSpec& board, const Camera& camera,
                                         const SessionLaserOptions& options) {
  options.Check();
  SessionLaserResult r;
  const RunRig& rig = run.rig;
  r.planes = options.planes > 0 ? options.planes : int(rig.planes_in_cam.size());
  if (r.planes < 1) {
    throw InputError(run.rig_in_run ? rig.source.string() : run.dir.string(),
                     run.rig_in_run ? "the rig has no laser: give the number of planes"
                                    : "no rig.json, and no laser planes in the calibration: give the number of planes");
  }
  r.axis = options.axis ? *options.axis : rig.planes_in_cam.empty() ? SearchAxis::kRows : StripeAxis(rig.planes_in_cam);
  // Without planes (a capture whose camera came alone), the first dim frame
  // read chooses the axis: the one along which it finds more stripe points (a
  // stripe across the rows, searched along the columns, gives a point per
  // column; searched along the rows, only the few rows its width covers).
  bool axis_known = options.axis || !rig.planes_in_cam.empty();
  ExtractionOptions extraction = options.extraction;
  if (options.method_from_planes && r.planes > 1 && FindsOneStripePerLine(extraction.method)) {
    extraction.method = ExtractionMethod::kMultiCom;
  }
  r.axis_from_frame = -1;
  const LaserChannelWeights matched = MatchedChannelWeights(rig);
  r.views = ReadSessionViews(run, board, options.corners);
  std::map<int, const RunFrame*> frames;
  for (const RunFrame& f : run.frames) frames.emplace(f.index, &f);

  const double inset = options.edge_inset_squares * board.square_m;
  const double margin = board.margin_squares * board.square_m;
  const double x0 = -board.square_m - margin + inset, x1 = board.cols * board.square_m + margin - inset;
  const double y0 = -board.square_m - margin + inset, y1 = board.rows * board.square_m + margin - inset;
  std::vector<LaserTargetView> target_views;
  for (size_t v = 0; v < r.views.size(); ++v) {
    const SessionView& sv = r.views[v];
    SessionLaserView lv;
    lv.view = int(v);
    if (sv.dim_frame < 0) {
      lv.note = "no laser frame follows bright frame " + std::to_string(sv.bright_frame);
    } else if (!sv.detection.ok) {
      lv.note = "board not found: " + sv.detection.reason;
    } else {
      lv.pose = EstimateTargetPose(camera, ViewOfDetection(board, sv.detection));
      if (!lv.pose.ok) lv.note = "no board pose: " + lv.pose.reason;
    }
    if (!lv.note.empty()) {
      r.laser_views.push_back(lv);
      continue;
    }
    RunFrame dim = *frames.at(sv.dim_frame);
    int declared_bits = 0;
    const AnyImage image = ReadFrameImage(run, dim, &declared_bits);
    if (dim.bit_depth <= 0) dim.bit_depth = declared_bits;  // as scan: threshold and saturation
    std::unique_ptr<StripeExtractor> chosen;
    std::vector<StripePoint> points;
    FrameExtraction fx;
    for (const SearchAxis axis : {r.axis, r.axis == SearchAxis::kRows ? SearchAxis::kCols : SearchAxis::kRows}) {
      ExtractionOptions given = extraction;
      given.axis = axis;
      // As in scan: a mosaic demosaiced, a colour frame on the laser's channels.
      FrameExtraction this_fx = RunFrameExtraction(given, dim, image, rig, matched);
      auto extractor = std::make_unique<StripeExtractor>(this_fx.options);
      std::vector<StripePoint> found;
      try {
        found = extractor->Extract(image);
      } catch (const InputError& e) {
        throw InputError(dim.image.string(), e.message());
      }
      if (!chosen || found.size() > points.size()) {
        chosen = std::move(extractor), points = std::move(found), fx = std::move(this_fx);
        if (!axis_known) r.axis = axis;
      }
      if (axis_known) break;
    }
    if (!axis_known) r.axis_from_frame = dim.index;
    axis_known = true;
    const StripeExtractor& extractor = *chosen;
    const ExtractionOptions& eo = fx.options;
    if (fx.matched_weights) r.channel_weights_source = matched.Describe();
    if (fx.mosaic_mean) {
      r.channel_weights_source = matched.missing;
      r.mosaic_mean = true;
    }
    lv.stripe_points = int(points.size());
    if (r.planes == 1) {
      for (auto& p : points) p.plane = 0;
    } else {
      PlaneIdOptions id = options.plane_id;
      id.axis = r.axis;
      id.edge_margin = std::max(id.edge_margin, extractor.resolved_options().EdgeLinesWithoutPoints() + 2);
      const int w = camera.width(), h = camera.height();
      PlaneIdentification ident = IdentifyPlanes(points, eo.roi ? *eo.roi : PixelRect{0, 0, w, h}, r.planes, id);
      std::string error;
      if (!GroupStripesOnFlatTarget(&points, ident.segments, r.planes, r.axis, options.line_tolerance_px, &error)) {
        lv.note = "frame " + std::to_string(dim.index) + " (" + std::to_string(points.size()) +
                  " stripe points): " + error;
        r.laser_views.push_back(lv);
        continue;
      }
    }
    // Keep the pixels whose rays meet the board inside its area.
    LaserTargetView tv;
    tv.cam_from_target = lv.pose.cam_from_target;
    const Pose target_from_cam = tv.cam_from_target.inverse();
    const Plane board_plane = Plane{Eigen::Vector3d::UnitZ(), 0.0}.Transformed(tv.cam_from_target);
    for (const StripePoint& p : points) {
      if (p.plane < 0) continue;
      const Eigen::Vector2d px(p.u, p.v);
      const auto ray = camera.Unproject(px);
      if (!ray) continue;
      const auto t = board_plane.IntersectRay(Eigen::Vector3d::Zero(), *ray);
      if (!t) continue;
      const Eigen::Vector3d b = target_from_cam * (*t * *ray);
      if (b.x() < x0 || b.x() > x1 || b.y() < y0 || b.y() > y1) continue;
      tv.stripe_pixels.push_back(px);
      tv.plane_ids.push_back(p.plane);
    }
    lv.on_board = int(tv.stripe_pixels.size());
    if (tv.stripe_pixels.empty()) {
      lv.note = "no stripe on the board in frame " + std::to_string(dim.index);
    } else {
      lv.used = true;
      target_views.push_back(std::move(tv));
    }
    r.laser_views.push_back(lv);
  }
  r.fits = CalibrateLaserPlanes(camera, target_views, options.fit);
  return r;
}

SessionHandEyeResult CalibrateSessionHandEye(const SessionRun& run, const CheckerboardSpec& board,
                                             const Camera& camera, const HandEyeOptions& options,
                                             const CornerDetectionOptions& corners) {
  options.Check();
  SessionHandEyeResult r;
  r.views = ReadSessionViews(run, board, corners);
  std::vector<HandEyeObservation> observations;
  for (size_t v = 0; v < r.views.size(); ++v) {
    const SessionView& sv = r.views[v];
    const std::string frame = "frame " + std::to_string(sv.bright_frame) + ": ";
    if (!sv.world_from_tool) {
      r.notes.push_back(frame + (run.from_listing ? "no robot tool pose (no manifest: give the tool's poses in a pose file)"
                                                  : "no robot tool pose (manifest key world_from_tool)"));
      continue;
    }
    if (!sv.detection.ok) {
      r.notes.push_back(frame + "board not found: " + sv.detection.reason);
      continue;
    }
    const CalibrationView cv = ViewOfDetection(board, sv.detection);
    const TargetPoseResult pose = EstimateTargetPose(camera, cv);
    if (!pose.ok) {
      r.notes.push_back(frame + "no board pose: " + pose.reason);
      continue;
    }
    observations.push_back({*sv.world_from_tool, pose.cam_from_target, cv.target_points, cv.pixels});
    r.used.push_back(int(v));
  }
  if (board.Symmetric()) {
    // The detector's frame of a symmetric board may be turned from view to
    // view: the first view's, chosen from the robot's motion.
    const std::vector<std::string> why = AlignBoardFrames(board, &observations);
    std::vector<HandEyeObservation> kept;
    std::vector<int> used;
    for (size_t k = 0; k < observations.size(); ++k) {
      if (!why[k].empty()) {
        r.notes.push_back("frame " + std::to_string(r.views[size_t(r.used[k])].bright_frame) + ": " + why[k]);
        continue;
      }
      kept.push_back(std::move(observations[k]));
      used.push_back(r.used[k]);
    }
    observations = std::move(kept);
    r.used = std::move(used);
  }
  if (observations.empty()) {
    r.hand_eye.ok = false;
    r.hand_eye.reason = "no view has both a robot tool pose and a detected board";
    return r;
  }
  r.hand_eye = CalibrateHandEye(observations, options, &camera);
  return r;
}

}  // namespace lt
