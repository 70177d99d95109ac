// Synthetic stripe frames for the extraction experiments (exp_stripe_shapes,
// exp_stripe_encodings): a profile P(d) of the distance d across a straight
// centre line, integrated over each pixel by 8x8 sub-samples, then noise; the
// truth is the line. Score matches extracted points to the stripes.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "pipeline/stripe_extractor.h"

namespace exp_stripes {

using Profile = std::function<double(double)>;

struct Stripe {
  double u0, v0, angle_deg;  // u = u0 + (v - v0) tan(angle)
  Profile profile;
  double CentreU(double v) const { return u0 + (v - v0) * std::tan(angle_deg * M_PI / 180); }
};

struct Frame {
  int width = 160, height = 96;
  std::vector<Stripe> stripes;
  double level = 0, noise = 0, speckle = 0;
  double clip = 0;  // > 0: round and clip to [0, clip] (an integer camera)
  unsigned seed = 1;
};

inline lt::Image<float> Render(const Frame& f) {
  constexpr int kSub = 8;
  lt::Image<float> img(f.width, f.height, 1, 0.0f);
  std::mt19937 rng(f.seed);
  std::normal_distribution<double> normal(0, 1);
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      double sum = 0;
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b) {
          const double px = x - 0.5 + (a + 0.5) / kSub, py = y - 0.5 + (b + 0.5) / kSub;
          for (const Stripe& s : f.stripes) {
            sum += s.profile((px - s.CentreU(py)) * std::cos(s.angle_deg * M_PI / 180));
          }
        }
      double v = sum / (kSub * kSub);
      if (f.speckle > 0) v *= std::max(0.0, 1 + f.speckle * normal(rng));
      v += f.level + f.noise * normal(rng);
      if (f.clip > 0) v = std::clamp(std::round(v), 0.0, f.clip);
      img.At(x, y) = float(v);
    }
  return img;
}

inline Profile Gauss(double a, double s) {
  return [=](double d) { return a * std::exp(-d * d / (2 * s * s)); };
}
inline Profile FlatTop(double a, double w, double soft) {
  return [=](double d) { return a * 0.5 * std::erfc((std::abs(d) - w / 2) / (soft * std::sqrt(2.0))); };
}
// Gaussian core and, on the right, an exponential tail at `k` of the peak.
inline Profile Tail(double a, double s, double tail, double k) {
  return [=](double d) {
    const double g = a * std::exp(-d * d / (2 * s * s));
    return d > 0 ? std::max(g, k * a * std::exp(-d / tail)) : g;
  };
}

struct Cell {
  int found = 0, lines = 0, unmatched = 0;
  double rms = 0, max_abs = 0;
  double width = 0;  // mean reported width of the matched points
};

// Matches `points` to the frame's stripes (the nearest along the search line,
// within `match` px).
inline Cell Score(const Frame& f, const std::vector<lt::StripePoint>& points, double match) {
  Cell c;
  double sum2 = 0, width = 0;
  for (const auto& p : points) {
    double best = HUGE_VAL;
    for (const Stripe& s : f.stripes) {
      const double d = p.u - s.CentreU(p.v);
      if (std::abs(d) < std::abs(best)) best = d;
    }
    if (!(std::abs(best) <= match)) {
      ++c.unmatched;
      continue;
    }
    ++c.found;
    sum2 += best * best;
    width += p.width;
    c.max_abs = std::max(c.max_abs, std::abs(best));
  }
  for (int y = 0; y < f.height; ++y)
    for (const Stripe& s : f.stripes) {
      const double u = s.CentreU(y);
      if (u > 0 && u < f.width - 1) ++c.lines;
    }
  if (c.found > 0) c.rms = std::sqrt(sum2 / c.found), c.width = width / c.found;
  return c;
}

template <typename T>
Cell Measure(const Frame& f, const lt::ImageView<T>& img, const lt::ExtractionOptions& o, double match) {
  lt::StripeExtractor extractor(o);
  return Score(f, extractor.Extract(img), match);
}

}  // namespace exp_stripes
