// Synthetic laser stripe frames with exactly known centre lines, for testing
// and benchmarking extraction without a renderer. Each stripe has a Gaussian
// cross-section A exp(-d^2 / (2 s^2)) in the perpendicular distance d from its
// centre line, and each pixel receives the profile integrated over its square
// area (closed form for straight lines; 4x4 sub-squares, each with the locally
// straight line, for arcs), so the centre line is the exact truth.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/image.h"

namespace lt {

struct SyntheticStripe {
  enum class Shape { kLine, kArc };
  Shape shape = Shape::kLine;
  // kLine: through (u0, v0), at angle_rad from the image's v axis (positive:
  // u grows with v).
  double u0 = 0, v0 = 0, angle_rad = 0;
  // kArc: circle of `radius` around (cu, cv); rows are crossed on the branch
  // right of the centre (u > cu) unless left_branch.
  double cu = 0, cv = 0, radius = 0;
  bool left_branch = false;

  double sigma = 2;        // Gaussian sigma across the line (pixels)
  double amplitude = 200;  // peak intensity of the profile (image units)
  // Rows [first, second) where the stripe is visible; empty = every row.
  std::vector<std::pair<int, int>> visible_rows;

  // Column where the centre line crosses row v (NaN if it does not).
  double CentreU(double v) const;
  // Row where the centre line crosses column u (lines only; NaN otherwise).
  double CentreV(double u) const;
  // Signed perpendicular distance from (x, y) to the centre line and the unit
  // normal there.
  double Distance(double x, double y, double* nx, double* ny) const;
  bool VisibleInRow(int v) const;
};

struct SyntheticFrame {
  int width = 640;
  int height = 480;
  double background = 0;   // constant level added everywhere
  double noise_sigma = 0;  // additive Gaussian noise (image units)
  uint64_t seed = 1;
  std::vector<SyntheticStripe> stripes;
};

// Float image (one channel) in image units, noise included.
Image<float> RenderSyntheticFrame(const SyntheticFrame& frame);

// Rounds and clamps to the sample type's range (saturation for integers).
template <typename T>
Image<T> QuantizeImage(const Image<float>& image);

}  // namespace lt
