#include "pipeline/eval_report.h"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/base64.h"
#include "core/error.h"
#include "core/image_io.h"
#include "pipeline/option_checks.h"
#include "pipeline/run_folder_reader.h"
#include "pipeline/svg_plot.h"

namespace lt {

namespace fs = std::filesystem;

void EvalReportOptions::Check() const {
  Require(max_frames >= 0, "max_frames", "must be >= 0");
  Require(max_scatter_points >= 1, "max_scatter_points", "must be >= 1");
}

namespace {

const char* PointMethodText(const std::string& method) {
  if (method == "scene") return "the scene's surfaces (scene.json rebuilt at each frame's time)";
  if (method == "gt_buffers") return "the surfaces the pixels see (ground-truth depth and normal buffers)";
  if (method == "mixed") return "the scene's surfaces where the scene was available, else the ground-truth buffers";
  return "no surface (no ground-truth buffers)";
}

const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};
const char* PlaneColor(int plane) { return plane < 0 ? "#7f7f7f" : kPalette[plane % 8]; }

std::string Fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "–";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}
std::string Opt(const std::optional<double>& v, int decimals, double scale = 1) {
  return v ? Fixed(*v * scale, decimals) : "–";
}
std::string Stat(const ErrorStats& s, double ErrorStats::*field, int decimals) {
  return s.n > 0 ? Fixed(s.*field, decimals) : "–";
}

// The frame's camera image as PNG bytes: scaled by its full scale (raw 10-bit
// DN in a 16-bit PNG: 1023) and encoded with gamma 2.2 for display, so that a
// dim laser frame's stripe and background stay visible; first channel only
// unless RGB.
std::optional<std::string> FramePng(const RunFrame& frame) {
  try {
    AnyImage any = ReadImage(frame.image, AlphaChannel::kDrop);
    double full = 1;
    if (std::holds_alternative<Image<uint8_t>>(any)) full = frame.FullScale(255);
    if (std::holds_alternative<Image<uint16_t>>(any)) full = frame.FullScale(65535);
    const Image<float> img = std::visit(
        [](auto&& im) {
          Image<float> f(im.width, im.height, im.channels);
          for (size_t i = 0; i < im.pixels.size(); ++i) f.pixels[i] = float(im.pixels[i]);
          return f;
        },
        any);
    if (std::holds_alternative<Image<float>>(any)) {  // float images: by their brightest value
      full = 0;
      for (float v : img.pixels) full = std::max(full, double(v));
      if (!(full > 0)) full = 1;
    }
    const int channels = img.channels >= 3 ? 3 : 1;
    Image<uint8_t> out(img.width, img.height, channels);
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        for (int c = 0; c < channels; ++c) {
          const double v = img.At(x, y, c) / full;
          out.At(x, y, c) = uint8_t(std::lround(std::pow(std::clamp(std::isfinite(v) ? v : 0.0, 0.0, 1.0), 1 / 2.2) * 255));
        }
      }
    }
    static std::atomic<int> counter{0};
    const fs::path tmp = fs::temp_directory_path() /
                         ("lt_report_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) + ".png");
    WriteImage(tmp, out);
    std::ifstream in(tmp, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    fs::remove(tmp);
    return ss.str();
  } catch (const InputError&) {
    return std::nullopt;
  }
}

// Frames to show: the worst by centre rms and missed centres, then typical ones (around the median).
std::vector<int> PickFrames(const RunMetrics& m, int max_frames) {
  std::vector<std::pair<double, int>> score;
  for (const FrameMetrics& f : m.frames) {
    const EvalSummary& s = f.total;
    const double miss = s.detection_rate ? 1 - *s.detection_rate : 1;
    score.push_back({(s.center_px.n > 0 ? s.center_px.rms : 0) + miss + 0.01 * double(s.counts.false_positives), f.index});
  }
  std::sort(score.begin(), score.end(), [](auto& a, auto& b) { return a.first > b.first || (a.first == b.first && a.second < b.second); });
  std::vector<int> picked;
  const int n = int(score.size());
  const int worst = std::min(n, (max_frames + 1) / 2);
  for (int i = 0; i < worst; ++i) picked.push_back(score[size_t(i)].second);
  for (int d = 0; int(picked.size()) < std::min(n, max_frames) && d < n; ++d) {
    const int i = std::clamp(n / 2 + (d % 2 ? -(d + 1) / 2 : d / 2), 0, n - 1);
    if (std::find(picked.begin(), picked.end(), score[size_t(i)].second) == picked.end()) picked.push_back(score[size_t(i)].second);
  }
  return picked;
}

std::string FrameFigure(const RunFrame& frame, const RunMetrics& m, int width, int height) {
  // The region around the frame's centres (whole image when small).
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  auto grow = [&](double u, double v) {
    x0 = std::min(x0, u), y0 = std::min(y0, v), x1 = std::max(x1, u), y1 = std::max(y1, v);
  };
  std::string marks;
  int shown = 0;
  for (const CenterSample& c : m.centers) {
    if (c.frame != frame.index) continue;
    ++shown;
    if (c.has_truth) {
      grow(c.u_true, c.v_true);
      marks += "<circle cx=\"" + Fixed(c.u_true, 3) + "\" cy=\"" + Fixed(c.v_true, 3) + "\" r=\"" +
               (c.matched ? "0.3\" fill=\"#0c0\"" : "0.9\" fill=\"none\" stroke=\"#fc0\" stroke-width=\"0.2\"") + "/>";
    }
    if (c.matched || !c.has_truth) {
      grow(c.u_measured, c.v_measured);
      const double s = c.has_truth ? 0.35 : 0.7;
      marks += "<path d=\"M" + Fixed(c.u_measured - s, 3) + " " + Fixed(c.v_measured - s, 3) + "l" + Fixed(2 * s, 3) +
               " " + Fixed(2 * s, 3) + "m0 " + Fixed(-2 * s, 3) + "l" + Fixed(-2 * s, 3) + " " + Fixed(2 * s, 3) +
               "\" stroke=\"" + (c.has_truth ? "#f00" : "#f0f") + "\"/>";
    }
  }
  if (shown == 0 || width <= 0 || height <= 0) return "";
  if (width > 400 || height > 400) {
    x0 = std::max(std::floor(x0) - 24, -0.5);
    y0 = std::max(std::floor(y0) - 24, -0.5);
    x1 = std::min(std::ceil(x1) + 24, width - 0.5);
    y1 = std::min(std::ceil(y1) + 24, height - 0.5);
  } else {
    x0 = y0 = -0.5;
    x1 = width - 0.5;
    y1 = height - 0.5;
  }
  std::string image;
  if (auto png = FramePng(frame)) {
    const std::string data = Base64Encode(reinterpret_cast<const uint8_t*>(png->data()), png->size());
    image = "<image x=\"-0.5\" y=\"-0.5\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
            "\" style=\"image-rendering:pixelated\" href=\"data:image/png;base64," + data + "\"/>";
  } else {
    image = "<rect x=\"-0.5\" y=\"-0.5\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
            "\" fill=\"#222\"/>";
  }
  const double w = x1 - x0, h = y1 - y0;
  const double display_w = std::min(1200.0, std::max(w * 4, 300.0));
  return "<figure><svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" + Fixed(x0, 1) + " " + Fixed(y0, 1) + " " +
         Fixed(w, 1) + " " + Fixed(h, 1) + "\" style=\"width:" + Fixed(display_w, 0) +
         "px;max-width:100%;background:#000\" stroke-width=\"0.1\">" + image + "<g>" + marks +
         "</g></svg><figcaption>frame " + std::to_string(frame.index) + ": " + SvgEscape(frame.image.filename().string()) +
         ", pixels " + Fixed(x0 + 0.5, 0) + ".." + Fixed(x1 - 0.5, 0) + " × " + Fixed(y0 + 0.5, 0) + ".." +
         Fixed(y1 - 0.5, 0) + "</figcaption></figure>\n";
}

std::string SummaryRow(const std::string& head, const EvalSummary& s) {
  const EvalCounts& c = s.counts;
  return "<tr><td>" + head + "</td><td>" + std::to_string(c.gt_centers) + "</td><td>" + std::to_string(c.matched) +
         "</td><td>" + Opt(s.detection_rate, 1, 100) + "%</td><td>" + std::to_string(c.false_positives) + "</td><td>" +
         Opt(s.plane_id_accuracy, 1, 100) + "%</td><td>" + Stat(s.center_px, &ErrorStats::rms, 3) + "</td><td>" +
         Stat(s.center_px, &ErrorStats::median, 3) + "</td><td>" + Stat(s.center_px, &ErrorStats::p95, 3) + "</td><td>" +
         Stat(s.center_px, &ErrorStats::max, 3) + "</td><td>" + Stat(s.point_mm, &ErrorStats::rms, 4) + "</td><td>" +
         Stat(s.point_mm, &ErrorStats::p95, 4) + "</td><td>" + Opt(s.completeness, 1, 100) + "%</td></tr>\n";
}

const char* kTableHead =
    "<tr><th></th><th>true centres</th><th>matched</th><th>detection</th><th>false pos.</th><th>plane id</th>"
    "<th>centre rms px</th><th>median</th><th>p95</th><th>max</th><th>point rms mm</th><th>p95</th>"
    "<th>completeness</th></tr>\n";

}  // namespace

std::string FormatEvalReport(const fs::path& run_dir, const RunMetrics& m, const EvalReportOptions& options) {
  options.Check();
  const EvalSummary& t = m.total;
  const bool rows = m.axis == SearchAxis::kRows;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>lasertwin eval: " << SvgEscape(run_dir.string())
    << "</title>\n<style>body{font-family:sans-serif;margin:1.5em;max-width:1300px}table{border-collapse:collapse;"
       "margin:.5em 0}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}th{background:#f3f3f3}"
       ".big td{font-size:1.2em}figure{display:inline-block;margin:.5em;vertical-align:top}"
       ".charts svg{margin:.3em}</style></head><body>\n";
  h << "<h1>Evaluation of " << SvgEscape(run_dir.string()) << "</h1>\n";
  h << "<p>" << m.frames.size() << " laser frame(s) against ground truth; scan lines: " << (rows ? "rows" : "columns")
    << "; pairs within " << Fixed(m.options.max_match_px, 2) << " px; a stripe point counts as reconstructed within "
    << Fixed(m.options.completeness_mm, 3) << " mm. Definitions: docs/evaluation.md.</p>\n";
  h << "<table class=\"big\"><tr><th>centre error rms</th><th>detection rate</th><th>false positives</th>"
       "<th>plane id accuracy</th><th>point error rms</th><th>completeness</th></tr><tr><td>"
    << Stat(t.center_px, &ErrorStats::rms, 3) << " px</td><td>" << Opt(t.detection_rate, 2, 100) << "%</td><td>"
    << t.counts.false_positives << " (" << Opt(t.false_positive_rate, 2, 100) << "%)</td><td>"
    << Opt(t.plane_id_accuracy, 2, 100) << "%</td><td>" << Stat(t.point_mm, &ErrorStats::rms, 4) << " mm</td><td>"
    << Opt(t.completeness, 2, 100) << "%</td></tr></table>\n";
  h << "<p>Centre error median " << Stat(t.center_px, &ErrorStats::median, 3) << " px, p95 "
    << Stat(t.center_px, &ErrorStats::p95, 3) << " px, max " << Stat(t.center_px, &ErrorStats::max, 3)
    << " px, bias (mean of measured − true) " << (t.center_px.n ? Fixed(t.center_bias_px, 4) : "–")
    << " px. Point error median " << Stat(t.point_mm, &ErrorStats::median, 4) << " mm, p95 "
    << Stat(t.point_mm, &ErrorStats::p95, 4) << " mm, max " << Stat(t.point_mm, &ErrorStats::max, 4) << " mm over "
    << t.point_mm.n << " points (" << t.counts.points_off_surface << " over no surface); distance to "
    << PointMethodText(m.PointErrorMethod()) << ".";
  if (t.stitched_point_mm.n > 0) {
    h << " Stitched (the world points as scan placed them, with the poses it used): median "
      << Stat(t.stitched_point_mm, &ErrorStats::median, 4) << " mm, p95 " << Stat(t.stitched_point_mm, &ErrorStats::p95, 4)
      << " mm, max " << Stat(t.stitched_point_mm, &ErrorStats::max, 4) << " mm over " << t.stitched_point_mm.n
      << " points.";
  }
  if (t.pose_offset_mm.n > 0) {
    h << " Stitch pose offset (each world point against where the true pose puts the same measurement): median "
      << Stat(t.pose_offset_mm, &ErrorStats::median, 4) << " mm, p95 " << Stat(t.pose_offset_mm, &ErrorStats::p95, 4)
      << " mm, max " << Stat(t.pose_offset_mm, &ErrorStats::max, 4) << " mm.";
  }
  h << "</p>\n";

  h << "<h2>By plane</h2><table>" << kTableHead;
  for (const auto& [k, s] : m.planes) h << SummaryRow(k < 0 ? "unidentified" : "plane " + std::to_string(k), s);
  h << SummaryRow("all", t) << "</table>\n";

  // Charts.
  std::vector<double> err;
  std::map<int, SvgSeries> by_line, by_depth;
  size_t matched = size_t(t.counts.matched);
  const size_t step = std::max<size_t>(1, matched / size_t(options.max_scatter_points) + 1);
  size_t k = 0;
  for (const CenterSample& c : m.centers) {
    if (!c.matched) continue;
    err.push_back(c.error_px);
    if (k++ % step) continue;
    for (auto* series : {&by_line, &by_depth}) {
      SvgSeries& s = (*series)[c.plane_true];
      s.name = "plane " + std::to_string(c.plane_true);
      s.color = PlaneColor(c.plane_true);
      s.marker_radius = 1.5;
      s.y.push_back(c.error_px);
    }
    by_line[c.plane_true].x.push_back(c.line);
    by_depth[c.plane_true].x.push_back(c.depth_true_m * 1e3);
  }
  std::vector<double> perr;
  SvgSeries pdepth;
  pdepth.marker_radius = 1.5;
  const size_t pstep = std::max<size_t>(1, m.points.size() / size_t(options.max_scatter_points) + 1);
  k = 0;
  for (const PointSample& p : m.points) {
    if (!p.on_surface) continue;
    perr.push_back(p.error_mm);
    if (k++ % pstep) continue;
    pdepth.x.push_back(p.depth_m * 1e3);
    pdepth.y.push_back(p.error_mm);
  }
  auto values = [](const std::map<int, SvgSeries>& s) {
    std::vector<SvgSeries> v;
    for (auto& [plane, series] : s) v.push_back(series);
    return v;
  };
  h << "<h2>Errors</h2><div class=\"charts\">\n";
  h << SvgHistogram({"Stripe centre error, measured − true", "px along the scan line", "centres"}, err, 50);
  h << SvgHistogram({"Point error, distance to the true surface", "mm", "points"}, perr, 50, "#ff7f0e");
  h << SvgPlot({"Centre error against scan line", rows ? "image row" : "image column", "error, px"}, values(by_line));
  h << SvgPlot({"Centre error against depth", "true depth z, mm", "error, px"}, values(by_depth));
  {
    SvgPlotOptions o{"Point error against depth", "point depth z, mm", "error, mm"};
    o.y_from_zero = true;
    pdepth.color = "#ff7f0e";
    h << SvgPlot(o, {pdepth});
  }
  h << "</div>\n";

  // Frames.
  h << "<h2>Frames</h2><p>Green dots: true centres; red crosses: measured centres paired with them; yellow rings: true "
       "centres not found; magenta crosses: false positives. The pictures scale: zoom in.</p>\n";
  std::vector<RunFrame> manifest;
  try {
    manifest = ReadRunManifest(run_dir);
  } catch (const InputError&) {
  }
  std::optional<RunRig> rig;
  try {
    rig = ReadRunRig(run_dir);
  } catch (const InputError&) {
  }
  for (int index : PickFrames(m, options.max_frames)) {
    for (const RunFrame& f : manifest) {
      if (f.index == index && rig) h << FrameFigure(f, m, rig->camera.width(), rig->camera.height());
    }
  }
  h << "<h2>By frame</h2><table>" << kTableHead;
  int rows_written = 0;
  for (const FrameMetrics& f : m.frames) {
    if (rows_written++ == 1000) {
      h << "<tr><td colspan=\"13\">… " << m.frames.size() - 1000 << " more in metrics.json</td></tr>\n";
      break;
    }
    h << SummaryRow("frame " + std::to_string(f.index), f.total);
  }
  h << "</table>\n</body></html>\n";
  return h.str();
}

fs::path WriteEvalReport(const fs::path& run_dir, const RunMetrics& metrics, const EvalReportOptions& options) {
  const fs::path path = run_dir / "report.html";
  WriteFileAtomically(path, FormatEvalReport(run_dir, metrics, options));
  return path;
}

}  // namespace lt
