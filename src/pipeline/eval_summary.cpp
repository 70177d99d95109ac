// The metrics of an evaluation (eval_metrics.h) from its samples: error statistics
// (Summarize, SortedQuantile), counts and rates, whole and per plane (eval_summary.h),
// and their JSON (ErrorStats, EvalSummary, RunMetrics ::ToJson). Matching the centres
// and evaluating a run's frames are in eval_metrics.cpp.
#include "pipeline/eval_summary.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace lt {

double SortedQuantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0;
  const double pos = std::clamp(q, 0.0, 1.0) * double(sorted.size() - 1);
  const size_t i = size_t(std::floor(pos));
  if (i + 1 >= sorted.size()) return sorted.back();
  const double f = pos - double(i);
  return sorted[i] + f * (sorted[i + 1] - sorted[i]);
}

ErrorStats Summarize(std::vector<double> values) {
  ErrorStats s;
  s.n = int64_t(values.size());
  if (values.empty()) return s;
  double sum_sq = 0;
  for (double& v : values) {
    if (!std::isfinite(v)) throw std::invalid_argument("Summarize: a value is not finite");
    v = std::abs(v);
    sum_sq += v * v;
  }
  std::sort(values.begin(), values.end());
  s.rms = std::sqrt(sum_sq / double(values.size()));
  s.median = SortedQuantile(values, 0.5);
  s.p95 = SortedQuantile(values, 0.95);
  s.max = values.back();
  return s;
}

namespace {

nlohmann::json Num(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
nlohmann::json Num(const std::optional<double>& v) { return v ? Num(*v) : nlohmann::json(nullptr); }
std::optional<double> Ratio(int64_t num, int64_t den) {
  return den > 0 ? std::optional<double>(double(num) / double(den)) : std::nullopt;
}

}  // namespace

namespace eval_detail {

// The metrics of the samples (of plane `plane` when set: true plane for
// ground-truth centres, measured plane for false positives and points).
EvalSummary Summarise(const std::vector<CenterSample>& centers, const std::vector<PointSample>& points,
                      std::optional<int> plane) {
  EvalSummary s;
  EvalCounts& c = s.counts;
  std::vector<double> center_errors, point_errors, stitched_errors, pose_offsets;
  double bias = 0;
  for (const CenterSample& x : centers) {
    if (!x.has_truth) {
      if (plane && x.plane_measured != *plane) continue;
      ++c.false_positives;
      ++c.measured_centers;
      continue;
    }
    if (plane && x.plane_true != *plane) continue;
    ++c.gt_centers;
    if (!x.matched) continue;
    ++c.matched;
    ++c.measured_centers;
    center_errors.push_back(x.error_px);
    bias += x.error_px;
    if (x.plane_measured == x.plane_true) ++c.plane_correct;
    if (x.plane_measured < 0) ++c.plane_unidentified;
    if (x.complete) ++c.complete;
  }
  for (const PointSample& p : points) {
    if (plane && p.plane != *plane) continue;
    ++c.points_triangulated;
    if (p.stitched) stitched_errors.push_back(p.stitched_error_mm);
    if (p.has_pose_offset) pose_offsets.push_back(p.pose_offset_mm);
    if (p.on_surface) {
      point_errors.push_back(p.error_mm);
    } else {
      ++c.points_off_surface;
    }
  }
  s.center_px = Summarize(std::move(center_errors));
  s.center_bias_px = c.matched > 0 ? bias / double(c.matched) : 0.0;
  s.point_mm = Summarize(std::move(point_errors));
  s.stitched_point_mm = Summarize(std::move(stitched_errors));
  s.pose_offset_mm = Summarize(std::move(pose_offsets));
  s.detection_rate = Ratio(c.matched, c.gt_centers);
  s.false_positive_rate = Ratio(c.false_positives, c.measured_centers);
  s.plane_id_accuracy = Ratio(c.plane_correct, c.matched);
  s.completeness = Ratio(c.complete, c.gt_centers);
  return s;
}

std::map<int, EvalSummary> SummarisePlanes(const std::vector<CenterSample>& centers,
                                           const std::vector<PointSample>& points) {
  std::vector<int> planes;
  for (const CenterSample& x : centers) planes.push_back(x.has_truth ? x.plane_true : x.plane_measured);
  for (const PointSample& p : points) planes.push_back(p.plane);
  std::sort(planes.begin(), planes.end());
  planes.erase(std::unique(planes.begin(), planes.end()), planes.end());
  std::map<int, EvalSummary> out;
  for (int k : planes) out[k] = Summarise(centers, points, k);
  return out;
}

}  // namespace eval_detail

namespace {

nlohmann::json PlanesToJson(const std::map<int, EvalSummary>& planes) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& [k, s] : planes) {
    nlohmann::json j = {{"plane", k}};
    j.update(s.ToJson());
    a.push_back(j);
  }
  return a;
}

}  // namespace

EvalCounts& EvalCounts::operator+=(const EvalCounts& o) {
  gt_centers += o.gt_centers;
  measured_centers += o.measured_centers;
  matched += o.matched;
  false_positives += o.false_positives;
  plane_correct += o.plane_correct;
  plane_unidentified += o.plane_unidentified;
  points_triangulated += o.points_triangulated;
  points_off_surface += o.points_off_surface;
  complete += o.complete;
  return *this;
}

nlohmann::json ErrorStats::ToJson() const {
  if (n == 0) return {{"n", 0}, {"rms", nullptr}, {"median", nullptr}, {"p95", nullptr}, {"max", nullptr}};
  return {{"n", n}, {"rms", Num(rms)}, {"median", Num(median)}, {"p95", Num(p95)}, {"max", Num(max)}};
}

nlohmann::json EvalSummary::ToJson() const {
  nlohmann::json center = center_px.ToJson();
  center["bias"] = center_px.n > 0 ? Num(center_bias_px) : nlohmann::json(nullptr);
  const EvalCounts& c = counts;
  nlohmann::json j = {{"stripe_center_error_px", center},
          {"detection_rate", Num(detection_rate)},
          {"false_positives", {{"count", c.false_positives}, {"rate", Num(false_positive_rate)}}},
          {"plane_id_accuracy", Num(plane_id_accuracy)},
          {"plane_unidentified", c.plane_unidentified},
          {"point_error_mm", point_mm.ToJson()},
          {"completeness", Num(completeness)},
          {"counts",
           {{"gt_centers", c.gt_centers},
            {"measured_centers", c.measured_centers},
            {"matched", c.matched},
            {"plane_correct", c.plane_correct},
            {"points_triangulated", c.points_triangulated},
            {"points_off_surface", c.points_off_surface},
            {"complete", c.complete}}}};
  if (stitched_point_mm.n > 0) j["stitched_point_error_mm"] = stitched_point_mm.ToJson();
  if (pose_offset_mm.n > 0) j["stitch_pose_offset_mm"] = pose_offset_mm.ToJson();
  return j;
}

nlohmann::json RunMetrics::ToJson() const {
  nlohmann::json j = {{"run", run_dir.string()},
                      {"options",
                       {{"max_match_px", options.max_match_px},
                        {"completeness_mm", options.completeness_mm},
                        {"frames_begin", options.frames_begin},
                        {"frames_end", options.frames_end}}},
                      {"axis", axis == SearchAxis::kRows ? "rows" : "cols"},
                      {"frames_evaluated", frames.size()},
                      {"frames_skipped", frames_skipped},
                      {"point_error_method", PointErrorMethod()}};
  if (!point_error_note.empty()) j["point_error_note"] = point_error_note;
  j.update(total.ToJson());
  j["planes"] = PlanesToJson(planes);
  nlohmann::json fa = nlohmann::json::array();
  for (const FrameMetrics& f : frames) {
    nlohmann::json fj = {{"index", f.index},
                         {"point_error_available", f.has_surface},
                         {"point_error_method", f.surface_from_scene ? "scene" : f.has_surface ? "gt_buffers" : "none"}};
    fj.update(f.total.ToJson());
    fj["planes"] = PlanesToJson(f.planes);
    fa.push_back(fj);
  }
  j["frames"] = fa;
  return j;
}

std::string RunMetrics::PointErrorMethod() const {
  size_t scene = 0, buffers = 0;
  for (const FrameMetrics& f : frames) {
    if (f.surface_from_scene) {
      ++scene;
    } else if (f.has_surface) {
      ++buffers;
    }
  }
  if (scene == 0 && buffers == 0) return "none";
  if (buffers == 0) return "scene";
  if (scene == 0) return "gt_buffers";
  return "mixed";
}

}  // namespace lt
