// Calibration from a recorded session (`lasertwin calibrate`, docs/calibration.md):
// a run folder (pipeline/run_folder_reader.h) of a checkerboard seen in several
// poses, each pose as a bright frame (no laser: the corners) followed by a dim
// frame (laser on: the stripe on the board), as `lasertwin calib-session`
// scenes render them and a real capture records them.
//
//   camera     corners of every bright frame -> CalibrateCamera
//   laser      per view, the board pose from the bright frame's corners
//              (EstimateTargetPose with the calibrated camera) and the stripe
//              of the dim frame (StripeExtractor; with several sheets, the
//              stripes grouped in image order by IdentifyPlanes) -> the stripe
//              pixels whose rays meet the board inside its area ->
//              CalibrateLaserPlanes (RANSAC + total least squares)
//   hand-eye   per view, the robot tool pose of the bright frame (manifest
//              key world_from_tool) and the board pose -> CalibrateHandEye
//              with the corners' reprojection refinement
//
// A view whose board is not detected is skipped (and listed with the
// detector's reason); the estimators refuse, with their reasons, when too few
// or degenerate views remain.
//
// The frames come from the run's manifest or, for a real capture without one,
// the folder's listing (pipeline/calib_session_run.h).
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/pose.h"
#include "pipeline/calib_camera.h"
#include "pipeline/calib_checkerboard.h"
#include "pipeline/calib_corners.h"
#include "pipeline/calib_hand_eye.h"
#include "pipeline/calib_laser_plane.h"
#include "pipeline/calib_session_run.h"
#include "pipeline/calib_target_pose.h"
#include "pipeline/extraction_options.h"
#include "pipeline/image_file_facts.h"
#include "pipeline/plane_identification.h"
#include "sensor/camera.h"

namespace lt {

// A board layout file (JSON: rows, cols, square_mm, margin_squares optional,
// default 1), as calib-session writes it (checkerboard.json). Errors name the
// file and JSON pointer.
CheckerboardSpec ReadCheckerboardFile(const std::filesystem::path& path);

// The board layout file of a rendered session: checkerboard.json beside the
// glTF of the run scene's object named "checkerboard". Throws lt::InputError
// when the run's scene.json has no such object or the file is missing.
std::filesystem::path FindSessionBoardFile(const std::filesystem::path& run_dir);

// Ground truth of a rendered session, from the run's scene.json: the board's
// pose (object "checkerboard") and the hand-eye pose (motion tool_from_cam).
struct SessionTruth {
  std::optional<Pose> world_from_board;
  std::optional<Pose> tool_from_cam;
};
SessionTruth ReadSessionTruth(const std::filesystem::path& run_dir);

// One pose of the board: its bright frame and the dim frame that follows it.
struct SessionView {
  int bright_frame = -1;  // frame index (the manifest's, or the position in the folder's name order)
  int dim_frame = -1;     // -1: none follows
  CornerDetection detection;
  std::optional<Pose> world_from_tool;  // of the bright frame
  std::optional<Pose> world_from_cam;   // of the bright frame (a rendered run's truth)
};

// When no bright frame shows the board and an alternating shutter pattern chose
// the bright frames: the hint that the pattern may be the other way round; else "".
std::string ShutterHint(const SessionRun& run, const std::vector<SessionView>& views);

// The views of a run: every frame without laser light starts one; a laser
// frame right after it is its dim frame. Corners are detected on the bright
// frames (a colour sensor's mosaic, run.rig.color_filter, through
// CornerDetectionImage, pipeline/calib_camera_images.h). The frames are read
// as scan reads them (pipeline/frame_image_reader.h); an Orientation tag goes
// to `warner` (null: nowhere). Throws lt::InputError for an unreadable run or
// image, or a run without bright frames.
std::vector<SessionView> ReadSessionViews(const SessionRun& run, const CheckerboardSpec& board,
                                          const CornerDetectionOptions& corners = {},
                                          ImageFileWarner* warner = nullptr);

// The Calibrate* functions below give what the frames' files declare and is
// not applied (ImageFileWarnings: Orientation; a transfer-curve tag on the
// laser step's dim frames) to `warn`, each once a run, with the count of the
// other frames it holds for at the end (ImageFileWarner), as scan does.

struct SessionCameraResult {
  std::vector<SessionView> views;
  std::vector<int> used;  // indices into views of the calibrated views, in the calibration's order
  CameraCalibrationResult calibration;
};
SessionCameraResult CalibrateSessionCamera(const SessionRun& run, const CheckerboardSpec& board,
                                           const CameraCalibrationOptions& options = {},
                                           const CornerDetectionOptions& corners = {},
                                           const std::function<void(const std::string&)>& warn = {});

struct SessionLaserOptions {
  // As `scan` (pipeline/frame_extraction.h): threshold kAuto, 10% of the
  // frame's full scale (its bit depth); background kAuto, the image sensor's
  // black level (rig.json's; 0 without a rig).
  ExtractionOptions extraction = AutoLevels();
  // The method was not chosen: with several sheets multicom (com and max find
  // one stripe per search line), else extraction.method; as scan's.
  bool method_from_planes = false;
  // --transfer was given (even linear): no warning about a dim frame's
  // transfer-curve tag, as scan's ScanOptions::transfer_given.
  bool transfer_given = false;
  // Unset: from the run rig's nominal planes (StripeAxis); without planes, the
  // axis finding more stripe points on the first dim frame read.
  std::optional<SearchAxis> axis;
  int planes = 0;                  // laser sheets; 0: as many as the run's rig has
  PlaneIdOptions plane_id;  // the stripe's connected pieces (link_distance, min_segment_points)
  // Several sheets: a piece of stripe joins a line when its points lie within
  // this mean distance (pixels, across the stripe) of the line's fit.
  double line_tolerance_px = 3.0;
  LaserPlaneFitOptions fit;
  // Stripe pixels are kept where their ray meets the board at least this far
  // (in squares) inside the board's outer edge.
  double edge_inset_squares = 0.5;
  CornerDetectionOptions corners;

  void Check() const;  // throws lt::InputError naming the option
  static ExtractionOptions AutoLevels() {
    ExtractionOptions e;
    e.background = ExtractionOptions::kAuto;
    return e;
  }
};

struct SessionLaserView {
  int view = 0;  // index into views
  bool used = false;
  std::string note;  // why the view was not used, or a plane identification failure
  int stripe_points = 0;  // extracted
  int on_board = 0;       // kept: their rays meet the board
  TargetPoseResult pose;
};

struct SessionLaserResult {
  std::vector<SessionView> views;
  std::vector<SessionLaserView> laser_views;
  std::vector<LaserPlaneFit> fits;  // plane k = k-th stripe in image order
  int planes = 0;
  SearchAxis axis = SearchAxis::kRows;
  int axis_from_frame = -1;  // the dim frame that chose the axis; -1: the options' or the planes'
  // Colour frames: the channels the stripe was extracted from (as scan's
  // channel_weights_source); empty for mono frames or given channels.
  // mosaic_mean: a mosaic extracted on the mean of R, G, B (the rig gives no
  // weights; the source says why).
  std::string channel_weights_source;
  bool mosaic_mean = false;
};
SessionLaserResult CalibrateSessionLaser(const SessionRun& run, const CheckerboardSpec& board, const Camera& camera,
                                         const SessionLaserOptions& options = {},
                                         const std::function<void(const std::string&)>& warn = {});

// Multi-line stripes on the flat target: each sheet's stripe is one straight
// line across the board (up to lens distortion), broken into pieces where it
// crosses black squares (`segments`: the connected pieces from
// IdentifyPlanes). The lines run nearly parallel, so with the slope pooled
// over all pieces each piece has an intercept, and the intercepts cluster by
// line (a gap of more than 4·tol_px starts a new cluster). A line is then
// fitted to each cluster and every piece goes to the line its points lie
// closest to, within tol_px mean distance; farther pieces, and lines with less
// than a fifth of the longest line's points, are stray light (plane −1). The
// lines must number n; they are numbered in image order (by
// their position across at the middle of the points) into each point's
// `plane`. Otherwise false, with the reason in *error.
bool GroupStripesOnFlatTarget(std::vector<StripePoint>* points, const std::vector<StripeSegment>& segments, int n,
                              SearchAxis axis, double tol_px, std::string* error);

struct SessionHandEyeResult {
  std::vector<SessionView> views;
  std::vector<int> used;  // views in the estimate
  std::vector<std::string> notes;  // skipped views and why
  HandEyeResult hand_eye;
};
SessionHandEyeResult CalibrateSessionHandEye(const SessionRun& run, const CheckerboardSpec& board,
                                             const Camera& camera, const HandEyeOptions& options = {},
                                             const CornerDetectionOptions& corners = {},
                                             const std::function<void(const std::string&)>& warn = {});

}  // namespace lt
