// Small self-contained SVG charts (no scripts, no external files) for the
// evaluation report and the run-time sweep: scatter/line plots with linear or
// logarithmic axes, and histograms. Each function returns one <svg> element.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace lt {

struct SvgSeries {
  std::string name;             // legend entry ("" for none)
  std::string color = "#1f77b4";
  std::vector<double> x, y;     // same length; non-finite points (and <= 0 on log axes) are skipped
  bool markers = true;          // a dot per point
  bool line = false;            // join the points in order (a skipped point breaks the line)
  bool dashed = false;          // dashed line
  double marker_radius = 2.5;   // pixels
  std::vector<std::string> labels;  // optional, one per point: drawn beside it
};

struct SvgPlotOptions {
  std::string title, x_label, y_label;
  int width = 640, height = 360;  // pixels
  bool log_x = false, log_y = false;
  bool y_from_zero = false;       // linear y axis starts at 0
  std::optional<double> x_min = {}, x_max = {}, y_min = {}, y_max = {};  // fixed axis ends (default: the data's range);
                                                     // points outside are skipped
};

// XML-escapes text (& < > " ').
std::string SvgEscape(const std::string& text);

// Distinct colours for series i = 0, 1, ...
std::string SvgColor(int i);

// A scatter / line plot of the series.
std::string SvgPlot(const SvgPlotOptions& options, const std::vector<SvgSeries>& series);

// A histogram of the values over `bins` equal bins between their minimum and
// maximum (non-finite values skipped); the title gets the count.
std::string SvgHistogram(const SvgPlotOptions& options, const std::vector<double>& values, int bins = 40,
                         const std::string& color = "#1f77b4");

}  // namespace lt
