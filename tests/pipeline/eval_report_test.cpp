// The SVG chart helper and the evaluation report page: structure and
// self-containedness (no scripts, no external references), axis mapping.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <regex>

#include "core/error.h"
#include "pipeline/eval_report.h"
#include "pipeline/svg_plot.h"

namespace lt {
namespace {

using ::testing::HasSubstr;

TEST(SvgPlot, EscapesAndDrawsEveryValidPoint) {
  EXPECT_EQ(SvgEscape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
  SvgSeries s;
  s.x = {1, 10, 100, -1};  // -1 cannot be drawn on a log axis
  s.y = {3, 2, 1, 5};
  s.labels = {"a", "b<", "c", "d"};
  SvgPlotOptions o{"t & t", "x", "y"};
  o.log_x = true;
  const std::string svg = SvgPlot(o, {s});
  EXPECT_THAT(svg, HasSubstr("t &amp; t"));
  EXPECT_THAT(svg, HasSubstr("b&lt;"));
  const std::regex circle("<circle");
  EXPECT_EQ(std::distance(std::sregex_iterator(svg.begin(), svg.end(), circle), std::sregex_iterator()), 3);
  // Log axis: decade ticks 1, 10, 100, equally spaced.
  for (const char* tick : {">1<", ">10<", ">100<"}) EXPECT_THAT(svg, HasSubstr(tick));
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

TEST(SvgHistogram, CountsEveryFiniteValue) {
  const std::string svg = SvgHistogram({"h", "x", "n"}, {0, 0.5, 1, 1, std::nan("")}, 2);
  EXPECT_THAT(svg, HasSubstr("h (n = 4)"));
  // Two bins: [0, 0.5) holds 1, [0.5, 1] holds 3: the second bar is 3 times as tall.
  std::smatch m;
  std::vector<double> heights;
  std::string rest = svg;
  const std::regex bar("<rect x=\"[0-9.]+\" y=\"[0-9.]+\" width=\"[0-9.]+\" height=\"([0-9.]+)\"/>");
  while (std::regex_search(rest, m, bar)) {
    heights.push_back(std::stod(m[1]));
    rest = m.suffix();
  }
  ASSERT_EQ(heights.size(), 2u);
  EXPECT_NEAR(heights[1] / heights[0], 3.0, 0.02);
}

TEST(EvalReport, SelfContainedPageWithoutFrames) {
  RunMetrics m;
  m.run_dir = "/nonexistent/run";
  CenterSample c;
  c.has_truth = c.matched = true;
  c.u_true = 10;
  c.u_measured = 10.2;
  c.error_px = 0.2;
  c.plane_true = c.plane_measured = 0;
  m.centers = {c};
  m.frames.push_back({});
  // The run folder does not exist: frames are left out, the rest is drawn.
  const std::string html = FormatEvalReport(m.run_dir, m);
  EXPECT_THAT(html, HasSubstr("<!DOCTYPE html>"));
  EXPECT_THAT(html, HasSubstr("Centre error against depth"));
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("http://www.w3.org/2000/svg\" src"), std::string::npos);
  // The stitched points' error, when the run has world points.
  EXPECT_EQ(html.find("Stitched"), std::string::npos);
  m.total.stitched_point_mm = Summarize({0.25, 0.5});
  EXPECT_THAT(FormatEvalReport(m.run_dir, m), HasSubstr("median 0.3750 mm, p95 0.4875 mm, max 0.5000 mm over 2 points."));
  EvalReportOptions bad;
  bad.max_frames = -1;
  EXPECT_THROW(bad.Check(), InputError);
}

}  // namespace
}  // namespace lt
