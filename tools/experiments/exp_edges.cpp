// Extraction at sharp edges (docs/experiments.md): stripe centre errors of
// several extraction methods against the renderer's exact centres, split
// into scan lines near an edge and scan lines on smooth surface.
//
//   exp_edges OUT_DIR RUN_DIR METHOD [METHOD ...]
//
// RUN_DIR is a rendered run; RUN_DIR/centers_METHOD/ holds `lasertwin scan
// --method METHOD`'s centres of its laser frames (the driver script
// tools/experiments/sharp_edges.sh copies each scan's centers/ there). Each
// measured point is paired with a truth centre of the same scan line
// (gt/NNNNNN_centers.csv) by the evaluation's matching (lt::MatchCenters:
// nearest along the line, one-to-one, closest pairs first, no distance
// limit); unpaired points are "spurious". A scan line is an edge line when,
// within kEdgeLines lines, the truth stripe jumps (> 1 px between
// neighbouring lines: a depth discontinuity), bends (second difference >
// 0.1 px: a crease between faces), splits (two truth centres on one line) or
// is missing (shadow or occlusion); every other line is smooth.
//
// Writes OUT_DIR/sharp_edges.csv (per method and class: points, detection
// rate, median / 95% / max error in px, spurious points) and
// OUT_DIR/sharp_edges.svg (signed error along the stripe per method).
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
#include "core/error.h"
#include "pipeline/eval_metrics.h"
#include "pipeline/ground_truth.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/scan_output.h"
#include "pipeline/svg_plot.h"

namespace lt {
namespace {

namespace fs = std::filesystem;

constexpr int kEdgeLines = 3;

struct ClassStats {
  std::vector<double> errors;
  int truth_lines = 0, found_lines = 0, spurious = 0;
};

int Run(int argc, char** argv) {
  CLI::App app{"Extraction at sharp edges: centre errors per method, edge vs smooth scan lines"};
  std::string out, run;
  std::vector<std::string> methods;
  app.add_option("OUT_DIR", out, "Folder for sharp_edges.csv and .svg")->required();
  app.add_option("RUN_DIR", run, "Rendered run with centers_METHOD/ folders")->required();
  app.add_option("METHODS", methods, "Extraction methods scanned (max, com, multicom, steger)")->required();
  CLI11_PARSE(app, argc, argv);

  std::vector<RunFrame> frames = ReadRunManifest(run);
  fs::create_directories(out);
  std::ostringstream csv;
  csv << "method,class,points,truth_lines,detection_rate,median_px,p95_px,max_px,spurious\n";
  std::vector<SvgSeries> series;
  std::printf("%-8s %-7s %7s %9s %9s %8s %8s %9s\n", "method", "class", "points", "detected", "median", "95%",
              "max", "spurious");
  for (size_t m = 0; m < methods.size(); ++m) {
    std::map<std::string, ClassStats> stats;
    SvgSeries ser;
    ser.name = methods[m];
    ser.color = SvgColor(int(m));
    for (const RunFrame& f : frames) {
      if (!f.IsLaserFrame() || !f.gt_centers) continue;
      const SearchAxis axis = f.gt_axis ? *f.gt_axis : SearchAxis::kRows;
      const bool cols = axis == SearchAxis::kCols;
      auto line_of = [&](double u, double v) { return int(std::lround(cols ? u : v)); };
      auto along = [&](double u, double v) { return cols ? v : u; };
      char name[32];
      std::snprintf(name, sizeof name, "%06lld.csv", static_cast<long long>(f.index));
      const fs::path measured_file = fs::path(run) / ("centers_" + methods[m]) / name;
      const std::vector<TruthCenter> truth = ReadTruthCentersCsv(*f.gt_centers);
      const std::vector<ScanPoint> measured = ReadScanCsv(measured_file);
      std::map<int, std::vector<double>> truth_by_line;
      for (const TruthCenter& c : truth) truth_by_line[line_of(c.u, c.v)].push_back(along(c.u, c.v));
      if (truth_by_line.empty()) continue;
      const int first = truth_by_line.begin()->first, last = truth_by_line.rbegin()->first;
      // Lines where the truth stripe has a feature; edge lines lie within kEdgeLines of one.
      std::vector<int> feature;
      auto single = [&](int line) -> std::optional<double> {
        auto it = truth_by_line.find(line);
        if (it == truth_by_line.end() || it->second.size() != 1) return std::nullopt;
        return it->second[0];
      };
      for (int l = first; l <= last; ++l) {
        auto a = single(l), b = single(l + 1), z = single(l - 1);
        bool f1 = !a;  // missing or split
        if (a && b && std::abs(*b - *a) > 1.0) f1 = true;
        if (a && b && z && std::abs(*b - 2 * *a + *z) > 0.1) f1 = true;
        if (f1) feature.push_back(l);
      }
      auto is_edge = [&](int line) {
        auto it = std::lower_bound(feature.begin(), feature.end(), line - kEdgeLines);
        return it != feature.end() && *it <= line + kEdgeLines;
      };
      const std::vector<int> match = MatchCenters(axis, truth, measured, INFINITY, *f.gt_centers, measured_file);
      std::map<int, bool> found;
      for (size_t k = 0; k < measured.size(); ++k) {
        const StripePoint& c = measured[k].pixel;
        const int line = line_of(c.u, c.v);
        const std::string cls = is_edge(line) ? "edge" : "smooth";
        if (match[k] < 0) {
          ++stats[cls].spurious;
          continue;
        }
        const TruthCenter& t = truth[size_t(match[k])];
        const double signed_err = along(c.u, c.v) - along(t.u, t.v);
        stats[cls].errors.push_back(std::abs(signed_err));
        found[line] = true;
        ser.x.push_back(line), ser.y.push_back(signed_err);
      }
      for (auto& [line, pos] : truth_by_line) {
        const std::string cls = is_edge(line) ? "edge" : "smooth";
        ++stats[cls].truth_lines;
        stats[cls].found_lines += found.count(line) ? 1 : 0;
      }
    }
    for (const char* cls : {"smooth", "edge"}) {
      const ClassStats& s = stats[cls];
      double rate = s.truth_lines ? double(s.found_lines) / s.truth_lines : NAN;
      double med = Quantile(s.errors, 0.5), p95 = Quantile(s.errors, 0.95),
             mx = s.errors.empty() ? NAN : *std::max_element(s.errors.begin(), s.errors.end());
      csv << methods[m] << "," << cls << "," << s.errors.size() << "," << s.truth_lines << "," << rate << "," << med
          << "," << p95 << "," << mx << "," << s.spurious << "\n";
      std::printf("%-8s %-7s %7zu %8.1f%% %9.3f %8.3f %8.3f %9d\n", methods[m].c_str(), cls, s.errors.size(),
                  100 * rate, med, p95, mx, s.spurious);
    }
    series.push_back(ser);
  }
  WriteFileAtomically(fs::path(out) / "sharp_edges.csv", csv.str());
  SvgPlotOptions po;
  po.height = 420;
  po.title = "Stripe centre error along the stripe (truth: exact centres)";
  po.x_label = "scan line (image column)";
  po.y_label = "measured - true centre (px)";
  po.y_min = -3, po.y_max = 3;
  WriteFileAtomically(fs::path(out) / "sharp_edges.svg", SvgPlot(po, series));
  std::cout << "wrote " << out << "/sharp_edges.csv and sharp_edges.svg\n";
  return 0;
}

}  // namespace
}  // namespace lt

int main(int argc, char** argv) { return lt::ExperimentMain("exp_edges", lt::Run, argc, argv); }
