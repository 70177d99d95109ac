// The frames of the extraction stress pass (exp_stripe_stress.cpp): centre
// curves (lines or circle arcs) with a profile across them, integrated over
// 8x8 sub-samples per pixel, a background, multiplicative speckle of a given
// grain, additive noise.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "core/image.h"
#include "stripe_frames.h"

namespace stress {

// The profiles across a stripe (Gauss, FlatTop, Tail) are exp_stripes'.
using exp_stripes::FlatTop;
using exp_stripes::Gauss;
using exp_stripes::Profile;
using exp_stripes::Tail;

struct Curve {
  bool arc = false;
  double u0 = 80.3, v0 = 48, angle_deg = 5;  // line: u = u0 + (v - v0) tan(angle)
  double cu = 0, cv = 0, radius = 0;         // arc: right branch of the circle
  std::vector<std::pair<double, double>> visible;  // v intervals where lit; empty: all
  Profile profile;

  double CentreU(double v) const {
    if (!arc) return u0 + (v - v0) * std::tan(angle_deg * M_PI / 180);
    const double dv = v - cv;
    return dv * dv < radius * radius ? cu + std::sqrt(radius * radius - dv * dv) : NAN;
  }
  // The arc's other crossing of row v (its left branch); NaN for lines.
  double OtherU(double v) const {
    if (!arc) return NAN;
    const double dv = v - cv;
    return dv * dv < radius * radius ? cu - std::sqrt(radius * radius - dv * dv) : NAN;
  }
  double Distance(double x, double y) const {
    if (arc) return std::hypot(x - cu, y - cv) - radius;
    return (x - CentreU(y)) * std::cos(angle_deg * M_PI / 180);
  }
  bool Lit(double v) const {
    if (visible.empty()) return true;
    for (auto [a, b] : visible)
      if (v >= a && v < b) return true;
    return false;
  }
  bool LitRow(int y) const { return Lit(y - 0.5) && Lit(y + 0.499); }
};

struct Frame {
  int width = 160, height = 96;
  std::vector<Curve> curves;
  std::function<double(double, double)> background;  // B(x, y), image units
  double noise = 0, speckle = 0, grain_x = 1, grain_y = 1;
  double clip = 0;  // > 0: round and clip to [0, clip]
  int bits = 0;     // 8 or 16 with clip; 0: float
  std::optional<lt::PixelRect> roi;
  unsigned seed = 1;
};

inline std::vector<double> SmoothNoise(int w, int h, double gx, double gy, std::mt19937* rng) {
  std::normal_distribution<double> normal(0, 1);
  std::vector<double> a(size_t(w) * h), b(a.size());
  for (double& v : a) v = normal(*rng);
  auto blur = [&](const std::vector<double>& in, std::vector<double>* out, double g, bool along_x) {
    const int r = int(std::ceil(3 * g));
    std::vector<double> k(2 * r + 1);
    for (int i = -r; i <= r; ++i) k[i + r] = std::exp(-0.5 * i * i / (g * g));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double s = 0;
        for (int i = -r; i <= r; ++i) {
          const int xx = along_x ? std::clamp(x + i, 0, w - 1) : x, yy = along_x ? y : std::clamp(y + i, 0, h - 1);
          s += k[i + r] * in[size_t(yy) * w + xx];
        }
        (*out)[size_t(y) * w + x] = s;
      }
  };
  blur(a, &b, gx, true);
  blur(b, &a, gy, false);
  double m = 0, m2 = 0;
  for (double v : a) m += v, m2 += v * v;
  m /= a.size();
  const double sd = std::sqrt(std::max(1e-12, m2 / a.size() - m * m));
  for (double& v : a) v = (v - m) / sd;
  return a;
}

inline lt::Image<float> Render(const Frame& f) {
  constexpr int kSub = 8;
  lt::Image<float> img(f.width, f.height, 1, 0.0f);
  std::mt19937 rng(f.seed);
  std::normal_distribution<double> normal(0, 1);
  std::vector<double> speckle;
  if (f.speckle > 0) speckle = SmoothNoise(f.width, f.height, f.grain_x, f.grain_y, &rng);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      double sum = 0;
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b) {
          const double px = x - 0.5 + (a + 0.5) / kSub, py = y - 0.5 + (b + 0.5) / kSub;
          for (const Curve& c : f.curves) {
            if (!c.Lit(py)) continue;
            const double d = c.Distance(px, py);
            if (std::isfinite(d)) sum += c.profile(d);
          }
        }
      double v = sum / (kSub * kSub);
      if (!speckle.empty()) v *= std::max(0.0, 1 + f.speckle * speckle[size_t(y) * f.width + x]);
      if (f.background) v += f.background(x, y);
      v += f.noise * normal(rng);
      if (f.clip > 0) v = std::clamp(std::round(v), 0.0, f.clip);
      img.At(x, y) = float(v);
    }
  return img;
}

}  // namespace stress
