// `lasertwin eval RUN_DIR [--max-match-px P] [--completeness-mm D] [--frames A:B]
// [--gt-buffers] [--quiet]`: compares the measured stripe centres and points of a
// scanned run with its ground truth; writes RUN_DIR/metrics.json and
// RUN_DIR/report.html (docs/evaluation.md) and prints the headline metrics.
// A point's error is its distance to the surfaces of the run's scene.json,
// rebuilt at each frame's time (scene/surface_distance.h), when the run has one;
// else (none, or it does not load; or with --gt-buffers) to the surfaces the
// ground-truth buffers hold, and the output says so.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>

#include "core/error.h"
#include "core/frame_range.h"
#include "pipeline/eval_metrics.h"
#include "pipeline/eval_report.h"
#include "tools/lasertwin/command.h"
#include "tools/lasertwin/run_scene_distance.h"

namespace lt::cli {
namespace {

struct EvalArgs {
  std::string run_dir;
  std::string frames;
  bool quiet = false;
  bool gt_buffers = false;
  EvalOptions options;
};

const char* MethodText(const std::string& method) {
  if (method == "scene") return "to the scene's surfaces (scene.json)";
  if (method == "gt_buffers") return "to the surfaces the pixels see (ground-truth buffers)";
  if (method == "mixed") return "to the scene's surfaces, or the ground-truth buffers";
  return "not available (no ground-truth buffers)";
}

std::string Pct(const std::optional<double>& v) {
  if (!v) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f%%", *v * 100);
  return buf;
}

std::string Val(const ErrorStats& s, double ErrorStats::*field, const char* format) {
  if (s.n == 0) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, format, s.*field);
  return buf;
}

void Run(EvalArgs& a) {
  if (!a.frames.empty()) {
    const FrameRange r = FrameRange::Parse(a.frames);
    a.options.frames_begin = r.begin, a.options.frames_end = r.EndOrMinusOne();
  }
  std::string why_not = "--gt-buffers: points are scored on the ground-truth buffers";
  const SurfaceDistanceSource distance = a.gt_buffers ? SurfaceDistanceSource() : RunSceneDistance(a.run_dir, &why_not);
  RunMetrics m = EvaluateRun(a.run_dir, a.options, distance);
  if (!distance) m.point_error_note = why_not;
  const auto json = WriteMetricsJson(a.run_dir, m);
  const auto report = WriteEvalReport(a.run_dir, m);
  if (a.quiet) return;
  const EvalSummary& t = m.total;
  std::cout << "evaluated " << m.frames.size() << " laser frame" << (m.frames.size() == 1 ? "" : "s") << ": "
            << t.counts.gt_centers << " true centres, " << t.counts.measured_centers << " measured\n"
            << "  stripe centre error  rms " << Val(t.center_px, &ErrorStats::rms, "%.4f") << " px, median "
            << Val(t.center_px, &ErrorStats::median, "%.4f") << ", p95 " << Val(t.center_px, &ErrorStats::p95, "%.4f")
            << ", max " << Val(t.center_px, &ErrorStats::max, "%.4f") << " (" << t.center_px.n << " pairs)\n"
            << "  detection rate       " << Pct(t.detection_rate) << "\n"
            << "  false positives      " << t.counts.false_positives << " (" << Pct(t.false_positive_rate) << ")\n"
            << "  plane id accuracy    " << Pct(t.plane_id_accuracy) << "\n"
            << "  point error          rms " << Val(t.point_mm, &ErrorStats::rms, "%.4f") << " mm, median "
            << Val(t.point_mm, &ErrorStats::median, "%.4f") << ", p95 " << Val(t.point_mm, &ErrorStats::p95, "%.4f")
            << ", max " << Val(t.point_mm, &ErrorStats::max, "%.4f") << " (" << t.point_mm.n << " points)\n"
            << "  point error measured " << MethodText(m.PointErrorMethod()) << "\n"
            << (m.point_error_note.empty() ? "" : "  (" + m.point_error_note + ")\n");
  if (t.stitched_point_mm.n > 0) {
    // The points where scan placed them in the world: the poses it used (a hand-eye
    // calibration, a pose file) against the manifest's.
    std::cout << "  stitched point error rms " << Val(t.stitched_point_mm, &ErrorStats::rms, "%.4f") << " mm, median "
              << Val(t.stitched_point_mm, &ErrorStats::median, "%.4f") << ", p95 "
              << Val(t.stitched_point_mm, &ErrorStats::p95, "%.4f") << ", max "
              << Val(t.stitched_point_mm, &ErrorStats::max, "%.4f") << " (" << t.stitched_point_mm.n
              << " world points as scan placed them)\n";
  }
  if (t.pose_offset_mm.n > 0) {
    // The same points against the manifest's pose: the stitching's error along surfaces too.
    std::cout << "  stitch pose offset   rms " << Val(t.pose_offset_mm, &ErrorStats::rms, "%.4f") << " mm, median "
              << Val(t.pose_offset_mm, &ErrorStats::median, "%.4f") << ", p95 "
              << Val(t.pose_offset_mm, &ErrorStats::p95, "%.4f") << ", max "
              << Val(t.pose_offset_mm, &ErrorStats::max, "%.4f") << " (scan's world point against the true pose's)\n";
  }
  std::cout << "  completeness         " << Pct(t.completeness) << " (within " << m.options.completeness_mm << " mm)\n"
            << "wrote " << json.string() << "\nreport " << report.string() << "\n";
}

void Add(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto* cmd = app.add_subcommand("eval", "Compare a scanned run with its ground truth (metrics.json, report.html)");
  cmd->add_option("RUN_DIR", args->run_dir, "Run folder, rendered and scanned (lasertwin render, lasertwin scan)")
      ->required();
  cmd->add_option("--max-match-px", args->options.max_match_px,
                  "Largest distance along the scan line between a true and a measured centre that pair")
      ->capture_default_str();
  cmd->add_option("--completeness-mm", args->options.completeness_mm,
                  "A true stripe point is reconstructed when its measured point is within this distance")
      ->capture_default_str();
  cmd->add_option("--frames", args->frames, "Frames to evaluate: A:B (A inclusive, B exclusive), A:, :B or N");
  cmd->add_flag("--gt-buffers", args->gt_buffers,
                "Score points against the ground-truth depth and normal buffers (the surfaces pixels see), not "
                "against the surfaces of the run's scene.json (the default when it loads)");
  cmd->add_flag("--quiet", args->quiet, "Print nothing");
  cmd->callback([args] { Run(*args); });
}

}  // namespace

LT_REGISTER_COMMAND("eval", Add);

}  // namespace lt::cli
