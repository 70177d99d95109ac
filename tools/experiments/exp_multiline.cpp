// Multi-line scan experiment (docs/experiments.md, "Multi-line scan"): how
// well plane identification numbers the stripes of a multi-sheet laser, and
// how accurate the triangulated points are, against the renderer's exact
// stripe centres.
//
//   exp_multiline OUT_DIR RUN_DIR METHOD [METHOD ...] [--lines FIRST,LAST]
//
// RUN_DIR/centers_METHOD/ holds `lasertwin scan --method METHOD`'s centres
// (tools/experiments/multi_line.sh copies them there). Measured centres are
// paired with truth centres by the evaluation's matching (lt::MatchCenters:
// same scan line, nearest along it within kMatchPx, one-to-one); the plane is
// right when it equals the truth centre's sheet. Point error: 3D distance
// between the triangulated point and the truth centre's point, for points
// with a plane.
//
// Writes OUT_DIR/multi_line.csv (per method and sheet) and
// OUT_DIR/multi_line.svg (point error along the stripes per sheet, first method).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "core/atomic_file.h"
#include "exp_common.h"
#include "pipeline/eval_metrics.h"
#include "pipeline/ground_truth.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan_output.h"
#include "pipeline/svg_plot.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

constexpr double kMatchPx = 3.0;

struct SheetStats {
  int truth = 0, detected = 0, matched = 0, identified = 0, correct = 0, spurious = 0;
  std::vector<double> errors_mm;
};

int Run(int argc, char** argv) {
  CLI::App app{"Multi-line scan: plane identification accuracy and point errors per sheet"};
  std::string out, run;
  std::vector<std::string> methods;
  app.add_option("OUT_DIR", out, "Folder for multi_line.csv and .svg")->required();
  app.add_option("RUN_DIR", run, "Rendered run with centers_METHOD/ folders")->required();
  app.add_option("METHODS", methods, "Extraction methods scanned (multicom, steger)")->required();
  std::vector<int> lines;
  app.add_option("--lines", lines, "FIRST,LAST: count only truth centres on these scan lines (the scan's ROI)")
      ->expected(2)
      ->delimiter(',');
  CLI11_PARSE(app, argc, argv);

  std::vector<RunFrame> frames = ReadRunManifest(run);
  fs::create_directories(out);
  std::ostringstream csv;
  csv << "method,sheet,truth_centres,detected,plane_id_accuracy,unidentified,spurious,median_mm,p95_mm,max_mm\n";
  std::vector<SvgSeries> series;
  std::printf("%-9s %-5s %6s %9s %9s %8s %9s %9s %9s %9s\n", "method", "sheet", "truth", "detected", "plane ok",
              "no plane", "spurious", "median", "95%", "max");
  for (size_t m = 0; m < methods.size(); ++m) {
    std::map<int, SheetStats> stats;  // sheet -1: all
    std::map<int, SvgSeries> per_sheet;
    for (const RunFrame& f : frames) {
      if (!f.IsLaserFrame() || !f.gt_centers) continue;
      const SearchAxis axis = f.gt_axis ? *f.gt_axis : SearchAxis::kRows;
      const bool cols = axis == SearchAxis::kCols;
      auto line_of = [&](double u, double v) { return int(std::lround(cols ? u : v)); };
      char name[32];
      std::snprintf(name, sizeof name, "%06lld.csv", static_cast<long long>(f.index));
      const fs::path measured_file = fs::path(run) / ("centers_" + methods[m]) / name;
      std::vector<TruthCenter> truth = ReadTruthCentersCsv(*f.gt_centers);
      if (lines.size() == 2)
        std::erase_if(truth, [&](const TruthCenter& c) {
          const int l = line_of(c.u, c.v);
          return l < lines[0] || l > lines[1];
        });
      const std::vector<ScanPoint> measured = ReadScanCsv(measured_file);
      const std::vector<int> match = MatchCenters(axis, truth, measured, kMatchPx, *f.gt_centers, measured_file);
      std::vector<bool> hit(truth.size(), false);
      for (const TruthCenter& t : truth) ++stats[t.plane].truth, ++stats[-1].truth;
      for (size_t k = 0; k < measured.size(); ++k) {
        if (match[k] < 0) {
          ++stats[-1].spurious;
          continue;
        }
        const TruthCenter& t = truth[size_t(match[k])];
        const StripePoint& c = measured[k].pixel;
        const std::optional<Eigen::Vector3d>& p = measured[k].p_in_cam;
        for (int key : {t.plane, -1}) {
          SheetStats& s = stats[key];
          ++s.matched;
          s.detected += hit[size_t(match[k])] ? 0 : 1;
          if (c.plane >= 0) {
            ++s.identified;
            s.correct += c.plane == t.plane;
          }
          if (c.plane == t.plane && p) s.errors_mm.push_back((*p - t.p_in_cam).norm() * 1e3);
        }
        hit[size_t(match[k])] = true;
        if (c.plane == t.plane && p) {
          SvgSeries& ps = per_sheet[t.plane];
          ps.x.push_back(line_of(c.u, c.v)), ps.y.push_back((*p - t.p_in_cam).norm() * 1e3);
        }
      }
    }
    for (auto& [sheet, s] : stats) {
      const double acc = s.matched ? double(s.correct) / s.matched : NAN;
      const std::string label = sheet < 0 ? "all" : std::to_string(sheet);
      const double mx = s.errors_mm.empty() ? NAN : *std::max_element(s.errors_mm.begin(), s.errors_mm.end());
      csv << methods[m] << "," << label << "," << s.truth << "," << s.detected << "," << acc << ","
          << s.matched - s.identified << "," << s.spurious << "," << Quantile(s.errors_mm, 0.5) << ","
          << Quantile(s.errors_mm, 0.95) << "," << mx << "\n";
      std::printf("%-9s %-5s %6d %8.1f%% %8.2f%% %8d %9d %9.3f %9.3f %9.3f\n", methods[m].c_str(), label.c_str(),
                  s.truth, s.truth ? 100.0 * s.detected / s.truth : NAN, 100 * acc, s.matched - s.identified,
                  s.spurious, Quantile(s.errors_mm, 0.5), Quantile(s.errors_mm, 0.95), mx);
    }
    if (m == 0)
      for (auto& [sheet, ps] : per_sheet) {
        ps.name = methods[m] + " sheet " + std::to_string(sheet);
        ps.color = SvgColor(sheet);
        series.push_back(ps);
      }
  }
  WriteFileAtomically(fs::path(out) / "multi_line.csv", csv.str());
  SvgPlotOptions po;
  po.height = 420;
  po.title = "Point error along the stripes, per laser sheet (" + methods[0] + ")";
  po.x_label = "scan line (image column)";
  po.y_label = "3D error (mm)";
  po.y_min = 0;
  WriteFileAtomically(fs::path(out) / "multi_line.svg", SvgPlot(po, series));
  std::cout << "wrote " << out << "/multi_line.csv and multi_line.svg\n";
  return 0;
}

}  // namespace
}  // namespace lt

int main(int argc, char** argv) { return lt::ExperimentMain("exp_multiline", lt::Run, argc, argv); }
