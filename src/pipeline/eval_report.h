// The evaluation report, RUN/report.html (docs/evaluation.md): one
// self-contained page (inline SVG charts and base64 PNG frames, no scripts, no
// external files): a summary table, per-plane and per-frame tables, histograms
// of the centre and point errors, centre error against scan line and against
// depth, point error against depth, and a few frames (the worst and typical
// ones) with the measured (red crosses) and true (green dots) centres drawn over
// the camera image.
#pragma once

#include <filesystem>
#include <string>

#include "pipeline/eval_metrics.h"

namespace lt {

struct EvalReportOptions {
  int max_frames = 6;            // frames shown as images
  int max_scatter_points = 20000;  // scatter plots keep every k-th sample beyond this
  void Check() const;
};

// The page's HTML. Frame images are read through the run's manifest; a missing
// or unreadable image leaves its frame drawn without the picture.
std::string FormatEvalReport(const std::filesystem::path& run_dir, const RunMetrics& metrics,
                             const EvalReportOptions& options = {});
// Writes RUN/report.html atomically and returns its path.
std::filesystem::path WriteEvalReport(const std::filesystem::path& run_dir, const RunMetrics& metrics,
                                      const EvalReportOptions& options = {});

}  // namespace lt
