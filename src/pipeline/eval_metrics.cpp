// Evaluation of a scanned run (eval_metrics.h): matching measured centres to the true
// ones, scoring each frame's centres and points, and EvaluateRun. The metrics of the
// samples and their JSON are in eval_summary.cpp.
#include "pipeline/eval_metrics.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "core/atomic_file.h"
#include "core/error.h"
#include "pipeline/eval_summary.h"
#include "pipeline/ground_truth.h"
#include "pipeline/option_checks.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan.h"
#include "pipeline/scan_output.h"

namespace lt {

namespace fs = std::filesystem;

using eval_detail::Summarise;
using eval_detail::SummarisePlanes;

void EvalOptions::Check() const {
  Require(std::isfinite(max_match_px) && max_match_px > 0, "max_match_px",
          "must be a finite number > 0, got " + FormatNumber(max_match_px));
  Require(std::isfinite(completeness_mm) && completeness_mm > 0, "completeness_mm",
          "must be a finite number > 0, got " + FormatNumber(completeness_mm));
  Require(frames_begin >= 0, "frames", "the first frame must be >= 0");
  Require(frames_end < 0 || frames_end > frames_begin, "frames", "the frame range is empty");
}

namespace {

// A whole number within tolerance (and small enough to be a pixel index).
bool IsWhole(double x, double tolerance) { return std::abs(x) < 1e8 && std::abs(x - std::round(x)) <= tolerance; }

// The scan axis of a frame's ground truth: the manifest's gt_axis, else the
// coordinate that is a whole number on every centre.
SearchAxis TruthAxis(const RunFrame& frame, const std::vector<TruthCenter>& truth) {
  if (frame.gt_axis) return *frame.gt_axis;
  const bool rows = std::all_of(truth.begin(), truth.end(), [](const TruthCenter& t) { return IsWhole(t.v, 1e-6); });
  const bool cols = std::all_of(truth.begin(), truth.end(), [](const TruthCenter& t) { return IsWhole(t.u, 1e-6); });
  if (rows) return SearchAxis::kRows;
  if (cols) return SearchAxis::kCols;
  throw InputError(frame.gt_centers->string(),
                   "the centres are neither on whole rows nor on whole columns, and the manifest has no gt_axis");
}

// Refuses centres that cannot belong to the run: outside the camera's image, or
// on a laser plane the rig does not have (measured centres may also carry -1,
// no plane identified). A ground-truth file or a centres file from another run
// would otherwise be scored as if it were this one's.
void CheckCentersFitTheRig(const RunRig& rig, const std::vector<TruthCenter>& truth, const fs::path& truth_file,
                           const std::vector<ScanPoint>& measured, const fs::path& measured_file) {
  const int planes = int(rig.planes_in_cam.size());
  const std::string image = std::to_string(rig.camera.width()) + "x" + std::to_string(rig.camera.height());
  const std::string plane_range = planes > 0 ? "0.." + std::to_string(planes - 1) : "none";
  auto where = [](double u, double v) { return " at (" + FormatNumber(u) + ", " + FormatNumber(v) + ")"; };
  for (const TruthCenter& t : truth) {
    const std::string at = truth_file.string() + ":" + std::to_string(t.line);
    if (!rig.camera.InImage({t.u, t.v})) {
      throw InputError(at, "the centre" + where(t.u, t.v) + " lies outside the " + image + " image of rig.json's camera");
    }
    if (t.plane >= planes) {
      throw InputError(at, "plane " + std::to_string(t.plane) + " is not one of rig.json's laser planes (" +
                               plane_range + ")");
    }
  }
  for (size_t j = 0; j < measured.size(); ++j) {
    const StripePoint& m = measured[j].pixel;
    const std::string at = measured_file.string() + ": centre " + std::to_string(j + 1);
    if (!rig.camera.InImage({m.u, m.v})) {
      throw InputError(at, where(m.u, m.v).substr(1) + " lies outside the " + image + " image of rig.json's camera");
    }
    if (m.plane < -1 || m.plane >= planes) {
      throw InputError(at, "plane " + std::to_string(m.plane) + " is not one of rig.json's laser planes (" +
                               plane_range + ", or -1 for none)");
    }
  }
}

}  // namespace

std::vector<int> MatchCenters(SearchAxis axis, const std::vector<TruthCenter>& truth,
                              const std::vector<ScanPoint>& measured, double max_match_px,
                              const fs::path& truth_file, const fs::path& measured_file) {
  const bool rows = axis == SearchAxis::kRows;
  auto line_of = [&](double u, double v) { return rows ? v : u; };
  auto along = [&](double u, double v) { return rows ? u : v; };
  const char* lines = rows ? "rows" : "columns";
  std::map<int, std::pair<std::vector<int>, std::vector<int>>> by_line;  // line -> (truth, measured) indices
  for (size_t i = 0; i < truth.size(); ++i) {
    const double l = line_of(truth[i].u, truth[i].v);
    if (!IsWhole(l, 1e-6)) {
      throw InputError(truth_file.string(), std::string("ground-truth centre ") + std::to_string(i + 1) +
                                                " is not on a whole image row/column (gt_axis " +
                                                (rows ? "rows" : "cols") + ")");
    }
    by_line[int(std::lround(l))].first.push_back(int(i));
  }
  for (size_t j = 0; j < measured.size(); ++j) {
    const double l = line_of(measured[j].pixel.u, measured[j].pixel.v);
    if (!IsWhole(l, 1e-3)) {
      throw InputError(measured_file.string(),
                       std::string("the centres are not on whole image ") + lines +
                           ", but this run's ground truth scans " + lines + ": scan it with --axis " +
                           (rows ? "rows" : "cols"));
    }
    by_line[int(std::lround(l))].second.push_back(int(j));
  }
  std::vector<int> partner(measured.size(), -1);  // measured -> truth
  for (auto& [line, ids] : by_line) {
    const auto& [ti, mi] = ids;
    std::vector<std::tuple<double, int, int>> pairs;
    for (int i : ti) {
      for (int j : mi) {
        const double d = std::abs(along(measured[size_t(j)].pixel.u, measured[size_t(j)].pixel.v) -
                                  along(truth[size_t(i)].u, truth[size_t(i)].v));
        if (d <= max_match_px) pairs.emplace_back(d, i, j);
      }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<int> truth_partner;
    for (const auto& [d, i, j] : pairs) {
      (void)d;
      if (partner[size_t(j)] >= 0 ||
          std::find(truth_partner.begin(), truth_partner.end(), i) != truth_partner.end()) {
        continue;
      }
      partner[size_t(j)] = i;
      truth_partner.push_back(i);
    }
  }
  return partner;
}

namespace {

struct FrameSamples {
  std::vector<CenterSample> centers;
  std::vector<PointSample> points;
};

FrameSamples EvaluateFrame(const RunFrame& frame, SearchAxis axis, const std::vector<TruthCenter>& truth,
                           const std::vector<ScanPoint>& measured, const fs::path& measured_file,
                           const TrueSurface* surface, const PointToSurface& scene_distance,
                           const EvalOptions& o) {
  const bool rows = axis == SearchAxis::kRows;
  auto line_of = [&](double u, double v) { return rows ? v : u; };
  auto along = [&](double u, double v) { return rows ? u : v; };
  const std::vector<int> partner = MatchCenters(axis, truth, measured, o.max_match_px, *frame.gt_centers, measured_file);
  std::map<int, std::pair<std::vector<int>, std::vector<int>>> by_line;  // line -> (truth, measured) indices
  for (size_t i = 0; i < truth.size(); ++i) by_line[int(std::lround(line_of(truth[i].u, truth[i].v)))].first.push_back(int(i));
  for (size_t j = 0; j < measured.size(); ++j)
    by_line[int(std::lround(line_of(measured[j].pixel.u, measured[j].pixel.v)))].second.push_back(int(j));

  FrameSamples out;
  for (auto& [line, ids] : by_line) {
    const auto& [ti, mi] = ids;
    std::map<int, int> matched_truth;
    for (int j : mi) {
      if (partner[size_t(j)] >= 0) matched_truth[partner[size_t(j)]] = j;
    }
    for (int i : ti) {
      const TruthCenter& t = truth[size_t(i)];
      CenterSample s;
      s.frame = frame.index;
      s.line = line;
      s.has_truth = true;
      s.u_true = t.u;
      s.v_true = t.v;
      s.depth_true_m = t.p_in_cam.z();
      s.plane_true = t.plane;
      auto it = matched_truth.find(i);
      if (it != matched_truth.end()) {
        const ScanPoint& m = measured[size_t(it->second)];
        s.matched = true;
        s.u_measured = m.pixel.u;
        s.v_measured = m.pixel.v;
        s.plane_measured = m.pixel.plane;
        s.error_px = along(m.pixel.u, m.pixel.v) - along(t.u, t.v);
        s.complete = m.p_in_cam && (*m.p_in_cam - t.p_in_cam).norm() <= o.completeness_mm * 1e-3;
      }
      out.centers.push_back(s);
    }
    for (int j : mi) {
      if (partner[size_t(j)] >= 0) continue;
      const ScanPoint& m = measured[size_t(j)];
      CenterSample s;
      s.frame = frame.index;
      s.line = line;
      s.u_measured = m.pixel.u;
      s.v_measured = m.pixel.v;
      s.plane_measured = m.pixel.plane;
      out.centers.push_back(s);
    }
  }
  if (!scene_distance && !surface) return out;
  std::vector<Eigen::Vector3d> exact;  // the exact centres of a point's line and the lines beside it
  // A point's distance in metres: to the scene, else to the surfaces the buffers see.
  auto distance = [&](const ScanPoint& m, const Eigen::Vector3d& p_in_cam) -> std::optional<double> {
    if (scene_distance) return scene_distance(p_in_cam);
    exact.clear();
    const int line = int(std::lround(line_of(m.pixel.u, m.pixel.v)));
    for (int l = line - 1; l <= line + 1; ++l) {
      const auto it = by_line.find(l);
      if (it == by_line.end()) continue;
      for (int i : it->second.first) exact.push_back(truth[size_t(i)].p_in_cam);
    }
    const std::optional<double> d = surface->SignedDistance(p_in_cam, exact);
    if (!d) return std::nullopt;
    return std::abs(*d);
  };
  for (const ScanPoint& m : measured) {
    if (!m.p_in_cam) continue;
    PointSample p;
    p.frame = frame.index;
    p.plane = m.pixel.plane;
    p.u = m.pixel.u;
    p.v = m.pixel.v;
    p.depth_m = m.p_in_cam->z();
    if (const std::optional<double> d = distance(m, *m.p_in_cam)) {
      p.on_surface = true;
      p.error_mm = *d * 1e3;
    }
    // Where the scan placed it, seen from the camera where it really was.
    // Placed with the manifest's pose (within the CSV's digits): the same distance, not searched again.
    if (m.p_in_world && frame.world_from_cam) {
      const Eigen::Vector3d placed = frame.world_from_cam->inverse() * *m.p_in_world;
      p.has_pose_offset = true;
      p.pose_offset_mm = (placed - *m.p_in_cam).norm() * 1e3;  // a rigid motion keeps lengths
      const std::optional<double> d = (placed - *m.p_in_cam).norm() <= 1e-9
                                          ? (p.on_surface ? std::optional<double>(p.error_mm * 1e-3) : std::nullopt)
                                          : distance(m, placed);
      if (d) {
        p.stitched = true;
        p.stitched_error_mm = *d * 1e3;
      }
    }
    out.points.push_back(p);
  }
  return out;
}

}  // namespace

RunMetrics EvaluateRun(const fs::path& run_dir, const EvalOptions& options,
                       const SurfaceDistanceSource& surface_distance) {
  options.Check();
  const std::vector<RunFrame> manifest = ReadRunManifest(run_dir);
  const fs::path centers_dir = run_dir / "centers";
  if (!fs::is_directory(centers_dir)) {
    throw InputError(centers_dir.string(), "no measured centres: run `lasertwin scan " + run_dir.string() + "` first");
  }
  RunMetrics run;
  run.run_dir = run_dir;
  run.options = options;
  const RunRig rig = ReadRunRig(run_dir);
  bool first = true;
  for (const RunFrame& f : manifest) {
    if (f.index < options.frames_begin || (options.frames_end >= 0 && f.index >= options.frames_end)) continue;
    if (!f.IsLaserFrame()) continue;
    if (!f.gt_centers) {
      ++run.frames_skipped;
      continue;
    }
    const std::vector<TruthCenter> truth = ReadTruthCentersCsv(*f.gt_centers);
    const SearchAxis axis = TruthAxis(f, truth);
    if (first) run.axis = axis;
    first = false;
    const fs::path measured_file = run_dir / ScanCentersName(f.index);
    if (!fs::exists(measured_file)) {
      throw InputError(measured_file.string(), "no such file: frame " + std::to_string(f.index) +
                                                   " was not scanned (run `lasertwin scan " + run_dir.string() + "`)");
    }
    const std::vector<ScanPoint> measured = ReadScanCsv(measured_file);
    CheckCentersFitTheRig(rig, truth, *f.gt_centers, measured, measured_file);
    const PointToSurface scene_distance = surface_distance ? surface_distance(f) : PointToSurface();
    std::optional<TrueSurface> surface;
    if (f.gt_buffers && !scene_distance) surface.emplace(rig.camera, *f.gt_buffers);
    FrameSamples s = EvaluateFrame(f, axis, truth, measured, measured_file, surface ? &*surface : nullptr,
                                   scene_distance, options);
    FrameMetrics fm;
    fm.index = f.index;
    fm.has_surface = surface.has_value() || bool(scene_distance);
    fm.surface_from_scene = bool(scene_distance);
    fm.total = Summarise(s.centers, s.points);
    fm.planes = SummarisePlanes(s.centers, s.points);
    run.frames.push_back(std::move(fm));
    run.centers.insert(run.centers.end(), s.centers.begin(), s.centers.end());
    run.points.insert(run.points.end(), s.points.begin(), s.points.end());
  }
  if (run.frames.empty()) {
    throw InputError((run_dir / "manifest.jsonl").string(),
                     "no laser frame with ground-truth stripe centres (files.centers) in the frame range");
  }
  run.total = Summarise(run.centers, run.points);
  run.planes = SummarisePlanes(run.centers, run.points);
  return run;
}

fs::path WriteMetricsJson(const fs::path& run_dir, const RunMetrics& metrics) {
  const fs::path path = run_dir / "metrics.json";
  WriteFileAtomically(path, metrics.ToJson().dump(2) + "\n");
  return path;
}

}  // namespace lt
