#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace lt {

namespace {

std::string Esc(const std::string& s) {
  std::string r;
  for (char c : s) {
    if (c == '<') r += "&lt;";
    else if (c == '>') r += "&gt;";
    else if (c == '&') r += "&amp;";
    else r += c;
  }
  return r;
}

// About five round tick values covering [lo, hi].
std::vector<double> Ticks(double lo, double hi) {
  double span = hi - lo;
  if (!(span > 0)) return {lo};
  double step = std::pow(10.0, std::floor(std::log10(span / 5)));
  for (double m : {1.0, 2.0, 5.0, 10.0})
    if (span / (step * m) <= 6) {
      step *= m;
      break;
    }
  std::vector<double> t;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * span; v += step)
    t.push_back(std::abs(v) < 1e-12 * span ? 0.0 : v);
  return t;
}

std::string Num(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}

}  // namespace

std::string PlotColor(int i) {
  static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2"};
  return colors[size_t(i) % 7];
}

std::string SvgLinePlot(const PlotOptions& o, const std::vector<PlotSeries>& series) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const PlotSeries& s : series)
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
      y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
    }
  if (!std::isfinite(x0)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (o.x_min) x0 = *o.x_min;
  if (o.x_max) x1 = *o.x_max;
  if (o.y_min) y0 = *o.y_min;
  if (o.y_max) y1 = *o.y_max;
  if (x1 <= x0) x1 = x0 + 1;
  if (y1 <= y0) y1 = y0 + 1;
  const double L = 70, R = 20, T = 36, B = 50;
  const double W = o.width - L - R, H = o.height - T - B;
  auto px = [&](double x) { return L + (x - x0) / (x1 - x0) * W; };
  auto py = [&](double y) { return T + H - (y - y0) / (y1 - y0) * H; };

  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << o.width << "\" height=\"" << o.height
    << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s << "<text x=\"" << o.width / 2 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">" << Esc(o.title)
    << "</text>\n";
  for (double t : Ticks(x0, x1)) {
    s << "<line x1=\"" << px(t) << "\" y1=\"" << T << "\" x2=\"" << px(t) << "\" y2=\"" << T + H
      << "\" stroke=\"#e0e0e0\"/>\n";
    s << "<text x=\"" << px(t) << "\" y=\"" << T + H + 16 << "\" text-anchor=\"middle\">" << Num(t) << "</text>\n";
  }
  for (double t : Ticks(y0, y1)) {
    s << "<line x1=\"" << L << "\" y1=\"" << py(t) << "\" x2=\"" << L + W << "\" y2=\"" << py(t)
      << "\" stroke=\"#e0e0e0\"/>\n";
    s << "<text x=\"" << L - 6 << "\" y=\"" << py(t) + 4 << "\" text-anchor=\"end\">" << Num(t) << "</text>\n";
  }
  s << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W << "\" height=\"" << H
    << "\" fill=\"none\" stroke=\"black\"/>\n";
  s << "<text x=\"" << L + W / 2 << "\" y=\"" << o.height - 12 << "\" text-anchor=\"middle\">" << Esc(o.x_label)
    << "</text>\n";
  s << "<text transform=\"translate(16," << T + H / 2 << ") rotate(-90)\" text-anchor=\"middle\">"
    << Esc(o.y_label) << "</text>\n";
  s << "<clipPath id=\"area\"><rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W << "\" height=\"" << H
    << "\"/></clipPath>\n<g clip-path=\"url(#area)\">\n";
  for (const PlotSeries& ser : series) {
    if (ser.line) {
      std::string pts;
      auto flush = [&] {
        if (!pts.empty())
          s << "<polyline fill=\"none\" stroke=\"" << ser.color << "\" stroke-width=\"1.5\""
            << (ser.dashed ? " stroke-dasharray=\"5,4\"" : "") << " points=\"" << pts << "\"/>\n";
        pts.clear();
      };
      for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i) {
        if (!std::isfinite(ser.y[i]) || !std::isfinite(ser.x[i])) {
          flush();
          continue;
        }
        pts += Num(px(ser.x[i])) + "," + Num(py(ser.y[i])) + " ";
      }
      flush();
    }
    if (ser.markers)
      for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i)
        if (std::isfinite(ser.y[i]) && std::isfinite(ser.x[i]))
          s << "<circle cx=\"" << px(ser.x[i]) << "\" cy=\"" << py(ser.y[i]) << "\" r=\"3\" fill=\"" << ser.color
            << "\"/>\n";
  }
  s << "</g>\n";
  double ly = T + 14;
  for (const PlotSeries& ser : series) {
    if (ser.name.empty()) continue;
    s << "<line x1=\"" << L + 10 << "\" y1=\"" << ly - 4 << "\" x2=\"" << L + 30 << "\" y2=\"" << ly - 4
      << "\" stroke=\"" << ser.color << "\" stroke-width=\"2\"" << (ser.dashed ? " stroke-dasharray=\"5,4\"" : "")
      << "/>\n";
    s << "<text x=\"" << L + 36 << "\" y=\"" << ly << "\">" << Esc(ser.name) << "</text>\n";
    ly += 16;
  }
  s << "</svg>\n";
  return s.str();
}

}  // namespace lt
