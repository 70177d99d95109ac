// A minimal SVG line plot for the experiment reports (docs/experiments.md):
// linear axes with ticks, one polyline and/or markers per series, a legend.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace lt {

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;  // NaN y values break the line and draw no marker
  std::string color = "#1f77b4";
  bool line = true;
  bool markers = true;
  bool dashed = false;
};

struct PlotOptions {
  std::string title, x_label, y_label;
  int width = 640, height = 420;
  std::optional<double> x_min, x_max, y_min, y_max;  // default: the data's range
};

std::string SvgLinePlot(const PlotOptions& options, const std::vector<PlotSeries>& series);

// Distinct colours for series i = 0, 1, ...
std::string PlotColor(int i);

}  // namespace lt
