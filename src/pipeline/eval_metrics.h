// Evaluation of a scanned run against its ground truth (`lasertwin eval`,
// docs/evaluation.md): measured stripe centres (RUN/centers/NNNNNN.csv, written
// by `lasertwin scan`) against the exact centres (RUN/gt/NNNNNN_centers.csv),
// and the triangulated points against the true surface (RUN/gt/NNNNNN.exr).
//
// Matching, per frame and per scan line (image row or column, the manifest's
// gt_axis): every ground-truth centre is paired with the nearest measured
// centre on the same line within max_match_px, one-to-one, greedily by
// distance (closest pairs first), whatever their plane numbers. The centre
// error of a pair is the distance along the scan line (|u_m - u_t| when
// scanning rows, |v_m - v_t| when scanning columns).
//   detection_rate     matched ground-truth centres / ground-truth centres
//   false_positives    measured centres paired with no ground-truth centre
//                      (count, and rate = count / measured centres)
//   plane_id_accuracy  pairs whose measured plane equals the true plane /
//                      pairs; a measured plane -1 (not identified) counts as
//                      wrong and is also counted in plane_unidentified
//
// Point error: every triangulated measured point P (camera frame) is projected
// into the image; the true surface there comes from the ground-truth depth and
// normal buffers: for each of the 4 pixels around the projection, the surface
// point S_i = Z_i r_i / r_i.z (r_i = Camera::Unproject of the pixel) and normal
// n_i; when the 4 pixels are on the same surface (same instance, normals
// within 30 degrees, each S_i within 30 degrees of the nearest pixel's tangent
// plane as seen from it) the error is |bilinear blend of m_i.(P - S_i)|, m_i
// the unit mean of n_i and the normal at P (the 4 normals blended): a chord of
// a sphere or cylinder is perpendicular to the sum of its ends' normals, so a
// point on a curved surface scores 0, not |P - S_i|^2 / (2R), else (across a break: an
// edge, a step, a silhouette, where a stripe point's light may come from any
// surface within its pixel) the smallest |d_i| over the 3x3 pixels around the
// nearest pixel and the distances to the exact stripe centres of its scan line
// and the two beside it (true surface points: a face narrower than a pixel,
// which no pixel centre sees, has them), as a cloud-to-mesh distance takes it.
// This is exact for locally planar surfaces (and second-order on curved ones). Points that project
// outside the image or onto background (Z = 0) have no true surface: counted
// in points_off_surface, not in the statistics.
// The buffers hold only the surfaces pixels see: a point near a face no pixel
// sees (a box's far side, a surface hidden behind another) is scored against
// the visible surface there. When the caller can give the exact distance to
// the scene's surfaces (SurfaceDistanceSource: `lasertwin eval` rebuilds the
// run's scene.json at each frame's time), every point of that frame is scored
// by it instead, and points_off_surface counts only points with no surface at
// all (an empty scene).
//   completeness       ground-truth centres whose measured partner has a
//                      triangulated point within completeness_mm of the true
//                      3D point (x_cam, y_cam, z_cam) / ground-truth centres
//
// Stitched point error: the same distance for the point where the scan placed it
// in the world (the centres CSV's world columns), taken to the frame's camera by the
// manifest's world_from_cam: the point error plus the error of the pose scan used
// (a hand-eye calibration's tool_from_cam, a pose file). Equal to the point error
// when scan placed the points with the manifest's poses.
//
// Statistics (ErrorStats) are of absolute values; empty statistics have n = 0
// and are written as null. No NaN or infinity is ever written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/extraction_options.h"
#include "pipeline/ground_truth.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/triangulation.h"

namespace lt {

struct EvalOptions {
  double max_match_px = 3.0;     // largest centre distance (along the scan line) of a pair, pixels
  double completeness_mm = 0.1;  // largest 3D distance of a "reconstructed" stripe point, mm
  int frames_begin = 0;          // frames [frames_begin, frames_end) of the manifest, by index
  int frames_end = -1;           // -1: to the end
  void Check() const;            // throws lt::InputError naming the option
};

// Statistics of |x|: count, root mean square, median, 95th percentile (linear
// interpolation between order statistics) and maximum.
struct ErrorStats {
  int64_t n = 0;
  double rms = 0, median = 0, p95 = 0, max = 0;
  nlohmann::json ToJson() const;  // {"n": 0, "rms": null, ...} when empty
};
// Throws std::invalid_argument on a non-finite value.
ErrorStats Summarize(std::vector<double> values);
// Percentile q in [0, 1] of already sorted values (linear interpolation); 0 when empty.
double SortedQuantile(const std::vector<double>& sorted, double q);

// One ground-truth centre or one unmatched measured centre of a frame.
struct CenterSample {
  int frame = 0;
  int line = 0;            // scan line: image row (rows) or column (cols)
  bool has_truth = false;  // false: a false positive (measured, unmatched)
  bool matched = false;    // true: has_truth and a measured partner
  double u_true = 0, v_true = 0, depth_true_m = 0;  // has_truth
  int plane_true = -1;
  double u_measured = 0, v_measured = 0;  // matched or a false positive
  int plane_measured = -1;
  double error_px = 0;  // signed, measured - true along the scan line (matched)
  bool complete = false;  // matched and triangulated within completeness_mm of the true point
};

// One triangulated measured point.
struct PointSample {
  int frame = 0;
  int plane = -1;           // the measured plane it was triangulated with
  double u = 0, v = 0;      // measured centre
  double depth_m = 0;       // z of the point, camera frame
  bool on_surface = false;  // a true surface lies under it (else error_mm is 0 and unused)
  double error_mm = 0;      // |distance to the true surface|
  // The point where the scan put it in the world (its CSV's x_world, y_world, z_world:
  // placed with the pose scan used, such as world_from_tool · tool_from_cam of a
  // calibration, or a pose file's) against the same surface; false when the CSV has
  // no world point or the manifest no world_from_cam.
  bool stitched = false;
  double stitched_error_mm = 0;
  // How far the scan's pose moved the point from where the manifest's pose puts
  // the same camera-frame point, |p_in_world - world_from_cam · p_in_cam|: the
  // stitching's own error, also along a surface, where the distance above is
  // blind to it (set with `stitched`, whether or not a surface lies under it).
  bool has_pose_offset = false;
  double pose_offset_mm = 0;
};

struct EvalCounts {
  int64_t gt_centers = 0, measured_centers = 0, matched = 0, false_positives = 0;
  int64_t plane_correct = 0, plane_unidentified = 0;
  int64_t points_triangulated = 0, points_off_surface = 0, complete = 0;
  EvalCounts& operator+=(const EvalCounts& o);
};

// Metrics of a set of samples (a frame, a plane, the run).
struct EvalSummary {
  EvalCounts counts;
  ErrorStats center_px;  // matched pairs
  double center_bias_px = 0;  // mean signed error of the pairs (0 when none)
  ErrorStats point_mm;
  ErrorStats stitched_point_mm;  // of the stitched world points (PointSample::stitched); n = 0 when none
  ErrorStats pose_offset_mm;     // PointSample::pose_offset_mm; n = 0 when none
  std::optional<double> detection_rate, false_positive_rate, plane_id_accuracy, completeness;
  nlohmann::json ToJson() const;
};

struct FrameMetrics {
  int index = 0;
  EvalSummary total;
  std::map<int, EvalSummary> planes;  // by plane: true plane for centres, measured for points and false positives
  bool has_surface = false;           // the frame's points were scored (buffers or scene surfaces)
  bool surface_from_scene = false;    // scored by the exact distance to the scene's surfaces
};

struct RunMetrics {
  std::filesystem::path run_dir;
  EvalOptions options;
  SearchAxis axis = SearchAxis::kRows;  // scan lines of the ground truth (first evaluated frame)
  int frames_skipped = 0;               // laser frames in range without ground-truth centres
  EvalSummary total;
  std::map<int, EvalSummary> planes;
  std::vector<FrameMetrics> frames;
  std::vector<CenterSample> centers;  // every sample, for plots (not in ToJson)
  std::vector<PointSample> points;
  // How the point errors were scored: "scene" (distance to the scene's
  // surfaces, every frame), "gt_buffers" (depth and normal buffers, every frame
  // that has them), "mixed" or "none" (no frame had either).
  std::string PointErrorMethod() const;
  std::string point_error_note;  // why the scene's surfaces were not used (metrics.json, when set)
  nlohmann::json ToJson() const;
};

// The exact distance, metres, from a point in a frame's camera frame to the
// true surface (the nearest point of any surface of the scene at the frame's
// time); nullopt when there is no surface.
using PointToSurface = std::function<std::optional<double>(const Eigen::Vector3d& p_in_cam)>;
// Gives a frame's PointToSurface, or an empty function when it has none (the
// frame is then scored on its ground-truth buffers). Called once per evaluated
// frame, in manifest order.
using SurfaceDistanceSource = std::function<PointToSurface(const RunFrame& frame)>;

// Evaluates the laser frames of a run that have ground-truth centres. Throws
// lt::InputError: no run folder or manifest, no centers/ folder ("run
// `lasertwin scan RUN_DIR` first"), a missing or malformed CSV (file:line), a
// measured file scanned along the other axis, ground-truth buffers of the
// wrong size or without Z/N channels, no frame with ground truth in range.
// surface_distance, when set, scores the points of the frames it gives a
// distance for (above).
RunMetrics EvaluateRun(const std::filesystem::path& run_dir, const EvalOptions& options,
                       const SurfaceDistanceSource& surface_distance = {});

// The matching of one frame (above): per scan line of `axis`, each
// ground-truth centre with the nearest measured centre within max_match_px,
// one-to-one, closest pairs first. Returns, per measured centre, the index of
// its ground-truth partner or -1. Throws lt::InputError naming truth_file or
// measured_file when a centre is not on a whole scan line.
std::vector<int> MatchCenters(SearchAxis axis, const std::vector<TruthCenter>& truth,
                              const std::vector<ScanPoint>& measured, double max_match_px,
                              const std::filesystem::path& truth_file, const std::filesystem::path& measured_file);

// Writes RUN/metrics.json (atomically) and returns its path.
std::filesystem::path WriteMetricsJson(const std::filesystem::path& run_dir, const RunMetrics& metrics);

}  // namespace lt
