// A stress pass of the extraction methods over stripe shapes a laser-line
// scanner produces and the earlier audit (exp_stripe_shapes) did not draw:
// exponential tails, flat tops and clipped stripes of 3-30 px, very wide and
// very thin stripes, speckle elongated along or across the stripe, circle arcs,
// stripes at 60-80 degrees, dashed and ending stripes, crossing and touching
// stripes, stepped backgrounds, glints, 1-px images, stripes on the border and
// ROIs cutting through a stripe (docs/extraction.md, "Stress pass").
//
// Each frame: centre curves (lines or circle arcs, optionally visible only on
// some rows) with a profile P(d) of the distance d across the curve, integrated
// over 8x8 sub-samples per pixel, a background B(x, y), multiplicative speckle
// (white noise smoothed by a Gaussian of given grain along x and y), additive
// noise, then float or rounded and clipped 8/16-bit. Per method it prints the
// search lines with a point within `match` px of a centre (of the lines whose
// centre lies inside the frame on a visible row), `+N` points matched to none,
// RMS / max |error| in px, and flags: NaN (a non-finite value), OUT (a point
// outside the image or ROI), AXIS (the transposed frame searched by columns
// gave other points).
//
//   build/bin/exp_stripe_stress
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "pipeline/stripe_extractor.h"
#include "stress_frames.h"

namespace {

using namespace stress;

struct Cell {
  int found = 0, lines = 0, unmatched = 0, bad = 0, outside = 0;
  double rms = 0, max_abs = 0;
  bool axis_differs = false;
};

template <typename T>
lt::Image<T> Convert(const lt::Image<float>& f) {
  lt::Image<T> out(f.width, f.height, 1, T(0));
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) out.At(x, y) = T(f.At(x, y));
  return out;
}

template <typename T>
lt::Image<T> Transposed(const lt::Image<T>& img) {
  lt::Image<T> out(img.height, img.width, 1, T(0));
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) out.At(y, x) = img.At(x, y);
  return out;
}

template <typename T>
Cell Measure(const Frame& f, const lt::Image<T>& img, lt::ExtractionOptions o, double match) {
  Cell c;
  std::vector<lt::StripePoint> points, cols;
  lt::StripeExtractor(o).Extract(img.View(), &points);
  // The same frame transposed, searched by columns.
  lt::ExtractionOptions oc = o;
  oc.axis = lt::SearchAxis::kCols;
  if (o.roi) oc.roi = lt::PixelRect{o.roi->y, o.roi->x, o.roi->height, o.roi->width};
  lt::StripeExtractor(oc).Extract(Transposed(img).View(), &cols);
  c.axis_differs = cols.size() != points.size();
  for (size_t i = 0; !c.axis_differs && i < points.size(); ++i) {
    c.axis_differs = cols[i].v != points[i].u || cols[i].u != points[i].v;
  }
  const lt::PixelRect r = o.roi ? *o.roi : lt::PixelRect{0, 0, f.width, f.height};
  double sum2 = 0;
  for (const auto& p : points) {
    if (!std::isfinite(p.u) || !std::isfinite(p.v) || !std::isfinite(p.width) || !std::isfinite(p.strength)) {
      ++c.bad;
      continue;
    }
    if (p.u < r.x - 0.5 || p.u > r.x + r.width - 0.5 || p.v < r.y || p.v > r.y + r.height - 1) ++c.outside;
    double best = HUGE_VAL;
    for (const Curve& s : f.curves)
      for (double u : {s.CentreU(p.v), s.OtherU(p.v)}) {
        const double d = p.u - u;
        if (std::abs(d) < std::abs(best)) best = d;
      }
    if (!(std::abs(best) <= match)) {
      ++c.unmatched;
      continue;
    }
    ++c.found;
    sum2 += best * best;
    c.max_abs = std::max(c.max_abs, std::abs(best));
  }
  for (int y = r.y; y < r.y + r.height; ++y)
    for (const Curve& s : f.curves)
      for (double u : {s.CentreU(y), s.OtherU(y)})
        if (s.LitRow(y) && u > r.x && u < r.x + r.width - 1) ++c.lines;
  if (c.found > 0) c.rms = std::sqrt(sum2 / c.found);
  return c;
}

bool g_local = false;  // --background local (max, com, multicom; steger ignores it)

void Row(const std::string& name, const Frame& f, double threshold, double background = 0, double match = 3) {
  const lt::Image<float> img = Render(f);
  std::printf("| %s |", name.c_str());
  for (auto m : {lt::ExtractionMethod::kMax, lt::ExtractionMethod::kCom, lt::ExtractionMethod::kMultiCom,
                 lt::ExtractionMethod::kSteger}) {
    lt::ExtractionOptions o;
    o.method = m;
    o.threshold = threshold;
    o.background = background;
    o.roi = f.roi;
    if (g_local) o.background_mode = lt::BackgroundMode::kLocal;
    Cell c;
    if (f.bits == 8) c = Measure(f, Convert<uint8_t>(img), o, match);
    else if (f.bits == 16) c = Measure(f, Convert<uint16_t>(img), o, match);
    else c = Measure(f, img, o, match);
    std::printf(" %d/%d", c.found, c.lines);
    if (c.unmatched) std::printf(" +%d", c.unmatched);
    if (c.found) std::printf(", %.3f / %.3f", c.rms, c.max_abs);
    if (c.bad) std::printf(" NaN %d", c.bad);
    if (c.outside) std::printf(" OUT %d", c.outside);
    if (c.axis_differs) std::printf(" AXIS");
    std::printf(" |");
  }
  std::printf("\n");
  std::fflush(stdout);
}

Frame One(Profile p, double angle = 5, double u0 = 80.3, int width = 160) {
  Frame f;
  f.width = width;
  Curve c;
  c.u0 = u0, c.angle_deg = angle, c.profile = std::move(p);
  f.curves.push_back(c);
  return f;
}

}  // namespace

void Frames() {
  char name[160];
  // Asymmetric: the truth is the profile's peak (d = 0).
  for (double tail : {1.0, 3.0, 10.0})
    for (double k : {0.3, 0.7}) {
      Frame f = One(Tail(1000, 1.5, tail, k));
      f.noise = 10;
      std::snprintf(name, sizeof name, "tail %.0f px at %.1f, sigma 1.5, 1%% noise (truth: peak)", tail, k);
      Row(name, f, 100, 0, 15);
    }
  // Flat tops (float, 1% noise) and clipped 8-bit stripes of 3..30 px.
  for (double w : {3.0, 8.0, 15.0, 30.0}) {
    Frame f = One(FlatTop(1000, w, 0.5), 5, 80.3, 200);
    f.noise = 10;
    std::snprintf(name, sizeof name, "flat top %.0f px, soft 0.5, 1%% noise", w);
    Row(name, f, 100, 0, 5);
  }
  for (double w : {3.0, 8.0, 15.0, 30.0}) {
    // A Gaussian clipped at 255 with a plateau about w px wide: peak A with
    // A exp(-(w/2)^2 / 2 s^2) = 255, s = 2.
    const double s = 2, amp = 255 * std::exp(w * w / (8 * s * s));
    Frame f = One(Gauss(std::min(amp, 1e9), s), 5, 80.3, 200);
    if (w > 12) f.curves[0].profile = FlatTop(2550, w, 2);
    f.noise = 2, f.clip = 255, f.bits = 8;
    f.background = [](double, double) { return 8.0; };
    std::snprintf(name, sizeof name, "8-bit saturated, plateau ~%.0f px, 2 DN", w);
    Row(name, f, 25.5, 8, 5);
  }
  // Very wide and very thin.
  for (double s : {8.0, 15.0}) {
    Frame f = One(Gauss(30000, s), 3, 160.3, 320);
    f.noise = 300, f.clip = 65535, f.bits = 16;
    std::snprintf(name, sizeof name, "16-bit, sigma %.0f, 1%% noise, 320 px", s);
    Row(name, f, 6553.5, 0, 5);
  }
  for (auto [s, a] : {std::pair{6.0, 45.0}, std::pair{10.0, 45.0}, std::pair{10.0, 60.0}}) {
    Frame f = One(Gauss(255 * 20, s), a, 160.3, 320);
    f.noise = 2, f.clip = 255, f.bits = 8;
    std::snprintf(name, sizeof name, "8-bit, sigma %.0f, 20x saturated, %.0f deg, 320 px", s, a);
    Row(name, f, 25.5, 0, 5);
  }
  for (double a : {0.0, 30.0}) {
    Frame f = One(Gauss(200, 0.3), a);
    f.noise = 2, f.clip = 255, f.bits = 8;
    std::snprintf(name, sizeof name, "8-bit, sigma 0.3, %.0f deg, 2 DN", a);
    Row(name, f, 25.5);
  }
  // Speckle elongated along the stripe (grain_y) or across it (grain_x).
  for (auto [gx, gy] : {std::pair{0.7, 6.0}, std::pair{6.0, 0.7}, std::pair{2.0, 2.0}}) {
    Frame f = One(Gauss(1000, 2.5));
    f.speckle = 0.3, f.grain_x = gx, f.grain_y = gy, f.noise = 5;
    std::snprintf(name, sizeof name, "speckle 30%%, grain %.1f across x %.1f along, sigma 2.5", gx, gy);
    Row(name, f, 100, 0, 6);
  }
  // Curved and steep.
  for (double r : {40.0, 80.0}) {
    Frame f;
    Curve c;
    c.arc = true, c.cu = 60, c.cv = 48, c.radius = r, c.profile = Gauss(1000, 1.5);
    f.curves.push_back(c);
    f.noise = 10;
    std::snprintf(name, sizeof name, "arc radius %.0f (up to 90 deg at its ends), sigma 1.5", r);
    Row(name, f, 100, 0, 4);
  }
  for (double a : {60.0, 75.0, 80.0}) {
    Frame f = One(Gauss(1000, 1.5), a, 80.3, 320);
    f.noise = 10;
    std::snprintf(name, sizeof name, "tilt %.0f deg, sigma 1.5, 320 px", a);
    Row(name, f, 100, 0, 4);
  }
  // Broken, ending, crossing, touching.
  {
    Frame f = One(Gauss(1000, 1.5));
    f.curves[0].visible = {{0, 20.3}, {24.6, 40.2}, {41.2, 60.5}, {75, 96}};
    f.noise = 10;
    Row("dashed: gaps of 4.3, 1, 14.5 rows", f, 100);
    Frame e = One(Gauss(1000, 1.5), 20);
    e.curves[0].visible = {{30.4, 70.6}};
    e.noise = 10;
    Row("ends inside the image (rows 30.4-70.6), 20 deg", e, 100);
  }
  for (double a : {10.0, 25.0}) {
    Frame f = One(Gauss(1000, 1.5), a);
    Curve c2 = f.curves[0];
    c2.angle_deg = -a;
    f.curves.push_back(c2);
    f.noise = 10;
    std::snprintf(name, sizeof name, "two crossing at +-%.0f deg", a);
    Row(name, f, 100, 0, 2);
  }
  for (double gap : {3.0, 4.0, 5.0}) {
    Frame f = One(Gauss(1000, 1.5), 5, 78);
    Curve c2 = f.curves[0];
    c2.u0 = 78 + gap;
    f.curves.push_back(c2);
    f.noise = 10;
    std::snprintf(name, sizeof name, "two touching, %.0f px apart (2 sigma = 3)", gap);
    Row(name, f, 100, 0, gap / 2);
  }
  // Backgrounds and glints.
  for (double step : {50.0, 300.0}) {
    for (double at : {70.0, 86.0}) {
      Frame f = One(Gauss(1000, 1.5));
      f.noise = 10;
      f.background = [=](double x, double) { return x >= at ? step : 0.0; };
      std::snprintf(name, sizeof name, "step of %.0f at column %.0f (stripe at ~80)", step, at);
      Row(name, f, 100, 0, 3);
    }
  }
  {
    Frame f = One(Gauss(1000, 1.5));
    f.noise = 10;
    f.background = [](double x, double) { return 2.5 * x; };
    Row("ramp 2.5/px (0-400)", f, 100, 0, 3);
  }
  for (double k : {1.5, 4.0})
    for (double dist : {5.0, 10.0}) {
      Frame f = One(Gauss(1000, 1.5), 0);
      Curve g;  // a glint: round blob of sigma 2, rows 40-56
      g.arc = true, g.cu = 80.3 + dist, g.cv = 48, g.radius = 0, g.profile = Gauss(1000 * k, 2);
      f.curves.push_back(g);
      f.noise = 10, f.clip = 255 * 8, f.bits = 16;
      std::snprintf(name, sizeof name, "glint %.1fx peak, sigma 2, %.0f px beside", k, dist);
      Row(name, f, 100, 0, 3);
    }
  // Borders, tiny images, ROIs.
  for (double u : {0.0, 0.6, 2.0, 159.0}) {
    Frame f = One(Gauss(1000, 1.5), 0, u);
    f.noise = 10;
    std::snprintf(name, sizeof name, "vertical stripe at u = %.1f (border)", u);
    Row(name, f, 100);
  }
  for (auto [w, h] : {std::pair{1, 96}, std::pair{160, 1}, std::pair{3, 96}, std::pair{160, 2}}) {
    Frame f = One(Gauss(1000, 1.5), 5, w / 2.0);
    f.width = w, f.height = h;
    std::snprintf(name, sizeof name, "%dx%d image", w, h);
    Row(name, f, 100);
  }
  for (int x0 : {78, 80, 81, 83}) {
    Frame f = One(Gauss(1000, 1.5), 0);
    f.noise = 10;
    f.roi = lt::PixelRect{x0, 10, 60, 70};
    std::snprintf(name, sizeof name, "ROI from column %d (stripe at 80.3)", x0);
    Row(name, f, 100);
  }
}

int main() {
  for (bool local : {false, true}) {
    g_local = local;
    std::printf("\n%s\n\n| frame | max | com | multicom | steger |\n| --- | --- | --- | --- | --- |\n",
                local ? "--background local (steger as above)" : "default options");
    Frames();
  }
  return 0;
}
