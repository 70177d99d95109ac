// Multi-line scan experiment (docs/experiments.md, "Multi-line scan"): how
// well plane identification numbers the stripes of a multi-sheet laser, and
// how accurate the triangulated points are, against the renderer's exact
// stripe centres.
//
//   exp_multiline OUT_DIR RUN_DIR METHOD [METHOD ...] [--lines FIRST,LAST]
//
// RUN_DIR/centers_METHOD/ holds `lasertwin scan --method METHOD`'s centres
// (tools/experiments/multi_line.sh copies them there). Each measured centre is
// matched to the truth centre on the same scan line nearest to it along the
// line, within kMatchPx; the plane is right when it equals the truth centre's
// sheet. Point error: 3D distance (world frame) between the triangulated point
// and the truth centre's point, for points with a plane.
//
// Writes OUT_DIR/multi_line.csv (per method and sheet) and
// OUT_DIR/multi_line.svg (point error along the stripes per sheet, first method).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>

#include "centre_matching.h"
#include "core/atomic_file.h"
#include "pipeline/run_folder_reader.h"
#include "svg_plot.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

constexpr double kMatchPx = 3.0;

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

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
  std::vector<PlotSeries> series;
  std::printf("%-9s %-5s %6s %9s %9s %8s %9s %9s %9s %9s\n", "method", "sheet", "truth", "detected", "plane ok",
              "no plane", "spurious", "median", "95%", "max");
  for (size_t m = 0; m < methods.size(); ++m) {
    std::map<int, SheetStats> stats;  // sheet -1: all
    std::map<int, PlotSeries> per_sheet;
    for (const RunFrame& f : frames) {
      if (!f.IsLaserFrame() || !f.gt_centers) continue;
      const bool cols = f.gt_axis && *f.gt_axis == SearchAxis::kCols;
      char name[32];
      std::snprintf(name, sizeof name, "%06lld.csv", static_cast<long long>(f.index));
      std::vector<FrameCentre> truth = ReadFrameCentres(*f.gt_centers, cols);
      if (lines.size() == 2)
        std::erase_if(truth, [&](const FrameCentre& c) { return c.line < lines[0] || c.line > lines[1]; });
      std::vector<FrameCentre> measured = ReadFrameCentres(fs::path(run) / ("centers_" + methods[m]) / name, cols);
      const std::vector<int> match = MatchToTruth(measured, truth, kMatchPx);
      std::vector<bool> hit(truth.size(), false);
      for (const FrameCentre& t : truth) ++stats[t.plane].truth, ++stats[-1].truth;
      for (size_t k = 0; k < measured.size(); ++k) {
        if (match[k] < 0) {
          ++stats[-1].spurious;
          continue;
        }
        const FrameCentre& t = truth[size_t(match[k])];
        const FrameCentre& c = measured[k];
        for (int key : {t.plane, -1}) {
          SheetStats& s = stats[key];
          ++s.matched;
          s.detected += hit[size_t(match[k])] ? 0 : 1;
          if (c.plane >= 0) {
            ++s.identified;
            s.correct += c.plane == t.plane;
          }
          if (c.plane == t.plane && c.p_world.allFinite())
            s.errors_mm.push_back((c.p_world - t.p_world).norm() * 1e3);
        }
        hit[size_t(match[k])] = true;
        if (c.plane == t.plane && c.p_world.allFinite()) {
          PlotSeries& ps = per_sheet[t.plane];
          ps.x.push_back(c.line), ps.y.push_back((c.p_world - t.p_world).norm() * 1e3);
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
        ps.color = PlotColor(sheet);
        ps.line = false;
        series.push_back(ps);
      }
  }
  WriteFileAtomically(fs::path(out) / "multi_line.csv", csv.str());
  PlotOptions po;
  po.title = "Point error along the stripes, per laser sheet (" + methods[0] + ")";
  po.x_label = "scan line (image column)";
  po.y_label = "3D error (mm)";
  po.y_min = 0;
  WriteFileAtomically(fs::path(out) / "multi_line.svg", SvgLinePlot(po, series));
  std::cout << "wrote " << out << "/multi_line.csv and multi_line.svg\n";
  return 0;
}

}  // namespace
}  // namespace lt

int main(int argc, char** argv) {
  try {
    return lt::Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "exp_multiline: error: " << e.what() << "\n";
    return 2;
  }
}
