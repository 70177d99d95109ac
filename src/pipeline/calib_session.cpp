#include "pipeline/calib_session.h"

#include <algorithm>

#include "core/error.h"
#include "core/json_reader.h"
#include "pipeline/calib_board_turns.h"
#include "pipeline/calib_camera_images.h"
#include "pipeline/frame_image_reader.h"

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

// ReadSessionViews, with what the frames' files declare said once a run.
std::vector<SessionView> ViewsWarned(const SessionRun& run, const CheckerboardSpec& board,
                                     const CornerDetectionOptions& corners,
                                     const std::function<void(const std::string&)>& warn) {
  ImageFileWarner warner(warn, "frame");
  std::vector<SessionView> views = ReadSessionViews(run, board, corners, &warner);
  warner.SayRepeats();
  return views;
}

}  // namespace

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
                                          const CornerDetectionOptions& corners, ImageFileWarner* warner) {
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
    // A colour sensor's raw mosaic is demosaiced to grey first. The corners
    // need no linear values: a transfer-curve tag is not said.
    RunFrame read = f;
    const AnyImage image = ReadFrameImage(&read, run.rig.camera, run.rig.source.string(), warner, false);
    v.detection = DetectCheckerboard(CornerDetectionImage(image, run.rig.color_filter), board, corners);
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
                                           const CornerDetectionOptions& corners,
                                           const std::function<void(const std::string&)>& warn) {
  options.Check();
  SessionCameraResult r;
  r.views = ViewsWarned(run, board, corners, warn);
  std::vector<CalibrationView> views;
  for (size_t v = 0; v < r.views.size(); ++v) {
    if (!r.views[v].detection.ok) continue;
    views.push_back(ViewOfDetection(board, r.views[v].detection));
    r.used.push_back(int(v));
  }
  r.calibration = CalibrateCamera(views, run.width, run.height, options);
  return r;
}

SessionHandEyeResult CalibrateSessionHandEye(const SessionRun& run, const CheckerboardSpec& board,
                                             const Camera& camera, const HandEyeOptions& options,
                                             const CornerDetectionOptions& corners,
                                             const std::function<void(const std::string&)>& warn) {
  options.Check();
  SessionHandEyeResult r;
  r.views = ViewsWarned(run, board, corners, warn);
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
