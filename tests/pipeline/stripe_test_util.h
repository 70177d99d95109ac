// Helpers for extraction tests: synthetic frames and error statistics against
// the exact centre lines.
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "pipeline/stripe_extractor.h"
#include "pipeline/synthetic_stripes.h"

namespace lt::test {

struct ErrorStats {
  double rms = 0;
  double max_abs = 0;
  double mean = 0;
  int points = 0;        // points matched to a stripe
  int unmatched = 0;     // points farther than `match` from every stripe
  int rows_with_truth = 0;  // rows (inside `rows`) where some stripe is visible
};

// Errors along the search line: u - CentreU(v) for row search (axis rows).
// Each point is matched to the stripe whose centre is nearest in its row.
inline ErrorStats RowErrors(const std::vector<StripePoint>& points, const SyntheticFrame& frame,
                            double match = 3.0) {
  ErrorStats e;
  double sum2 = 0, sum = 0;
  for (const auto& p : points) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& s : frame.stripes) {
      if (!s.VisibleInRow(int(p.v))) continue;
      double d = p.u - s.CentreU(p.v);
      if (std::abs(d) < std::abs(best)) best = d;
    }
    if (!(std::abs(best) <= match)) {
      ++e.unmatched;
      continue;
    }
    ++e.points;
    sum += best;
    sum2 += best * best;
    e.max_abs = std::max(e.max_abs, std::abs(best));
  }
  if (e.points > 0) {
    e.rms = std::sqrt(sum2 / e.points);
    e.mean = sum / e.points;
  }
  return e;
}

template <typename T>
std::vector<StripePoint> ExtractFrom(const SyntheticFrame& frame, const ExtractionOptions& options) {
  Image<T> img = QuantizeImage<T>(RenderSyntheticFrame(frame));
  StripeExtractor extractor(options);
  return extractor.Extract(img.View());
}

inline SyntheticStripe LineStripe(double u0, double v0, double angle_deg, double sigma, double amplitude) {
  SyntheticStripe s;
  s.shape = SyntheticStripe::Shape::kLine;
  s.u0 = u0;
  s.v0 = v0;
  s.angle_rad = angle_deg * M_PI / 180.0;
  s.sigma = sigma;
  s.amplitude = amplitude;
  return s;
}

}  // namespace lt::test
