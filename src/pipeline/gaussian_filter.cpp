#include "pipeline/gaussian_filter.h"

#include <array>
#include <cmath>

namespace lt {

namespace {
constexpr double kInvSqrt2Pi = 0.39894228040143267794;
double Gauss(double z, double s) { return kInvSqrt2Pi / s * std::exp(-0.5 * z * z / (s * s)); }
double GaussD1(double z, double s) { return -z / (s * s) * Gauss(z, s); }
double Phi(double z, double s) { return 0.5 * std::erfc(-z / (s * std::sqrt(2.0))); }
}  // namespace

double IntegratedGaussian0(double z, double s) { return Phi(z + 0.5, s) - Phi(z - 0.5, s); }
double IntegratedGaussian1(double z, double s) { return Gauss(z + 0.5, s) - Gauss(z - 0.5, s); }
double IntegratedGaussian2(double z, double s) { return GaussD1(z + 0.5, s) - GaussD1(z - 0.5, s); }

GaussianKernels::GaussianKernels(double s) : sigma(s), radius(int(std::ceil(4.0 * s)) + 1) {
  const int n = 2 * radius + 1;
  k0.resize(n);
  k1.resize(n);
  k2.resize(n);
  for (int i = -radius; i <= radius; ++i) {
    k0[i + radius] = float(IntegratedGaussian0(i, s));
    k1[i + radius] = float(IntegratedGaussian1(i, s));
    k2[i + radius] = float(IntegratedGaussian2(i, s));
  }
}

void ConvolveSegment3(const float* __restrict in, int len, const GaussianKernels& k, float* __restrict out0,
                      float* __restrict out1, float* __restrict out2) {
  const int R = k.radius;
  const float* k0 = k.k0.data();
  const float* k1 = k.k1.data();
  const float* k2 = k.k2.data();
  for (int x = 0; x < len; ++x) out0[x] = out1[x] = out2[x] = 0.0f;
  // Taps outside, samples inside: the inner loop runs along x and vectorises.
  for (int j = 0; j <= 2 * R; ++j) {
    const float c0 = k0[j], c1 = k1[j], c2 = k2[j];
    const float* p = in + 2 * R - j;  // in[x + R - i] with i = j - R
    for (int x = 0; x < len; ++x) {
      const float v = p[x];
      out0[x] += v * c0;
      out1[x] += v * c1;
      out2[x] += v * c2;
    }
  }
}

template <typename T>
SmoothedDerivatives SmoothedDerivativesAt(const ImageView<T>& image, double x, double y, double sigma, int radius) {
  // r(x, y) = sum_{i,j} I[j][i] K0(x - i) K0(y - j), and derivatives.
  constexpr int kMax = 2 * 64 + 2;
  const int R = std::min(radius, 64);
  const int ix0 = int(std::floor(x)) - R, iy0 = int(std::floor(y)) - R;
  const int n = 2 * R + 2;
  std::array<double, kMax> kx0, kx1, kx2, ky0, ky1, ky2;
  // Neighbouring taps share pixel edges: Phi, g and g' are evaluated once per
  // edge (n + 1 edges per axis) and differenced.
  auto fill = [&](double first_offset, double* k0, double* k1, double* k2) {
    const double inv_s2 = 1.0 / (sigma * sigma), inv = 1.0 / (sigma * std::sqrt(2.0));
    double prev_phi = 0, prev_g = 0, prev_dg = 0;
    for (int e = 0; e <= n; ++e) {
      const double z = first_offset + 0.5 - e;  // edge between taps e - 1 and e
      const double phi = 0.5 * std::erfc(-z * inv);
      const double g = kInvSqrt2Pi / sigma * std::exp(-0.5 * z * z * inv_s2);
      const double dg = -z * inv_s2 * g;
      if (e > 0) {
        k0[e - 1] = prev_phi - phi;
        k1[e - 1] = prev_g - g;
        k2[e - 1] = prev_dg - dg;
      }
      prev_phi = phi, prev_g = g, prev_dg = dg;
    }
  };
  fill(x - ix0, kx0.data(), kx1.data(), kx2.data());
  fill(y - iy0, ky0.data(), ky1.data(), ky2.data());
  std::array<int, kMax> cols;
  for (int i = 0; i < n; ++i) cols[i] = MirrorIndex(ix0 + i, image.width);
  SmoothedDerivatives d;
  for (int j = 0; j < n; ++j) {
    const T* row = image.Row(MirrorIndex(iy0 + j, image.height));
    double s0 = 0, s1 = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      const double v = double(row[cols[i]]);
      s0 += v * kx0[i];
      s1 += v * kx1[i];
      s2 += v * kx2[i];
    }
    d.r += ky0[j] * s0;
    d.rx += ky0[j] * s1;
    d.rxx += ky0[j] * s2;
    d.ry += ky1[j] * s0;
    d.rxy += ky1[j] * s1;
    d.ryy += ky2[j] * s0;
  }
  return d;
}

template SmoothedDerivatives SmoothedDerivativesAt<uint8_t>(const ImageView<uint8_t>&, double, double, double, int);
template SmoothedDerivatives SmoothedDerivativesAt<uint16_t>(const ImageView<uint16_t>&, double, double, double, int);
template SmoothedDerivatives SmoothedDerivativesAt<float>(const ImageView<float>&, double, double, double, int);

}  // namespace lt
