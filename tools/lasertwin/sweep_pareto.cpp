// The Pareto plot of `lasertwin sweep` (sweep_pareto.h): which configurations change
// the physics, reading a sweep.csv's points, and the SVG of error against time with
// its front. The sweep itself (configurations, runs, sweep.csv) is in cmd_sweep.cpp.
#include "tools/lasertwin/sweep_pareto.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>
#include <utility>

#include "core/error.h"
#include "core/text_fields.h"
#include "pipeline/svg_plot.h"

namespace lt::cli {

namespace fs = std::filesystem;

// Configurations that change the light transport (fewer or more bounces,
// subsurface scattering off) rather than how it is sampled: their error against
// the geometric ground truth moves because they drop or add effects a real
// scanner sees, so they are not candidates for the front.
bool ChangesPhysics(const std::string& factor) { return factor == "max_bounces" || factor == "subsurface"; }

// The points of a sweep.csv (--replot). Errors name the file and line.
std::vector<ParetoPoint> ReadParetoPoints(const fs::path& csv) {
  std::ifstream in(csv);
  if (!in) throw InputError(csv.string(), "cannot open (run the sweep first)");
  auto split = [](const std::string& line) {
    const std::vector<std::string_view> f = SplitFields(line, ',');
    return std::vector<std::string>(f.begin(), f.end());
  };
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> head = split(line);
  auto column = [&](const std::string& name) {
    auto it = std::find(head.begin(), head.end(), name);
    if (it == head.end()) throw InputError(csv.string() + ":1", "no column '" + name + "'");
    return size_t(it - head.begin());
  };
  const size_t name = column("name"), method = column("method"), factor = column("factor"), render = column("render_cpu_ms"),
               scan = column("scan_cpu_ms"), error = column("point_rms_mm"), detection = column("detection_rate");
  std::vector<std::pair<std::vector<std::string>, int>> rows;
  std::map<std::string, int> methods_per_run;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    rows.push_back({split(line), n});
    if (rows.back().first.size() != head.size()) throw InputError(csv.string() + ":" + std::to_string(n), "wrong field count");
    ++methods_per_run[rows.back().first[name]];
  }
  std::vector<ParetoPoint> out;
  for (const auto& [f, n] : rows) {
    if (f[error].empty()) continue;
    auto number = [&, n = n](const std::string& text) {
      const std::optional<double> v = ParseFiniteNumber(text);
      if (!v) throw InputError(csv.string() + ":" + std::to_string(n), "not a number: '" + text + "'");
      return *v;
    };
    out.push_back({f[name] + (methods_per_run[f[name]] > 1 ? "/" + f[method] : ""), number(f[render]) + number(f[scan]),
                   number(f[error]), f[detection].empty() ? 0.0 : number(f[detection]), ChangesPhysics(f[factor])});
  }
  return out;
}

// Error (point rms, mm) against time (render + scan CPU per frame), log x; the
// Pareto front is taken over the configurations that detect at least
// min_detection of the true centres (an error over few points is no bargain)
// and keep the scene's light transport (ChangesPhysics).
std::string ParetoSvg(const std::vector<ParetoPoint>& points, double min_detection, const std::string& title) {
  SvgSeries kept, dropped, physics, front;
  physics.name = "bounces / subsurface changed";
  physics.color = "#ff7f0e";
  char buf[64];
  std::snprintf(buf, sizeof buf, "detection >= %g%%", min_detection * 100);
  kept.name = buf;
  kept.color = "#1f77b4";
  std::snprintf(buf, sizeof buf, "detection < %g%%", min_detection * 100);
  dropped.name = buf;
  dropped.color = "#bbb";
  front.name = "Pareto front";
  front.color = "#d62728";
  front.line = true;
  front.marker_radius = 4;
  std::vector<ParetoPoint> candidates;
  for (const ParetoPoint& p : points) {
    const bool detected = p.detection >= min_detection;
    SvgSeries& s = !detected ? dropped : p.physics_changed ? physics : kept;
    s.x.push_back(p.time_ms);
    s.y.push_back(p.error_mm);
    s.labels.push_back(p.label);
    if (detected && !p.physics_changed) candidates.push_back(p);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const ParetoPoint& a, const ParetoPoint& b) { return std::tie(a.time_ms, a.error_mm) < std::tie(b.time_ms, b.error_mm); });
  double best = std::numeric_limits<double>::infinity();
  for (const ParetoPoint& p : candidates) {
    if (p.error_mm < best) {
      best = p.error_mm;
      front.x.push_back(p.time_ms);
      front.y.push_back(p.error_mm);
    }
  }
  SvgPlotOptions o{title, "CPU time per frame, render + scan (ms, log scale)", "point error rms (mm)"};
  o.width = 800;
  o.height = 460;
  o.log_x = true;
  o.y_from_zero = true;
  return SvgPlot(o, {dropped, physics, kept, front});
}

}  // namespace lt::cli
