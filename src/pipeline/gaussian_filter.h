// Gaussian smoothing and derivative kernels integrated over each pixel's
// width (Steger 1998, "An unbiased detector of curvilinear structures", IEEE
// PAMI 20(2), section on discrete kernels): for an offset z from the pixel
// centre, k0(z) = Phi((z + 1/2) / sigma) - Phi((z - 1/2) / sigma),
// k1(z) = g(z + 1/2) - g(z - 1/2), k2(z) = g'(z + 1/2) - g'(z - 1/2), with g the
// normalised Gaussian. Convolving samples with them gives the exact derivatives
// of the sample sequence smoothed by a pixel-wide box and the Gaussian, which
// keeps small sigmas well behaved.
#pragma once

#include <vector>

#include "core/image.h"

namespace lt {

struct GaussianKernels {
  double sigma = 1;
  int radius = 0;                // taps at offsets -radius..radius
  std::vector<float> k0, k1, k2;  // k[i + radius] for offset i

  // radius = ceil(4 sigma) + 1 (the truncated mass is below 1e-4).
  explicit GaussianKernels(double sigma);
};

double IntegratedGaussian0(double z, double sigma);
double IntegratedGaussian1(double z, double sigma);
double IntegratedGaussian2(double z, double sigma);

// Horizontal pass: for x in [0, len) writes out_m[x] = sum_i in[x + R - i] k_m[i + R]
// (in holds len + 2R samples: the segment and R samples of margin each side).
void ConvolveSegment3(const float* in, int len, const GaussianKernels& k, float* out0, float* out1, float* out2);

// Derivatives of the smoothed image at a subpixel point, computed directly
// with kernels evaluated at the exact offsets (rows and columns outside the
// image are mirrored).
struct SmoothedDerivatives {
  double r = 0, rx = 0, ry = 0, rxx = 0, rxy = 0, ryy = 0;
};
template <typename T>
SmoothedDerivatives SmoothedDerivativesAt(const ImageView<T>& image, double x, double y, double sigma, int radius);

// Mirror index into [0, n) without repeating the edge sample (..., 2, 1, 0, 1, 2, ...).
inline int MirrorIndex(int i, int n) {
  if (n == 1) return 0;
  while (i < 0 || i >= n) i = i < 0 ? -i : 2 * n - 2 - i;
  return i;
}

}  // namespace lt
