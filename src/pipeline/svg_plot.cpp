#include "pipeline/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace lt {

namespace {

std::string F(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string TickText(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// One axis: data range to pixels, linear or log10.
struct Axis {
  double lo = 0, hi = 1;
  bool log = false;
  double p0 = 0, p1 = 1;  // pixel positions of lo and hi

  double T(double v) const { return log ? std::log10(v) : v; }
  double Map(double v) const { return p0 + (T(v) - T(lo)) / (T(hi) - T(lo)) * (p1 - p0); }
  bool Valid(double v) const { return std::isfinite(v) && (!log || v > 0); }

  // Fits the range to the values (with a margin) and makes it non-empty.
  void Fit(double mn, double mx, bool from_zero) {
    if (!(mn <= mx)) mn = mx = log ? 1 : 0;
    if (log) {
      double a = std::floor(std::log10(mn)), b = std::ceil(std::log10(mx));
      if (b <= a) b = a + 1;
      lo = std::pow(10, a);
      hi = std::pow(10, b);
      return;
    }
    if (from_zero) mn = std::min(mn, 0.0);
    if (mx - mn < 1e-300) {
      const double d = std::max(std::abs(mx) * 0.1, 1e-12);
      mn -= d;
      mx += d;
    }
    const double margin = from_zero && mn == 0 ? 0 : 0.04 * (mx - mn);
    lo = mn - margin;
    hi = mx + 0.04 * (mx - mn);
  }

  std::vector<double> Ticks() const {
    std::vector<double> t;
    if (log) {
      for (double e = std::round(std::log10(lo)); e <= std::round(std::log10(hi)) + 1e-9; e += 1) t.push_back(std::pow(10, e));
      return t;
    }
    const double raw = (hi - lo) / 6;
    const double mag = std::pow(10, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
      if (m * mag >= raw) {
        step = m * mag;
        break;
      }
    }
    for (double v = std::ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) t.push_back(std::abs(v) < step * 1e-9 ? 0 : v);
    return t;
  }
};

struct Frame {
  Axis x, y;
  std::string svg;

  Frame(const SvgPlotOptions& o) {
    x.log = o.log_x;
    y.log = o.log_y;
    x.p0 = 64;
    x.p1 = o.width - 16;
    y.p0 = o.height - 48;
    y.p1 = 28;
    svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(o.width) + "\" height=\"" +
          std::to_string(o.height) + "\" viewBox=\"0 0 " + std::to_string(o.width) + " " + std::to_string(o.height) +
          "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + F(o.width / 2.0) + "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">" +
           SvgEscape(o.title) + "</text>\n";
  }

  void DrawAxes(const SvgPlotOptions& o) {
    for (double t : x.Ticks()) {
      const double px = x.Map(t);
      svg += "<line x1=\"" + F(px) + "\" y1=\"" + F(y.p1) + "\" x2=\"" + F(px) + "\" y2=\"" + F(y.p0) +
             "\" stroke=\"#ddd\"/><text x=\"" + F(px) + "\" y=\"" + F(y.p0 + 14) + "\" text-anchor=\"middle\">" +
             TickText(t) + "</text>\n";
    }
    for (double t : y.Ticks()) {
      const double py = y.Map(t);
      svg += "<line x1=\"" + F(x.p0) + "\" y1=\"" + F(py) + "\" x2=\"" + F(x.p1) + "\" y2=\"" + F(py) +
             "\" stroke=\"#ddd\"/><text x=\"" + F(x.p0 - 4) + "\" y=\"" + F(py + 4) + "\" text-anchor=\"end\">" +
             TickText(t) + "</text>\n";
    }
    svg += "<rect x=\"" + F(x.p0) + "\" y=\"" + F(y.p1) + "\" width=\"" + F(x.p1 - x.p0) + "\" height=\"" +
           F(y.p0 - y.p1) + "\" fill=\"none\" stroke=\"#333\"/>\n";
    svg += "<text x=\"" + F((x.p0 + x.p1) / 2) + "\" y=\"" + F(o.height - 8.0) + "\" text-anchor=\"middle\">" +
           SvgEscape(o.x_label) + "</text>\n";
    svg += "<text transform=\"translate(14," + F((y.p0 + y.p1) / 2) + ") rotate(-90)\" text-anchor=\"middle\">" +
           SvgEscape(o.y_label) + "</text>\n";
  }

  std::string Finish() { return svg + "</svg>\n"; }
};

}  // namespace

std::string SvgEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out.push_back(c);
    }
  }
  return out;
}

std::string SvgColor(int i) {
  static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"};
  return colors[size_t(i) % 7];
}

std::string SvgPlot(const SvgPlotOptions& o, const std::vector<SvgSeries>& series) {
  Frame f(o);
  double xmn = std::numeric_limits<double>::infinity(), xmx = -xmn, ymn = xmn, ymx = -xmn;
  for (const SvgSeries& s : series) {
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!f.x.Valid(s.x[i]) || !f.y.Valid(s.y[i])) continue;
      xmn = std::min(xmn, s.x[i]);
      xmx = std::max(xmx, s.x[i]);
      ymn = std::min(ymn, s.y[i]);
      ymx = std::max(ymx, s.y[i]);
    }
  }
  f.x.Fit(xmn, xmx, false);
  f.y.Fit(ymn, ymx, o.y_from_zero);
  if (o.x_min) f.x.lo = *o.x_min;
  if (o.x_max) f.x.hi = *o.x_max;
  if (o.y_min) f.y.lo = *o.y_min;
  if (o.y_max) f.y.hi = *o.y_max;
  auto inside = [&](double xv, double yv) {
    return f.x.Valid(xv) && f.y.Valid(yv) && (!o.x_min || xv >= *o.x_min) && (!o.x_max || xv <= *o.x_max) &&
           (!o.y_min || yv >= *o.y_min) && (!o.y_max || yv <= *o.y_max);
  };
  f.DrawAxes(o);
  int legend = 0;
  for (const SvgSeries& s : series) {
    std::string path;
    std::string marks;
    bool broken = true;
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!inside(s.x[i], s.y[i])) {
        broken = true;
        continue;
      }
      const double px = f.x.Map(s.x[i]), py = f.y.Map(s.y[i]);
      path += (path.empty() ? "M" : broken ? " M" : " L") + F(px) + " " + F(py);
      broken = false;
      if (s.markers) marks += "<circle cx=\"" + F(px) + "\" cy=\"" + F(py) + "\" r=\"" + F(s.marker_radius) + "\"/>";
      if (i < s.labels.size() && !s.labels[i].empty()) {
        const bool right_edge = px > f.x.p1 - 90;  // keep labels inside the plot
        marks += "<text x=\"" + F(right_edge ? px - 4 : px + 4) + "\" y=\"" + F(py - 4) + "\" font-size=\"9\" fill=\"#333\"" +
                 (right_edge ? " text-anchor=\"end\"" : "") + ">" + SvgEscape(s.labels[i]) + "</text>";
      }
    }
    if (s.line && !path.empty()) {
      f.svg += "<path d=\"" + path + "\" fill=\"none\" stroke=\"" + s.color + "\" stroke-width=\"1.5\"" +
               (s.dashed ? std::string(" stroke-dasharray=\"6 4\"") : std::string()) + "/>\n";
    }
    if (!marks.empty()) f.svg += "<g fill=\"" + s.color + "\" fill-opacity=\"0.7\">" + marks + "</g>\n";
    if (!s.name.empty()) {
      const double ly = f.y.p1 + 14 + 14 * legend++;
      f.svg += "<rect x=\"" + F(f.x.p1 - 190) + "\" y=\"" + F(ly - 8) + "\" width=\"10\" height=\"10\" fill=\"" +
               s.color + "\"/><text x=\"" + F(f.x.p1 - 176) + "\" y=\"" + F(ly + 1) + "\">" + SvgEscape(s.name) +
               "</text>\n";
    }
  }
  return f.Finish();
}

std::string SvgHistogram(const SvgPlotOptions& options, const std::vector<double>& values, int bins,
                         const std::string& color) {
  SvgPlotOptions o = options;
  o.log_x = o.log_y = false;
  std::vector<double> v;
  for (double x : values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  o.title += " (n = " + std::to_string(v.size()) + ")";
  bins = std::max(bins, 1);
  Frame f(o);
  double mn = v.empty() ? 0 : *std::min_element(v.begin(), v.end());
  double mx = v.empty() ? 1 : *std::max_element(v.begin(), v.end());
  if (mx - mn < 1e-12) {
    mn -= 0.5;
    mx += 0.5;
  }
  std::vector<int64_t> count(size_t(bins), 0);
  const double width = (mx - mn) / bins;
  for (double x : v) count[size_t(std::clamp(int((x - mn) / width), 0, bins - 1))]++;
  const int64_t top = v.empty() ? 1 : *std::max_element(count.begin(), count.end());
  f.x.lo = mn;
  f.x.hi = mx;
  f.y.Fit(0, double(top), true);
  f.DrawAxes(o);
  f.svg += "<g fill=\"" + color + "\">";
  for (int b = 0; b < bins; ++b) {
    if (count[size_t(b)] == 0) continue;
    const double x0 = f.x.Map(mn + b * width), x1 = f.x.Map(mn + (b + 1) * width), y1 = f.y.Map(double(count[size_t(b)]));
    f.svg += "<rect x=\"" + F(x0) + "\" y=\"" + F(y1) + "\" width=\"" + F(std::max(x1 - x0 - 0.5, 0.5)) +
             "\" height=\"" + F(f.y.p0 - y1) + "\"/>";
  }
  f.svg += "</g>\n";
  return f.Finish();
}

}  // namespace lt
